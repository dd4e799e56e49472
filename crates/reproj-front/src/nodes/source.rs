//! How a node reads: its line, column and source text (from its span, or from the variable it
//! loads or its operands where the front end left none), and its type as WGSL spells it.

use naga::{Expression, Handle, TypeInner};

use crate::ir;
use crate::parse::Shader;

/// Line, column and source text of the expression `h`, from its span or, where the front end
/// left none, from the variable it loads or its operands.
pub(super) fn source_position(
    shader: &Shader,
    lines: &LineIndex,
    fun: &naga::Function,
    h: Handle<Expression>,
    e: &Expression,
) -> (u32, u32, String) {
    let span = fun.expressions.get_span(h);
    match (span.is_defined(), e) {
        // Loads made by the front end (`x += ...`, a read after a loop) have no span: name the
        // variable instead.
        (false, Expression::Load { pointer }) => match ir::root_local(&fun.expressions, *pointer) {
            Some(v) => {
                let (l, c, _) = span_text(shader, lines, fun.local_variables.get_span(v));
                (
                    l,
                    c,
                    fun.local_variables[v].name.clone().unwrap_or_default(),
                )
            }
            None => (0, 0, String::new()),
        },
        (false, _) => operand_span(shader, &fun.expressions, e)
            .map_or((0, 0, String::new()), |s| span_text(shader, lines, s)),
        _ => span_text(shader, lines, span),
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
