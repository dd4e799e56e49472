//! How a node reads: its line, column and source text (from its span, or from the variable it
//! loads or its operands where the front end left none), and its type as WGSL spells it.

use std::collections::HashMap;

use naga::{Expression, Handle, TypeInner};

use crate::ir;
use crate::shader::Shader;

/// Line, column and source text of the expression `h`, from its span or, where the front end
/// left none, from the variable it loads or its operands.
pub(super) fn source_position(
    shader: &Shader,
    lines: &LineIndex,
    fun: &naga::Function,
    h: Handle<Expression>,
    e: &Expression,
) -> (u32, u32, String) {
    position_within(shader, lines, fun, h, e, 8)
}

/// [`source_position`], looking through at most `depth` levels of span-less operands.
fn position_within(
    shader: &Shader,
    lines: &LineIndex,
    fun: &naga::Function,
    h: Handle<Expression>,
    e: &Expression,
    depth: u32,
) -> (u32, u32, String) {
    let span = fun.expressions.get_span(h);
    let unplaced = (0, 0, String::new());
    match (span.is_defined(), e) {
        // Loads made by the front end (`x += ...`, a read after a loop or a `?:`) have no span:
        // the variable's declaration (WGSL), else where it was last written (GLSL through
        // SPIR-V, whose variables carry no line), else its name.
        (false, Expression::Load { pointer }) => match ir::root_local(&fun.expressions, *pointer) {
            Some(v) => {
                let name = || fun.local_variables[v].name.clone().unwrap_or_default();
                let declared = fun.local_variables.get_span(v);
                if declared.is_defined() {
                    let (l, c, _) = span_text(shader, lines, declared);
                    (l, c, name())
                } else if let Some(stored) = read_through_glslang(shader)
                    .then(|| last_store_span(fun, &fun.body, v))
                    .flatten()
                {
                    span_text(shader, lines, stored)
                } else {
                    (0, 0, name())
                }
            }
            None => unplaced,
        },
        (false, _) => match operand_span(shader, &fun.expressions, e) {
            Some(s) => span_text(shader, lines, s),
            // No operand spanned either (glslang's SPIR-V gives some values no line): the
            // nearest operand below that has a place.
            None if depth > 0 && read_through_glslang(shader) => ir::operands(e)
                .into_iter()
                .map(|o| position_within(shader, lines, fun, o, &fun.expressions[o], depth - 1))
                .find(|p| p.0 > 0)
                .unwrap_or(unplaced),
            None => unplaced,
        },
        _ => span_text(shader, lines, span),
    }
}

/// Whether `shader` is GLSL as glslang's SPIR-V gave it, whose values have lines only where an
/// `OpLine` names one (WGSL, and the WGSL naga writes of SPIR-V or GLSL, spans every value).
fn read_through_glslang(shader: &Shader) -> bool {
    shader.lang == crate::shader::Lang::Glsl && !shader.wgsl_form
}

/// The span of the last store to `v` in `block`, in program order, that has one: the stored
/// value's, else the statement's.
fn last_store_span(
    fun: &naga::Function,
    block: &naga::Block,
    v: Handle<naga::LocalVariable>,
) -> Option<naga::Span> {
    use naga::Statement as S;
    let mut found = None;
    for (statement, span) in block.span_iter() {
        let inner = match statement {
            S::Store { pointer, value }
                if ir::root_local(&fun.expressions, *pointer) == Some(v) =>
            {
                let value = fun.expressions.get_span(*value);
                Some(if value.is_defined() { value } else { *span }).filter(|s| s.is_defined())
            }
            S::Block(b) => last_store_span(fun, b, v),
            S::If { accept, reject, .. } => {
                last_store_span(fun, reject, v).or_else(|| last_store_span(fun, accept, v))
            }
            S::Loop {
                body, continuing, ..
            } => last_store_span(fun, continuing, v).or_else(|| last_store_span(fun, body, v)),
            S::Switch { cases, .. } => cases
                .iter()
                .rev()
                .find_map(|c| last_store_span(fun, &c.body, v)),
            _ => None,
        };
        if inner.is_some() {
            found = inner;
        }
    }
    found
}

/// Nodes still without a place (glslang's SPIR-V gives its constants, the fragment's inputs and
/// the zero its outputs start as no line; naga's WGSL never leaves one out): an input, or the
/// zero an output starts as, takes the variable's declaration; a value stored, the store's line;
/// anything else the line and column of its first user that has one, else of the nearest node
/// before it that has one, and as text its value (a constant's literal) or that node's text.
pub(super) fn place_leaves(
    shader: &Shader,
    lines: &LineIndex,
    nodes: &mut [super::Node],
    module: &naga::Module,
    fun: &naga::Function,
) {
    let placed: HashMap<Handle<Expression>, usize> = nodes
        .iter()
        .enumerate()
        .filter(|(_, n)| n.line > 0)
        .filter_map(|(i, n)| Some((n.handle?, i)))
        .collect();
    if !read_through_glslang(shader) {
        return;
    }
    let unplaced: std::collections::HashSet<Handle<Expression>> = nodes
        .iter()
        .filter(|n| n.line == 0)
        .filter_map(|n| n.handle)
        .collect();
    if unplaced.is_empty() {
        return;
    }
    let mut user: HashMap<Handle<Expression>, usize> = HashMap::new();
    for (h, e) in fun.expressions.iter() {
        let Some(&at) = placed.get(&h) else { continue };
        for o in ir::operands(e) {
            if unplaced.contains(&o) {
                user.entry(o).or_insert(at);
            }
        }
    }
    let stored = stored_values(fun);
    for i in 0..nodes.len() {
        let Some(h) = nodes[i].handle.filter(|h| unplaced.contains(h)) else {
            continue;
        };
        let e = &fun.expressions[h];
        let local = stored.get(&h).map(|&(v, _)| v);
        // An input, or the zero an output starts as: where the variable is declared.
        let name = match *e {
            Expression::FunctionArgument(a) => {
                fun.arguments.get(a as usize).and_then(|a| a.name.clone())
            }
            Expression::ZeroValue(_) => local.and_then(|v| fun.local_variables[v].name.clone()),
            _ => None,
        };
        // A value stored where the store has a line; an unnamed local starting at zero
        // (glslang's temporary for a `?:`): where it is written.
        let written = || {
            let (v, span) = *stored.get(&h)?;
            let span = Some(span)
                .filter(|s| s.is_defined())
                .or_else(|| last_store_span(fun, &fun.body, v))?;
            let (line, col, text) = span_text(shader, lines, span);
            Some((line, col, leaf_text(module, fun, e).unwrap_or(text)))
        };
        // A column of a matrix input (split into `NAME_colC` vectors): the matrix's declaration.
        let declared = name
            .as_deref()
            .and_then(|n| {
                declaration(shader, lines, n).or_else(|| {
                    let (matrix, column) = n.rsplit_once("_col")?;
                    column.parse::<u8>().ok()?;
                    declaration(shader, lines, matrix)
                })
            })
            .or_else(written);
        let place = match (declared, user.get(&h)) {
            (Some(place), _) => place,
            (None, Some(&u)) => {
                let u = &nodes[u];
                let text = leaf_text(module, fun, e).unwrap_or_else(|| u.text.clone());
                (u.line, u.col, text)
            }
            // Last, the nearest node before it (in evaluation order) that has a place.
            (None, None) => match nodes[..i].iter().rev().find(|n| n.line > 0) {
                Some(u) => {
                    let text = leaf_text(module, fun, e).unwrap_or_else(|| u.text.clone());
                    (u.line, u.col, text)
                }
                None => continue,
            },
        };
        let n = &mut nodes[i];
        (n.line, n.col, n.text) = place;
    }
}

/// Each value `fun` stores, with the local it is stored into and the store's span (the first
/// store of it), and the zero each local variable starts as: the zero a GLSL output starts as, the
/// constants glslang's `?:` stores into its temporary.
fn stored_values(fun: &naga::Function) -> HashMap<Handle<Expression>, (LocalHandle, naga::Span)> {
    fn block(
        fun: &naga::Function,
        b: &naga::Block,
        out: &mut HashMap<Handle<Expression>, (LocalHandle, naga::Span)>,
    ) {
        use naga::Statement as S;
        for (s, span) in b.span_iter() {
            match *s {
                S::Store { pointer, value } => {
                    if let Some(v) = ir::root_local(&fun.expressions, pointer) {
                        out.entry(value).or_insert((v, *span));
                    }
                }
                S::Block(ref b) => block(fun, b, out),
                S::If {
                    ref accept,
                    ref reject,
                    ..
                } => {
                    block(fun, accept, out);
                    block(fun, reject, out);
                }
                S::Loop {
                    ref body,
                    ref continuing,
                    ..
                } => {
                    block(fun, body, out);
                    block(fun, continuing, out);
                }
                S::Switch { ref cases, .. } => cases.iter().for_each(|c| block(fun, &c.body, out)),
                _ => {}
            }
        }
    }
    let mut out: HashMap<_, _> = fun
        .local_variables
        .iter()
        .filter_map(|(v, l)| Some((l.init?, (v, naga::Span::default()))))
        .collect();
    block(fun, &fun.body, &mut out);
    out
}

type LocalHandle = Handle<naga::LocalVariable>;

/// Line, column and text of the declaration of the variable `name` in the shader's source: the
/// first `TYPE NAME;` (or `= …`, `[…]`) there, the line's text without its final `;`.
fn declaration(shader: &Shader, lines: &LineIndex, name: &str) -> Option<(u32, u32, String)> {
    let src = &shader.source;
    let ident = |b: u8| b.is_ascii_alphanumeric() || b == b'_';
    src.match_indices(name).find_map(|(at, _)| {
        let end = at + name.len();
        let before = src[..at].trim_end();
        let after = src[end..].trim_start();
        let whole = !src[..at].bytes().next_back().is_some_and(ident)
            && !src[end..].bytes().next().is_some_and(ident);
        let typed = before.bytes().next_back().is_some_and(ident) && before.len() < at;
        let declares = after.starts_with([';', '=', '[']);
        if !(whole && typed && declares) {
            return None;
        }
        let start = src[..at].rfind('\n').map_or(0, |i| i + 1);
        let stop = src[at..].find('\n').map_or(src.len(), |i| at + i);
        // Without a comment at the line's end.
        let line = src[start..stop]
            .split("//")
            .next()
            .unwrap_or_default()
            .trim();
        let text = line.strip_suffix(';').unwrap_or(line).trim_end();
        let (l, _) = lines.location(at);
        let col = (start + src[start..stop].len() - src[start..stop].trim_start().len() - start)
            as u32
            + 1;
        Some((
            l,
            col,
            text.split_whitespace().collect::<Vec<_>>().join(" "),
        ))
    })
}

/// A constant's value or name, or an argument's name, as the node's text.
fn leaf_text(module: &naga::Module, fun: &naga::Function, e: &Expression) -> Option<String> {
    let literal = |l: &naga::Literal| match *l {
        naga::Literal::F32(v) => Some(format!("{v:?}")),
        naga::Literal::F16(v) => Some(format!("{v:?}")),
        naga::Literal::F64(v) => Some(format!("{v:?}")),
        _ => None,
    };
    match *e {
        Expression::Literal(ref l) => literal(l),
        Expression::Constant(c) => {
            let constant = &module.constants[c];
            match module.global_expressions[constant.init] {
                Expression::Literal(ref l) if constant.name.is_none() => literal(l),
                _ => constant.name.clone(),
            }
        }
        Expression::FunctionArgument(i) => fun.arguments.get(i as usize)?.name.clone(),
        _ => None,
    }
}

/// A span for an expression the front end left without one (naga's GLSL reader gives built-in
/// calls none): the union of its operands' spans, widened to the call around them when the text
/// before the first operand is `name(`, so that `mix(a, b, t)` reads as written.
fn operand_span(
    shader: &Shader,
    exprs: &naga::Arena<Expression>,
    e: &Expression,
) -> Option<naga::Span> {
    let text = |s: &naga::Span| s.to_range().and_then(|r| shader.source.get(r));
    // Operands spanned where they are used (a constant's span is its declaration, elsewhere).
    let one_expression = |s: &naga::Span| text(s).is_some_and(|t| !t.contains([';', '{', '}']));
    let spans: Vec<naga::Span> = ir::operands(e)
        .into_iter()
        .map(|o| exprs.get_span(o))
        .filter(|s| s.is_defined() && one_expression(s))
        .collect();
    let union = spans.iter().copied().reduce(|mut a, b| {
        a.subsume(b);
        a
    })?;
    let span = if one_expression(&union) {
        union
    } else {
        // Operands far apart: the last one, nearest the use.
        *spans
            .iter()
            .max_by_key(|s| s.to_range().map_or(0, |r| r.start))?
    };
    let range = span.to_range()?;
    let before = shader.source.get(..range.start)?.trim_end();
    let Some(open) = before.strip_suffix('(') else {
        return Some(span);
    };
    let name_len = open
        .bytes()
        .rev()
        .take_while(|b| b.is_ascii_alphanumeric() || *b == b'_')
        .count();
    if name_len == 0 {
        return Some(span);
    }
    // The name alone: `span_text` extends a call's name to its closing parenthesis.
    let start = open.len() - name_len;
    Some(naga::Span::new(start as u32, open.len() as u32))
}

/// The start of every line of a text, to turn byte offsets into lines without rescanning the
/// text (naga's `Span::location` counts the lines before the span every time).
pub(super) struct LineIndex {
    starts: Vec<usize>,
}

impl LineIndex {
    pub(super) fn new(text: &str) -> LineIndex {
        let starts = std::iter::once(0)
            .chain(text.match_indices('\n').map(|(i, _)| i + 1))
            .collect();
        LineIndex { starts }
    }

    /// 1-based line and byte column of `offset`, as `naga::Span::location` gives them.
    fn location(&self, offset: usize) -> (u32, u32) {
        let line = self.starts.partition_point(|&s| s <= offset);
        let start = self.starts[line - 1];
        (line as u32, (offset - start) as u32 + 1)
    }
}

pub(super) fn span_text(
    shader: &Shader,
    lines: &LineIndex,
    span: naga::Span,
) -> (u32, u32, String) {
    if !span.is_defined() || span.to_range().is_none_or(|r| r.end > shader.source.len()) {
        return (0, 0, String::new());
    }
    let (line_number, line_position) = lines.location(span.to_range().unwrap().start);
    let mut range = span.to_range().unwrap();
    // Calls are spanned by their name only: extend to the closing parenthesis.
    let src = shader.source.as_bytes();
    let is_ident = shader.source[range.clone()]
        .bytes()
        .all(|b| b.is_ascii_alphanumeric() || b == b'_' || b == b'<' || b == b'>');
    if is_ident {
        let mut i = range.end;
        while i < src.len() && src[i].is_ascii_whitespace() {
            i += 1;
        }
        if i < src.len() && src[i] == b'(' {
            let mut depth = 0usize;
            while i < src.len() {
                match src[i] {
                    b'(' => depth += 1,
                    b')' => {
                        depth -= 1;
                        if depth == 0 {
                            range.end = i + 1;
                            break;
                        }
                    }
                    _ => {}
                }
                i += 1;
            }
        }
    }
    let text = shader.source[range]
        .split_whitespace()
        .collect::<Vec<_>>()
        .join(" ");
    (line_number, line_position, text)
}

/// WGSL name of a node's type (naga's own printer), or `None` if expressions of this type are not
/// nodes (only f32/f16 scalars, vectors and matrices are).
pub(super) fn node_type(
    inner: &TypeInner,
    types: &naga::UniqueArena<naga::Type>,
) -> Option<String> {
    use naga::common::wgsl::TypeContext;
    let float = |s: naga::Scalar| match (s.kind, s.width) {
        (naga::ScalarKind::Float, 2 | 4) => Some(s),
        (naga::ScalarKind::AbstractFloat, _) => Some(naga::Scalar::F32),
        _ => None,
    };
    let inner = match *inner {
        TypeInner::Scalar(s) => TypeInner::Scalar(float(s)?),
        TypeInner::Vector { size, scalar } => TypeInner::Vector {
            size,
            scalar: float(scalar)?,
        },
        TypeInner::Matrix {
            columns,
            rows,
            scalar,
        } => TypeInner::Matrix {
            columns,
            rows,
            scalar: float(scalar)?,
        },
        _ => return None,
    };
    let mut name = String::new();
    types.write_type_inner(&inner, &mut name).ok()?;
    Some(name)
}
