//! A limit on how deep an expression tree may be, measured before any recursive walk.
//!
//! Why: normalization, node enumeration, costs and the rebuild walk expression trees recursively
//! (one stack frame per level). naga's WGSL parser caps *nesting* (brackets, calls: see
//! [`crate::diagnostic::WGSL_NESTING_LIMIT`]) but not a long flat chain: `1.0 + 1.0 + … + 1.0`
//! with 20,000 terms parses into a left-leaning tree 20,000 levels deep, which overflowed the
//! stack. The depth is measured here without recursion (naga's arenas list an expression's
//! operands before it, so one pass in arena order finds every depth), and a tree deeper than
//! [`MAX_EXPRESSION_DEPTH`] is refused at its place in the source.
//!
//! naga's own WGSL and GLSL front ends lower such a chain recursively too, so the source text is
//! measured first ([`check_chains`]): a statement with more than [`MAX_EXPRESSION_DEPTH`]
//! binary operators is refused before naga reads it.

use std::path::Path;

use naga::{Function, Span};

use crate::diagnostic::{Message, SourceDiagnostic};
use crate::parse::{FrontError, Shader};

/// The deepest expression tree reproj walks. Far past real shaders (a few hundred levels at
/// most); far below what overflows the main thread's stack in any command's walks.
pub const MAX_EXPRESSION_DEPTH: usize = 4096;

/// The depth of the deepest expression of `fun` and its span (a leaf is depth 1), measured in one
/// pass in arena order.
pub fn deepest(fun: &Function) -> (usize, Span) {
    let mut depth = vec![0usize; fun.expressions.len()];
    let mut best = (0, Span::UNDEFINED);
    for (h, e) in fun.expressions.iter() {
        let i = h.index();
        let below = crate::ir::operands(e)
            .into_iter()
            // An operand listed later than its user cannot happen in a valid module; it counts 0.
            .filter_map(|o| depth.get(o.index()).copied().filter(|_| o.index() < i))
            .max()
            .unwrap_or(0);
        depth[i] = below + 1;
        if depth[i] > best.0 {
            best = (depth[i], fun.expressions.get_span(h));
        }
    }
    best
}

/// Refuse `shader` when one of its functions holds an expression tree deeper than
/// [`MAX_EXPRESSION_DEPTH`], labelled at the deepest expression.
pub fn check_depth(shader: &Shader) -> Result<(), FrontError> {
    let module = &shader.module;
    let functions = module
        .functions
        .iter()
        .map(|(_, f)| f)
        .chain(module.entry_points.iter().map(|ep| &ep.function));
    for fun in functions {
        let (depth, span) = deepest(fun);
        if depth > MAX_EXPRESSION_DEPTH {
            return Err(shader.unsupported(
                span,
                format!(
                    "an expression {depth} levels deep (reproj reads at most {MAX_EXPRESSION_DEPTH}): \
                     split the long chain of operations with `let`s into shorter ones"
                ),
            ));
        }
    }
    Ok(())
}

/// Refuse a module read from another form (SPIR-V, composed WGSL) whose expressions nest past
/// [`MAX_EXPRESSION_DEPTH`], before it is written as WGSL and read again (naga's writer and
/// parser recurse too). It has no text of the user's to point into: the message says how deep.
pub fn check_module(path: &Path, module: &naga::Module, what: &str) -> Result<(), FrontError> {
    let functions = module
        .functions
        .iter()
        .map(|(_, f)| f)
        .chain(module.entry_points.iter().map(|ep| &ep.function));
    for fun in functions {
        let (depth, _) = deepest(fun);
        if depth > MAX_EXPRESSION_DEPTH {
            let name = fun.name.as_deref().unwrap_or("a function");
            return Err(FrontError::Unsupported(SourceDiagnostic::new(
                path.to_owned(),
                "",
                vec![Message::new(format!(
                    "unsupported: in the {what} module, `{name}` has an expression {depth} levels deep (reproj reads at most {MAX_EXPRESSION_DEPTH}): split the long chain of operations into shorter ones"
                ))],
            )));
        }
    }
    Ok(())
}

/// Refuse shader text (WGSL or GLSL) with a statement holding more than
/// [`MAX_EXPRESSION_DEPTH`] binary operators, labelled at the operator past the limit. A flat
/// chain is as deep as it has operators; counted without parsing, outside comments, a statement
/// ending at `;`, `{` or `}`. An operator is binary when it follows a name, a number, `)` or `]`
/// (so `-1.0` in a list of constants does not count); `<` and `>` of types count too, a few per
/// statement at most.
pub fn check_chains(path: &Path, source: &str) -> Result<(), FrontError> {
    let bytes = source.as_bytes();
    let (mut i, mut count) = (0usize, 0usize);
    let mut prev = b' ';
    while i < bytes.len() {
        let c = bytes[i];
        let next = bytes.get(i + 1).copied();
        match (c, next) {
            (b'/', Some(b'/')) => {
                while i < bytes.len() && bytes[i] != b'\n' {
                    i += 1;
                }
                continue;
            }
            (b'/', Some(b'*')) => {
                i += 2;
                while i + 1 < bytes.len() && !(bytes[i] == b'*' && bytes[i + 1] == b'/') {
                    i += 1;
                }
                i += 2;
                continue;
            }
            (b';' | b'{' | b'}', _) => count = 0,
            _ => {}
        }
        let operator = b"+-*/%&|^<>=!".contains(&c);
        if operator && (prev.is_ascii_alphanumeric() || matches!(prev, b'_' | b'.' | b')' | b']')) {
            count += 1;
            if count > MAX_EXPRESSION_DEPTH {
                let mut m = Message::new(format!(
                    "a statement with more than {MAX_EXPRESSION_DEPTH} operators: reproj reads expressions at most {MAX_EXPRESSION_DEPTH} levels deep"
                ));
                m.labels.push((i..i + 1, format!("operator {count} here")));
                m.notes.push(
                    "split the long chain of operations with `let`s into shorter ones".into(),
                );
                return Err(FrontError::Unsupported(SourceDiagnostic::new(
                    path.to_owned(),
                    source,
                    vec![m],
                )));
            }
        }
        if !c.is_ascii_whitespace() {
            prev = c;
        }
        i += 1;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `let x = u.x + u.x + ...;` with `terms` terms (a uniform: literals would be folded).
    fn chain(terms: usize) -> String {
        let sum = vec!["u.x"; terms].join(" + ");
        format!(
            "@group(0) @binding(0) var<uniform> u: vec4<f32>;\n\
             @fragment fn main() -> @location(0) vec4<f32> {{ let x = {sum}; return vec4<f32>(x); }}"
        )
    }

    fn shader(src: String) -> Shader {
        crate::parse::parse_shader(std::path::Path::new("chain.wgsl"), src).unwrap()
    }

    #[test]
    fn a_flat_chain_is_measured_without_recursion() {
        let s = shader(chain(100));
        let (depth, _) = deepest(&s.module.entry_points[0].function);
        assert!((100..110).contains(&depth), "{depth}");
        assert!(check_depth(&s).is_ok());
    }

    /// Issue 45: 20,000 terms overflowed the stack (in naga's WGSL lowering, then in reproj's
    /// walks); now refused from the text, before naga reads it.
    #[test]
    fn a_chain_past_the_limit_is_refused_from_the_text() {
        let e = crate::parse::parse_shader(Path::new("chain.wgsl"), chain(20_000)).unwrap_err();
        let text = e.to_string();
        assert!(text.contains("levels deep"), "{text}");
        assert!(text.contains("chain.wgsl:2"), "{text}");
    }

    /// Long lists of negative constants and comments full of operators are not chains.
    #[test]
    fn constants_and_comments_are_not_chains() {
        let list = vec!["-1.0"; 10_000].join(", ");
        let ops = vec!["a + b"; 5_000].join(" ");
        let src = format!("// {ops}\n/* {ops} */\nconst K = array<f32, 10000>({list});\n");
        assert!(check_chains(Path::new("k.wgsl"), &src).is_ok());
        let src = format!("const K = {};", vec!["1.0"; 5_000].join(" * "));
        assert!(check_chains(Path::new("k.wgsl"), &src).is_err());
    }

    /// The IR measure agrees with the text on a chain under the limit.
    #[test]
    fn a_chain_under_the_limit_passes_both_measures() {
        let s = shader(chain(3_000));
        let (depth, _) = deepest(&s.module.entry_points[0].function);
        assert!(depth >= 3_000, "{depth}");
        assert!(check_depth(&s).is_ok());
    }
}
