//! Columns for GLSL read through glslang: its `OpLine`s name a line and no column, so every value
//! of a line first spans the whole line. Each line's text is parsed as GLSL expressions (a small
//! Pratt parser: what a line of shading code holds, not the whole grammar) and each value is
//! narrowed to the sub-expression it was compiled from, matched by kind (operator, function,
//! constructor, member) and by its operands' matches; a variable or a literal is placed among its
//! user's operands, and a value stored where the line assigns it. A value that matches nothing
//! keeps its line (or its one placed operand's place, for a conversion or splat glslang
//! inserted), so a narrowed span is never a guess between two equal readings.

use std::collections::HashMap;
use std::ops::Range;

use naga::{Expression, Handle};

mod parse;
mod want;

pub(super) use parse::parse_line;
use want::{Ctx, Want};

/// Narrow the span of every expression of `module`'s functions that spans a whole line of
/// `source` to the sub-expression of that line it was compiled from; `info` is the module's
/// validation (only spans change, so it stays the module's).
pub(super) fn narrow_spans(
    module: &mut naga::Module,
    info: &naga::valid::ModuleInfo,
    source: &str,
) {
    let mut spans: Vec<HashMap<Handle<Expression>, naga::Span>> = Vec::new();
    for (h, fun) in module.functions.iter() {
        let ctx = Ctx {
            module,
            fun,
            info: &info[h],
        };
        spans.push(narrowed(&ctx, source));
    }
    for (i, ep) in module.entry_points.iter().enumerate() {
        let ctx = Ctx {
            module,
            fun: &ep.function,
            info: info.get_entry_point(i),
        };
        spans.push(narrowed(&ctx, source));
    }
    let mut spans = spans.into_iter();
    let functions = module.functions.iter_mut().map(|(_, f)| f);
    let entries = module.entry_points.iter_mut().map(|e| &mut e.function);
    for fun in functions.chain(entries) {
        let Some(spans) = spans.next().filter(|s| !s.is_empty()) else {
            continue;
        };
        let mut rebuilt = naga::Arena::new();
        for (h, value, span) in fun.expressions.drain() {
            rebuilt.append(value, spans.get(&h).copied().unwrap_or(span));
        }
        fun.expressions = rebuilt;
    }
}

/// The narrowed span of each expression of the function that matched a sub-expression of its
/// line.
fn narrowed(ctx: &Ctx, source: &str) -> HashMap<Handle<Expression>, naga::Span> {
    let exprs = &ctx.fun.expressions;
    // The expressions of each line, in evaluation order.
    let mut lines: Vec<(Range<usize>, Vec<Handle<Expression>>)> = Vec::new();
    let mut at: HashMap<Range<usize>, usize> = HashMap::new();
    for (h, _) in exprs.iter() {
        let Some(range) = exprs.get_span(h).to_range() else {
            continue;
        };
        if range.end > source.len() || range.is_empty() {
            continue;
        }
        let i = *at.entry(range.clone()).or_insert_with(|| {
            lines.push((range, Vec::new()));
            lines.len() - 1
        });
        lines[i].1.push(h);
    }
    let mut out = HashMap::new();
    let mut forests: HashMap<Range<usize>, Forest> = HashMap::new();
    for (range, handles) in lines {
        let Some(text) = source.get(range.clone()) else {
            continue;
        };
        let forest = parse_line(text);
        let line = Line {
            range: range.clone(),
            forest: &forest,
        };
        for (h, node) in match_line(ctx, &line, &handles, &out) {
            out.insert(h, line.span(node));
        }
        forests.insert(range, forest);
    }
    place_stored(ctx, &ctx.fun.body, &mut forests, source, &mut out);
    out
}

/// One line of the source: where it is and its parse.
struct Line<'a> {
    range: Range<usize>,
    forest: &'a Forest,
}

impl Line<'_> {
    fn span(&self, node: usize) -> naga::Span {
        let r = &self.forest.nodes[node].range;
        naga::Span::new(
            (self.range.start + r.start) as u32,
            (self.range.start + r.end) as u32,
        )
    }

    /// Whether `h` may be placed on this line: it is spanned by the line or by nothing.
    fn may_hold(&self, ctx: &Ctx, h: Handle<Expression>) -> bool {
        ctx.fun
            .expressions
            .get_span(h)
            .to_range()
            .is_none_or(|r| r == self.range)
    }
}

/// Match each of `handles` (one line's expressions, in evaluation order) to a node of the line's
/// parse; variables and literals (`handles` or operands spanned by nothing, not yet in
/// `placed`) are placed among their user's operands. The result maps an expression to its node.
fn match_line(
    ctx: &Ctx,
    line: &Line,
    handles: &[Handle<Expression>],
    placed: &HashMap<Handle<Expression>, naga::Span>,
) -> Vec<(Handle<Expression>, usize)> {
    let forest = line.forest;
    let targets = forest.targets();
    let mut matched: HashMap<Handle<Expression>, usize> = HashMap::new();
    let mut order = Vec::new();
    let mut used = vec![false; forest.nodes.len()];
    let mut leaves = Vec::new();
    for &h in handles {
        if ctx.is_pointer(h) {
            continue;
        }
        let operands: Vec<(Handle<Expression>, Option<Want>)> =
            crate::ir::operands(&ctx.fun.expressions[h])
                .into_iter()
                .filter(|&o| !ctx.is_pointer(o))
                .map(|o| {
                    let leaf = (!matched.contains_key(&o)
                        && !placed.contains_key(&o)
                        && line.may_hold(ctx, o))
                    .then(|| ctx.wanted(o))
                    .flatten()
                    .filter(Want::is_leaf);
                    (o, leaf)
                })
                .collect();
        let want = ctx.wanted(h);
        if want.as_ref().is_some_and(Want::is_leaf) {
            leaves.push(h);
            continue;
        }
        // How many of `h`'s operands node `n` has as its own operands.
        let held = |n: usize| {
            let children = &forest.nodes[n].children;
            operands
                .iter()
                .filter(|(o, leaf)| match (matched.get(o), leaf) {
                    (Some(m), _) => children.contains(m),
                    (None, Some(want)) => children
                        .iter()
                        .any(|&c| !targets[c] && want.accepts(forest, c)),
                    (None, None) => false,
                })
                .count()
        };
        let anchored = operands
            .iter()
            .any(|(o, leaf)| matched.contains_key(o) || leaf.is_some());
        let best = want.as_ref().and_then(|want| {
            (0..forest.nodes.len())
                .filter(|&n| !targets[n] && want.accepts(forest, n))
                .map(|n| (n, held(n)))
                // Where operands are placed, the node must hold one of them.
                .filter(|&(_, held)| !anchored || held > 0)
                // Most operands held, then a node not taken yet, then the first in the line.
                .max_by_key(|&(n, held)| (held, !used[n], std::cmp::Reverse(n)))
                .map(|(n, _)| n)
        });
        let node = match best {
            Some(n) => n,
            None => {
                // Nothing in the text (a conversion, a splat or a component glslang inserted):
                // its one operand's place, that operand placed first where the line holds
                // it once.
                let inserted = matches!(
                    ctx.fun.expressions[h],
                    Expression::As { .. }
                        | Expression::Splat { .. }
                        | Expression::AccessIndex { .. }
                        | Expression::Swizzle { .. }
                );
                if let (true, [(o, leaf)]) = (inserted, &operands[..]) {
                    let at = matched.get(o).copied().or_else(|| {
                        let n = leaf.as_ref().and_then(|w| only(forest, &targets, w))?;
                        matched.insert(*o, n);
                        order.push(*o);
                        Some(n)
                    });
                    if let Some(n) = at {
                        matched.insert(h, n);
                        order.push(h);
                    }
                }
                continue;
            }
        };
        used[node] = true;
        matched.insert(h, node);
        order.push(h);
        // Its variables and literals: among its operands in the text.
        for (o, leaf) in operands {
            let Some(want) = leaf.filter(|_| !matched.contains_key(&o)) else {
                continue;
            };
            let children = &forest.nodes[node].children;
            let fits = |c: &&usize| !targets[**c] && want.accepts(forest, **c);
            let child = children
                .iter()
                .filter(fits)
                .find(|c| !used[**c])
                .or_else(|| children.iter().find(fits));
            if let Some(&c) = child {
                used[c] = true;
                matched.insert(o, c);
                order.push(o);
            }
        }
    }
    // Variables and literals no matched user placed: where the line holds exactly one of them.
    for h in leaves {
        if matched.contains_key(&h) {
            continue;
        }
        if let Some(n) = ctx.wanted(h).and_then(|w| only(forest, &targets, &w)) {
            matched.insert(h, n);
            order.push(h);
        }
    }
    order.into_iter().map(|h| (h, matched[&h])).collect()
}

/// The one node of the line `want` accepts (not one a `=` assigns), if there is one only.
fn only(forest: &Forest, targets: &[bool], want: &Want) -> Option<usize> {
    let mut at = (0..forest.nodes.len()).filter(|&n| !targets[n] && want.accepts(forest, n));
    match (at.next(), at.next()) {
        (Some(n), None) => Some(n),
        _ => None,
    }
}

/// Values stored by `block`'s statements that no line placed (a literal assigned, glslang's
/// constants spanned by nothing): the right side of the line's `=` that assigns the variable.
fn place_stored(
    ctx: &Ctx,
    block: &naga::Block,
    forests: &mut HashMap<Range<usize>, Forest>,
    source: &str,
    out: &mut HashMap<Handle<Expression>, naga::Span>,
) {
    use naga::Statement as S;
    for (statement, span) in block.span_iter() {
        match statement {
            S::Store { pointer, value } => {
                let Some(range) = span.to_range() else {
                    continue;
                };
                let Some(text) = source.get(range.clone()) else {
                    continue;
                };
                let forest = &*forests
                    .entry(range.clone())
                    .or_insert_with(|| parse_line(text));
                let line = Line { range, forest };
                if out.contains_key(value) || !line.may_hold(ctx, *value) {
                    continue;
                }
                let Some(target) = ctx.loaded(*pointer) else {
                    continue;
                };
                let assigned = forest
                    .nodes
                    .iter()
                    .find_map(|n| match (&n.kind, &n.children[..]) {
                        (Kind::Assign("="), &[left, right]) if target.accepts(forest, left) => {
                            Some(right)
                        }
                        _ => None,
                    });
                let fits = ctx.wanted(*value);
                if let Some(right) =
                    assigned.filter(|&r| fits.as_ref().is_none_or(|w| w.accepts(forest, r)))
                {
                    out.insert(*value, line.span(right));
                }
            }
            S::Block(b) => place_stored(ctx, b, forests, source, out),
            S::If { accept, reject, .. } => {
                place_stored(ctx, accept, forests, source, out);
                place_stored(ctx, reject, forests, source, out);
            }
            S::Loop {
                body, continuing, ..
            } => {
                place_stored(ctx, body, forests, source, out);
                place_stored(ctx, continuing, forests, source, out);
            }
            S::Switch { cases, .. } => {
                for c in cases {
                    place_stored(ctx, &c.body, forests, source, out);
                }
            }
            _ => {}
        }
    }
}

/// A parsed line: every sub-expression with its byte range in the line and its operands.
#[derive(Debug, Default)]
pub(super) struct Forest {
    pub(super) nodes: Vec<Node>,
}

#[derive(Debug)]
pub(super) struct Node {
    pub(super) kind: Kind,
    pub(super) range: Range<usize>,
    pub(super) children: Vec<usize>,
}

#[derive(Debug, PartialEq)]
pub(super) enum Kind {
    Ident(String),
    Number(f64),
    Call(String),
    Binary(&'static str),
    Assign(&'static str),
    Unary(&'static str),
    Postfix,
    Member(String),
    Index,
    Ternary,
}

impl Forest {
    /// Whether each node is what a plain `=` assigns (written, never read there).
    fn targets(&self) -> Vec<bool> {
        let mut targets = vec![false; self.nodes.len()];
        for n in &self.nodes {
            if let (Kind::Assign("="), Some(&left)) = (&n.kind, n.children.first()) {
                targets[left] = true;
            }
        }
        targets
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn texts<'a>(line: &'a str, f: &Forest) -> Vec<&'a str> {
        f.nodes.iter().map(|n| &line[n.range.clone()]).collect()
    }

    #[test]
    fn a_declaration_parses_into_its_sub_expressions() {
        let line = "float a = sin(p.x) * 2.0 + cos(p.y * 3.0)";
        let f = parse_line(line);
        let t = texts(line, &f);
        for want in [
            "sin(p.x)",
            "p.x",
            "sin(p.x) * 2.0",
            "cos(p.y * 3.0)",
            "p.y * 3.0",
            "sin(p.x) * 2.0 + cos(p.y * 3.0)",
            "2.0",
        ] {
            assert!(t.contains(&want), "{want} not in {t:?}");
        }
    }

    #[test]
    fn control_lines_and_comments_parse_what_they_hold() {
        let line = "for (int i = 0; i < 4; i++) { c += texture(s, uv * 0.5).rgb; } // done * 2";
        let f = parse_line(line);
        let t = texts(line, &f);
        for want in [
            "i < 4",
            "c += texture(s, uv * 0.5).rgb",
            "texture(s, uv * 0.5)",
        ] {
            assert!(t.contains(&want), "{want} not in {t:?}");
        }
        assert!(!t.iter().any(|t| t.contains("done")), "{t:?}");
        // Precedence and the ternary.
        let line = "x = a + b * c > 0.5 ? -d : e.x";
        let f = parse_line(line);
        let t = texts(line, &f);
        for want in ["b * c", "a + b * c", "a + b * c > 0.5", "-d", "e.x"] {
            assert!(t.contains(&want), "{want} not in {t:?}");
        }
        assert!(t.contains(&"a + b * c > 0.5 ? -d : e.x"), "{t:?}");
    }

    #[test]
    fn unbalanced_or_foreign_text_parses_without_panic() {
        for line in [
            "",
            ")",
            "((",
            "a(",
            "a[",
            "vec3(1.0,",
            "1e",
            "0x",
            "? :",
            "a ? b",
            "--",
            "#define X 1",
            "}",
            "a.",
            "/* open",
            "\"str\"",
            "x = = y",
            "é + 1.0",
        ] {
            let _ = parse_line(line);
        }
        // Lines that make every try read to the end, or nest deep, end (a hang guard, not a
        // timing: the parse reads a bounded number of tokens).
        let chain = format!("{}(", "a+".repeat(2000));
        let nested = format!("{}a", "(".repeat(4000));
        for line in [chain, nested] {
            let start = std::time::Instant::now();
            let _ = parse_line(&line);
            assert!(start.elapsed().as_secs() < 5, "{}", line.len());
        }
    }
}
