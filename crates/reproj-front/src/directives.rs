//! What a shader's preprocessor lines say about its defs, read without naga_oil: which defs the
//! text reads (for the warning on a def nobody reads, [`crate::InputWarning::UnreadDef`]) and
//! which `@fragment` entry points the defs given leave out (for the message when the entry point
//! is missing, [`HiddenEntry`]). The grammar is naga_oil's: `#ifdef X`, `#ifndef X`,
//! `#if X op VALUE`, each also after `#else`, then `#else` and `#endif`; `#X` and `#{X}` in other
//! lines substitute a def's value.

use std::collections::{BTreeMap, BTreeSet};
use std::fmt;

use crate::input::DefValue;

/// One condition of an `#if…` line.
#[derive(Debug, Clone, PartialEq)]
enum Cond {
    Def(String),
    NotDef(String),
    Cmp {
        name: String,
        op: String,
        value: String,
    },
}

/// A conditional directive: `Some(cond)` for `#if…` and `#else if…`, `None` for a bare `#else`;
/// and whether it follows `#else`.
#[derive(Debug, Clone, PartialEq)]
enum Directive {
    Branch { is_else: bool, cond: Option<Cond> },
    EndIf,
}

/// The text of `line` before a `//` comment, trimmed.
fn code(line: &str) -> &str {
    line.split("//").next().unwrap_or("").trim()
}

/// The identifier at the start of `s` (letters, digits, `_`).
fn ident(s: &str) -> &str {
    let end = s
        .find(|c: char| !(c.is_alphanumeric() || c == '_'))
        .unwrap_or(s.len());
    &s[..end]
}

/// The conditional directive on a trimmed line, if it is one.
fn directive(line: &str) -> Option<Directive> {
    let rest = line.strip_prefix('#')?.trim_start();
    let (is_else, rest) = match rest.strip_prefix("else") {
        Some(r) if ident(rest) == "else" => (true, r.trim_start()),
        _ => (false, rest),
    };
    let word = ident(rest);
    let after = rest[word.len()..].trim_start();
    let name = ident(after).to_owned();
    let cond = match word {
        "ifdef" if !name.is_empty() => Some(Cond::Def(name)),
        "ifndef" if !name.is_empty() => Some(Cond::NotDef(name)),
        "if" if !name.is_empty() => {
            let tail = after[name.len()..].trim_start();
            let op_len = tail
                .find(|c: char| !"=!<>".contains(c))
                .unwrap_or(tail.len());
            Some(Cond::Cmp {
                name,
                op: tail[..op_len].to_owned(),
                value: tail[op_len..].trim().to_owned(),
            })
        }
        "endif" if !is_else => return Some(Directive::EndIf),
        "" if is_else => None,
        _ => return None,
    };
    Some(Directive::Branch { is_else, cond })
}

/// Every def `source` reads: in a conditional directive, or substituted as `#NAME` / `#{NAME}`
/// in a line that is not a directive.
pub fn read_defs(source: &str) -> BTreeSet<String> {
    let mut read = BTreeSet::new();
    for line in source.lines().map(code) {
        if let Some(Directive::Branch { cond: Some(c), .. }) = directive(line) {
            let (Cond::Def(n) | Cond::NotDef(n) | Cond::Cmp { name: n, .. }) = c;
            read.insert(n);
        } else if !line.starts_with('#') {
            for (at, _) in line.match_indices('#') {
                let rest = line[at + 1..].trim_start();
                let name = ident(rest.strip_prefix('{').unwrap_or(rest));
                if !name.is_empty() {
                    read.insert(name.to_owned());
                }
            }
        }
    }
    read
}

/// The byte range of the first `#if NAME op VALUE` line (trimmed) of `source` that compares
/// `name`.
pub fn comparison_of(source: &str, name: &str) -> Option<std::ops::Range<usize>> {
    let mut at = 0;
    for raw in source.split_inclusive('\n') {
        let line = code(raw);
        if let Some(Directive::Branch {
            cond: Some(Cond::Cmp { name: n, .. }),
            ..
        }) = directive(line)
            && n == name
        {
            let start = at + (raw.len() - raw.trim_start().len());
            return Some(start..start + line.len());
        }
        at += raw.len();
    }
    None
}

impl Cond {
    /// Whether the condition holds under `defs` (a comparison with a def not given: no).
    fn holds(&self, defs: &BTreeMap<String, DefValue>) -> bool {
        match self {
            Cond::Def(n) => defs.contains_key(n),
            Cond::NotDef(n) => !defs.contains_key(n),
            Cond::Cmp { name, op, value } => {
                let Some(have) = defs.get(name) else {
                    return false;
                };
                let ord = match (have, value.parse::<DefValue>()) {
                    (DefValue::Bool(a), Ok(DefValue::Bool(b))) => a.cmp(&b),
                    (DefValue::Bool(_), _) => return false,
                    (a, Ok(b)) => int(*a).cmp(&int(b)),
                    (_, Err(_)) => return false,
                };
                match op.as_str() {
                    "==" => ord.is_eq(),
                    "!=" => ord.is_ne(),
                    ">" => ord.is_gt(),
                    ">=" => ord.is_ge(),
                    "<" => ord.is_lt(),
                    "<=" => ord.is_le(),
                    _ => false,
                }
            }
        }
    }

    /// What would make the condition hold, said to the user.
    fn fix(&self) -> String {
        match self {
            Cond::Def(n) => format!("pass --def {n}"),
            Cond::NotDef(n) => format!("leave {n} undefined"),
            Cond::Cmp { name, op, value } if op == "==" => format!("pass --def {name}={value}"),
            Cond::Cmp { name, op, value } => {
                format!("pass --def {name}=VALUE with VALUE {op} {value}")
            }
        }
    }
}

/// A def's value as an integer, for comparisons (a bool as 0 or 1).
fn int(v: DefValue) -> i64 {
    match v {
        DefValue::Bool(b) => i64::from(b),
        DefValue::Int(i) => i64::from(i),
        DefValue::UInt(u) => i64::from(u),
    }
}

/// A directive that keeps an entry point out, and what would let it in.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Guard {
    /// The directive's text (`#ifdef PREPASS_FRAGMENT`).
    pub directive: String,
    /// Its line (1-based) in the shader.
    pub line: usize,
    /// What would make it hold (`pass --def PREPASS_FRAGMENT`).
    pub fix: String,
}

/// An `@fragment` entry point of the shader's text that the defs given leave out.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct HiddenEntry {
    /// The function's name (empty when no `fn NAME` follows the attribute).
    pub name: String,
    /// The directives around it whose branch is not taken, outermost first.
    pub guards: Vec<Guard>,
}

impl fmt::Display for HiddenEntry {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        for (i, g) in self.guards.iter().enumerate() {
            let sep = if i == 0 { "" } else { ", and " };
            write!(f, "{sep}`{}` at line {} guards", g.directive, g.line)?;
            if i + 1 == self.guards.len() {
                write!(f, " `@fragment fn {}`", self.name)?;
            }
        }
        let fixes: Vec<&str> = self.guards.iter().map(|g| g.fix.as_str()).collect();
        write!(f, ": {}", fixes.join(" and "))
    }
}

/// The entry points of [`hidden_fragments`], as an error message's tail: empty when there are
/// none, else `" with the defs given; …"`.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct HiddenEntries(pub Vec<HiddenEntry>);

impl fmt::Display for HiddenEntries {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if self.0.is_empty() {
            return Ok(());
        }
        let each: Vec<String> = self.0.iter().map(ToString::to_string).collect();
        write!(f, " with the defs given; {}", each.join("; "))
    }
}

/// One open `#if…` of [`hidden_fragments`]'s walk.
struct Frame {
    /// Whether the enclosing text is kept.
    outer: bool,
    /// Whether a branch of this `#if…` chain was taken before the current one.
    taken: bool,
    /// Whether the current branch is taken.
    active: bool,
    /// The current branch's directive and line, and its fix when it is not taken.
    guard: Guard,
}

/// Every `@fragment` of `source` (the shader's own text) inside a branch that `defs` does not
/// take, with the directives that keep it out.
pub fn hidden_fragments(source: &str, defs: &BTreeMap<String, DefValue>) -> Vec<HiddenEntry> {
    let mut stack: Vec<Frame> = Vec::new();
    let mut hidden = Vec::new();
    let mut offset = 0;
    for (i, raw) in source.split_inclusive('\n').enumerate() {
        let at = offset;
        offset += raw.len();
        let line = code(raw);
        let kept = stack.last().is_none_or(|f| f.outer && f.active);
        match directive(line) {
            Some(Directive::EndIf) => {
                stack.pop();
            }
            Some(Directive::Branch { is_else, cond }) => {
                let fix = match &cond {
                    Some(c) => c.fix(),
                    None => "every condition before it must fail".to_owned(),
                };
                let holds = cond.as_ref().is_none_or(|c| c.holds(defs));
                let guard = Guard {
                    directive: line.to_owned(),
                    line: i + 1,
                    fix,
                };
                match stack.last_mut() {
                    Some(top) if is_else => {
                        top.taken |= top.active;
                        top.active = !top.taken && holds;
                        top.guard = guard;
                    }
                    _ => stack.push(Frame {
                        outer: kept,
                        taken: false,
                        active: holds,
                        guard,
                    }),
                }
            }
            None if !kept && line.contains("@fragment") => {
                let after = &source[at + raw.find("@fragment").unwrap_or(0)..];
                let name = after
                    .find("fn ")
                    .map(|f| ident(after[f + 3..].trim_start()).to_owned())
                    .unwrap_or_default();
                let guards = stack
                    .iter()
                    .filter(|f| !f.active)
                    .map(|f| f.guard.clone())
                    .collect();
                hidden.push(HiddenEntry { name, guards });
            }
            None => {}
        }
    }
    hidden
}

/// True when `source` uses naga_oil's preprocessor (a line starting with `#`: `#import`,
/// `#define_import_path`, `#ifdef`, `#if`...), which plain WGSL never does. Such a shader is
/// composed even without an import: its `#ifdef`s are naga_oil's to resolve.
pub fn needs_composing(source: &str) -> bool {
    source.lines().any(|l| l.trim_start().starts_with('#'))
}

#[cfg(test)]
mod tests {
    use super::*;

    const SHADER: &str = "\
#import x
#ifdef PREPASS_FRAGMENT
@fragment
fn prepass() -> @location(0) vec4<f32> { return vec4(#{ALPHA}); }
#else ifdef DEFERRED
#if N >= 3
@fragment fn deferred() {}
#endif
#else
@fragment fn main() {}
#endif
";

    #[test]
    fn the_defs_read_are_those_of_directives_and_substitutions() {
        let read: Vec<String> = read_defs(SHADER).into_iter().collect();
        assert_eq!(read, ["ALPHA", "DEFERRED", "N", "PREPASS_FRAGMENT"]);
        let range = comparison_of(SHADER, "N").unwrap();
        assert_eq!(&SHADER[range], "#if N >= 3");
        assert_eq!(comparison_of(SHADER, "DEFERRED"), None);
    }

    #[test]
    fn hidden_entry_points_name_their_guards() {
        let none = BTreeMap::new();
        let hidden = hidden_fragments(SHADER, &none);
        assert_eq!(hidden.len(), 2);
        assert_eq!(
            hidden[0].to_string(),
            "`#ifdef PREPASS_FRAGMENT` at line 2 guards `@fragment fn prepass`: pass --def PREPASS_FRAGMENT"
        );
        assert_eq!(hidden[1].name, "deferred");
        assert_eq!(hidden[1].guards.len(), 2, "{:?}", hidden[1]);
        assert!(
            hidden[1].to_string().contains("VALUE >= 3"),
            "{}",
            hidden[1]
        );

        let deferred: BTreeMap<_, _> = [
            ("DEFERRED".to_owned(), DefValue::Bool(true)),
            ("N".to_owned(), DefValue::UInt(4)),
        ]
        .into();
        let hidden = hidden_fragments(SHADER, &deferred);
        let names: Vec<&str> = hidden.iter().map(|h| h.name.as_str()).collect();
        assert_eq!(names, ["prepass", "main"]);
        assert!(
            hidden[1].guards[0]
                .fix
                .contains("every condition before it must fail")
        );
    }
}
