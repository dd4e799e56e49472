//! WGSL written for an older naga: `binding_array<…>` without `enable wgpu_binding_array;`.
//!
//! naga 30 (wgpu 28 on) reads `binding_array` only under that enable directive; the naga of
//! earlier wgpu releases read it without one, and shaders written for them (Bevy's
//! `mesh_view_bindings`, `bindless`, its binding-array examples) have none. Such a text, and
//! each module it imports, is read as if it began with the directive. The directive takes the
//! place of a blank or comment first line (a comment is then dropped: lines and the spans in
//! them stay where they were) and goes on a line of its own before any other first line.

use std::borrow::Cow;

/// The directive added.
const ENABLE: &str = "enable wgpu_binding_array;";

/// `source` with `enable wgpu_binding_array;` where it uses `binding_array<` outside comments
/// and enables no `wgpu_binding_array` itself; otherwise `source` as it is.
pub fn enable_binding_arrays(source: &str) -> Cow<'_, str> {
    let code = || source.lines().map(|l| l.split("//").next().unwrap_or(""));
    let uses = code().any(|l| l.contains("binding_array<"));
    let enables = code().any(|l| {
        let l = l.trim_start();
        l.starts_with("enable") && l.contains("wgpu_binding_array")
    });
    if !uses || enables {
        return Cow::Borrowed(source);
    }
    let (first, rest) = source.split_once('\n').unwrap_or((source, ""));
    let first = first.trim_end_matches('\r');
    let trimmed = first.trim();
    if trimmed.is_empty() || (trimmed.starts_with("//") && !trimmed.starts_with("/*")) {
        Cow::Owned(format!("{ENABLE}\n{rest}"))
    } else {
        Cow::Owned(format!("{ENABLE}\n{source}"))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_directive_takes_a_comment_lines_place() {
        let s = "// a header\n@group(0) @binding(0) var t: binding_array<texture_2d<f32>>;\n";
        let out = enable_binding_arrays(s);
        assert_eq!(out.lines().count(), s.lines().count());
        assert!(out.starts_with("enable wgpu_binding_array;\n@group"));
    }

    #[test]
    fn a_code_first_line_gets_the_directive_above_it() {
        let s = "#import x\n@group(0) @binding(0) var t: binding_array<texture_2d<f32>>;\n";
        assert!(enable_binding_arrays(s).starts_with("enable wgpu_binding_array;\n#import x"));
    }

    #[test]
    fn a_text_that_enables_it_or_does_not_use_it_is_kept() {
        let s = "enable wgpu_binding_array;\nvar<private> t: binding_array<u32, 2>;\n";
        assert!(matches!(enable_binding_arrays(s), Cow::Borrowed(_)));
        let s = "// binding_array<u32> in a comment\nfn f() {}\n";
        assert!(matches!(enable_binding_arrays(s), Cow::Borrowed(_)));
    }
}
