//! A line of GLSL as a forest of expressions: tokens, then a Pratt parser run from the line's
//! start and again after each expression (or token) it could not read, so that declarations,
//! `for (…)` heads and braces around expressions leave the expressions in them readable.

use std::collections::HashMap;
use std::ops::Range;

use super::{Forest, Kind, Node};

#[derive(Debug, Clone, PartialEq)]
enum Tok {
    Ident(String),
    Number(f64),
    Punct(&'static str),
}

/// Punctuation, longest first so that `<<=` is read before `<<` and `<`.
const PUNCT: &[&str] = &[
    "<<=", ">>=", "++", "--", "<=", ">=", "==", "!=", "&&", "||", "^^", "+=", "-=", "*=", "/=",
    "%=", "&=", "|=", "^=", "<<", ">>", "+", "-", "*", "/", "%", "<", ">", "=", "!", "~", "&", "|",
    "^", "?", ":", "(", ")", "[", "]", "{", "}", ",", ";", ".",
];

fn tokens(line: &str) -> Vec<(Tok, Range<usize>)> {
    let b = line.as_bytes();
    let mut out = Vec::new();
    let mut i = 0;
    while i < b.len() {
        let c = b[i];
        if c.is_ascii_whitespace() {
            i += 1;
        } else if line[i..].starts_with("//") {
            break;
        } else if line[i..].starts_with("/*") {
            match line[i + 2..].find("*/") {
                Some(end) => i += end + 4,
                None => break,
            }
        } else if c.is_ascii_alphabetic() || c == b'_' {
            let start = i;
            while i < b.len() && (b[i].is_ascii_alphanumeric() || b[i] == b'_') {
                i += 1;
            }
            out.push((Tok::Ident(line[start..i].to_owned()), start..i));
        } else if c.is_ascii_digit() || (c == b'.' && b.get(i + 1).is_some_and(u8::is_ascii_digit))
        {
            let start = i;
            let (value, end) = number(line, i);
            i = end.max(i + 1);
            match value {
                Some(v) => out.push((Tok::Number(v), start..i)),
                // Not a number GLSL reads: nothing to match it to.
                None => out.push((Tok::Punct("?"), start..i)),
            }
        } else if let Some(p) = PUNCT.iter().find(|p| line[i..].starts_with(**p)) {
            out.push((Tok::Punct(p), i..i + p.len()));
            i += p.len();
        } else {
            // Anything else (a preprocessor `#`, a quote, a non-ASCII character): skipped.
            i += line[i..].chars().next().map_or(1, char::len_utf8);
        }
    }
    out
}

/// A numeric literal at `start`: its value (where it has one) and where it ends.
fn number(line: &str, start: usize) -> (Option<f64>, usize) {
    let b = line.as_bytes();
    let mut i = start;
    if line[i..].starts_with("0x") || line[i..].starts_with("0X") {
        i += 2;
        let digits = i;
        while i < b.len() && b[i].is_ascii_hexdigit() {
            i += 1;
        }
        let value = u64::from_str_radix(&line[digits..i], 16)
            .ok()
            .map(|v| v as f64);
        while i < b.len() && matches!(b[i], b'u' | b'U') {
            i += 1;
        }
        return (value, i);
    }
    while i < b.len() && (b[i].is_ascii_digit() || b[i] == b'.') {
        i += 1;
    }
    if i < b.len() && matches!(b[i], b'e' | b'E') {
        let mut j = i + 1;
        if j < b.len() && matches!(b[j], b'+' | b'-') {
            j += 1;
        }
        if j < b.len() && b[j].is_ascii_digit() {
            while j < b.len() && b[j].is_ascii_digit() {
                j += 1;
            }
            i = j;
        }
    }
    let value = line[start..i].parse::<f64>().ok();
    // Suffixes: f, F, lf, LF, u, U, hf.
    while i < b.len() && matches!(b[i], b'f' | b'F' | b'l' | b'L' | b'u' | b'U' | b'h') {
        i += 1;
    }
    (value, i)
}

/// Lines longer than this are not read (their values keep the whole line).
const LONGEST: usize = 4096;

/// Tokens one line's parse may read, all its tries together.
const BUDGET: u32 = 20_000;

/// Parse `line` into every expression it holds (each with its sub-expressions).
pub(in crate::glslang) fn parse_line(line: &str) -> Forest {
    if line.len() > LONGEST {
        return Forest::default();
    }
    let mut p = Parser {
        toks: tokens(line),
        pos: 0,
        forest: Forest::default(),
        depth: 0,
        parens: HashMap::new(),
        seen: HashMap::new(),
        steps: 0,
    };
    while p.pos < p.toks.len() && p.steps < BUDGET {
        let start = p.pos;
        if p.expression(0).is_none() {
            // What was read of a failed expression is kept: its complete sub-expressions are
            // still the line's. Read on from the next token.
            p.pos = start + 1;
        } else if p.pos == start {
            p.pos += 1;
        }
    }
    p.forest
}

struct Parser {
    toks: Vec<(Tok, Range<usize>)>,
    pos: usize,
    forest: Forest,
    /// Nesting, bounded so that a line of thousands of `(` cannot exhaust the stack.
    depth: u32,
    /// The text of a parenthesized node with its parentheses.
    parens: HashMap<usize, Range<usize>>,
    /// Each node by its range and operands.
    seen: HashMap<(usize, usize, Vec<usize>), Vec<usize>>,
    /// Tokens read, all tries together: a line that makes every try read to its end stops here.
    steps: u32,
}

/// Binding power of a binary operator: (left, right); assignment and `?:` bind to the right.
fn infix(op: &str) -> Option<(u8, u8)> {
    Some(match op {
        "=" | "+=" | "-=" | "*=" | "/=" | "%=" | "&=" | "|=" | "^=" | "<<=" | ">>=" => (2, 1),
        "?" => (4, 3),
        "||" => (5, 6),
        "^^" => (7, 8),
        "&&" => (9, 10),
        "|" => (11, 12),
        "^" => (13, 14),
        "&" => (15, 16),
        "==" | "!=" => (17, 18),
        "<" | ">" | "<=" | ">=" => (19, 20),
        "<<" | ">>" => (21, 22),
        "+" | "-" => (23, 24),
        "*" | "/" | "%" => (25, 26),
        _ => return None,
    })
}

const PREFIX: u8 = 27;

impl Parser {
    fn peek(&self) -> Option<&Tok> {
        self.toks.get(self.pos).map(|(t, _)| t)
    }

    fn punct(&self, p: &str) -> bool {
        matches!(self.peek(), Some(Tok::Punct(q)) if *q == p)
    }

    /// A node; one read again (after a failed expression around it) is the one read before.
    fn push(&mut self, kind: Kind, range: Range<usize>, children: Vec<usize>) -> usize {
        let key = (range.start, range.end, children.clone());
        let nodes = &self.forest.nodes;
        let same = self.seen.get(&key).into_iter().flatten().copied();
        if let Some(i) = same.clone().find(|&i| nodes[i].kind == kind) {
            return i;
        }
        self.forest.nodes.push(Node {
            kind,
            range,
            children,
        });
        let i = self.forest.nodes.len() - 1;
        self.seen.entry(key).or_default().push(i);
        i
    }

    /// The text node `n` takes in its user's: its own, with the parentheses around it.
    fn range(&self, n: usize) -> Range<usize> {
        self.parens
            .get(&n)
            .cloned()
            .unwrap_or_else(|| self.forest.nodes[n].range.clone())
    }

    /// An expression whose operators bind at least as tight as `min`.
    fn expression(&mut self, min: u8) -> Option<usize> {
        if self.depth > 64 {
            return None;
        }
        self.depth += 1;
        let out = self.expression_inner(min);
        self.depth -= 1;
        out
    }

    fn expression_inner(&mut self, min: u8) -> Option<usize> {
        let mut left = self.prefix()?;
        while let Some(Tok::Punct(op)) = self.peek().cloned() {
            let Some((l, r)) = infix(op) else { break };
            if l < min {
                break;
            }
            self.pos += 1;
            if op == "?" {
                let then = self.expression(0)?;
                if !self.punct(":") {
                    return None;
                }
                self.pos += 1;
                let otherwise = self.expression(r)?;
                let range = self.range(left).start..self.range(otherwise).end;
                left = self.push(Kind::Ternary, range, vec![left, then, otherwise]);
                continue;
            }
            let right = self.expression(r)?;
            let range = self.range(left).start..self.range(right).end;
            let kind = if l == 2 {
                Kind::Assign(op)
            } else {
                Kind::Binary(op)
            };
            left = self.push(kind, range, vec![left, right]);
        }
        Some(left)
    }

    /// A primary expression with its prefix operators and postfixes.
    fn prefix(&mut self) -> Option<usize> {
        self.steps += 1;
        if self.steps > BUDGET {
            return None;
        }
        let (tok, range) = self.toks.get(self.pos)?.clone();
        self.pos += 1;
        let mut node = match tok {
            Tok::Punct(op @ ("-" | "+" | "!" | "~" | "++" | "--")) => {
                let operand = self.expression(PREFIX)?;
                let whole = range.start..self.range(operand).end;
                return Some(self.push(Kind::Unary(op), whole, vec![operand]));
            }
            Tok::Punct("(") => {
                let inner = self.expression(0)?;
                if !self.punct(")") {
                    return None;
                }
                let end = self.toks[self.pos].1.end;
                self.pos += 1;
                self.parens.insert(inner, range.start..end);
                inner
            }
            Tok::Number(v) => self.push(Kind::Number(v), range, Vec::new()),
            Tok::Ident(name) if self.punct("(") => {
                self.pos += 1;
                let mut args = Vec::new();
                if self.punct(")") {
                    self.pos += 1;
                } else {
                    loop {
                        args.push(self.expression(3)?);
                        match self.peek() {
                            Some(Tok::Punct(",")) => self.pos += 1,
                            Some(Tok::Punct(")")) => {
                                self.pos += 1;
                                break;
                            }
                            _ => return None,
                        }
                    }
                }
                let end = self.toks[self.pos - 1].1.end;
                self.push(Kind::Call(name), range.start..end, args)
            }
            Tok::Ident(name) => self.push(Kind::Ident(name), range, Vec::new()),
            Tok::Punct(_) => return None,
        };
        // Postfixes: `.member`, `[index]`, `++`, `--`.
        loop {
            match self.peek() {
                Some(Tok::Punct(".")) => {
                    let Some((Tok::Ident(name), r)) = self.toks.get(self.pos + 1).cloned() else {
                        return None;
                    };
                    self.pos += 2;
                    let whole = self.range(node).start..r.end;
                    node = self.push(Kind::Member(name), whole, vec![node]);
                }
                Some(Tok::Punct("[")) => {
                    self.pos += 1;
                    let index = self.expression(0)?;
                    if !self.punct("]") {
                        return None;
                    }
                    let end = self.toks[self.pos].1.end;
                    self.pos += 1;
                    let whole = self.range(node).start..end;
                    node = self.push(Kind::Index, whole, vec![node, index]);
                }
                Some(Tok::Punct("++" | "--")) => {
                    let end = self.toks[self.pos].1.end;
                    self.pos += 1;
                    let whole = self.range(node).start..end;
                    node = self.push(Kind::Postfix, whole, vec![node]);
                }
                _ => break,
            }
        }
        Some(node)
    }
}
