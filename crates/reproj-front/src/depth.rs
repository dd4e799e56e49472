//! A limit on how long a chain of operations one statement may hold, measured on the text before
//! naga reads it.
//!
//! Why: naga's WGSL (and GLSL) front end lowers an expression recursively, one stack frame per
//! level. Its parser caps *nesting* (brackets, calls: see
//! [`crate::diagnostic::WGSL_NESTING_LIMIT`]) but not a long flat chain: `1.0 + 1.0 + … + 1.0`
//! with 20,000 terms is a left-leaning tree 20,000 levels deep, which overflowed the stack. A
//! chain is as deep as it has operators, so the binary operators of each statement are counted
//! ([`check_chains`]) and a statement with more than [`MAX_EXPRESSION_DEPTH`] is refused at the
//! operator past the limit. Long code made of many statements is not limited: a chain of `let`s
//! (each naming the one before) is read and walked whole (`tests/scale.rs`, 20,000 lines).

use std::path::Path;

use crate::diagnostic::{Message, SourceDiagnostic};
use crate::shader::FrontError;

/// The most binary operators one statement may hold. Far past real shaders (a few hundred at
/// most); far below what overflows naga's lowering on the main thread's stack (10,000 did not).
pub const MAX_EXPRESSION_DEPTH: usize = 4096;

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

    /// `let x = u.x + u.x + ...;` with `terms` terms.
    fn chain(terms: usize) -> String {
        let sum = vec!["u.x"; terms].join(" + ");
        format!(
            "@group(0) @binding(0) var<uniform> u: vec4<f32>;\n\
             @fragment fn main() -> @location(0) vec4<f32> {{ let x = {sum}; return vec4<f32>(x); }}"
        )
    }

    /// 20,000 terms overflowed the stack in naga's WGSL lowering; now refused from
    /// the text, before naga reads it.
    #[test]
    fn a_chain_past_the_limit_is_refused_from_the_text() {
        let e = crate::parse::parse_shader(Path::new("chain.wgsl"), chain(20_000)).unwrap_err();
        let text = e.to_string();
        assert!(text.contains("levels deep"), "{text}");
        assert!(text.contains("chain.wgsl:2"), "{text}");
    }

    /// A chain under the limit parses.
    #[test]
    fn a_chain_under_the_limit_parses() {
        assert!(crate::parse::parse_shader(Path::new("chain.wgsl"), chain(3_000)).is_ok());
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
}
