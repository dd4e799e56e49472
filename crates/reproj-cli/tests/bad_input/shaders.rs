//! Bad shaders, and what the instancer refuses: syntax and type errors with their place, missing
//! or ambiguous entry points, nodes and options `instance` cannot honour, what a writer cannot
//! write (`--lang`), `--override` values, and bytes that are not text.

use super::{Case, case, input, input_bytes};

pub(super) fn cases() -> Vec<Case> {
    let mut v = vec![
        // Shaders.
        case(
            "syntax error",
            &[("s.wgsl", &input("shaders/syntax_error.wgsl"))],
            &["nodes", "s.wgsl"],
            "s.wgsl:3",
        ),
        case(
            "type mismatch",
            &[("s.wgsl", &input("shaders/type_mismatch.wgsl"))],
            &["nodes", "s.wgsl"],
            "s.wgsl:3",
        ),
        case(
            "unknown identifier",
            &[("s.wgsl", &input("shaders/unknown_identifier.wgsl"))],
            &["nodes", "s.wgsl"],
            "s.wgsl:3",
        ),
        case(
            "empty file",
            &[("s.wgsl", &input("shaders/empty.wgsl"))],
            &["nodes", "s.wgsl"],
            "fragment",
        ),
        case(
            "vertex only",
            &[("s.wgsl", &input("shaders/vertex_only.wgsl"))],
            &["nodes", "s.wgsl"],
            "fragment",
        ),
        case(
            "two fragment entries",
            &[("s.wgsl", &input("shaders/two_fragment_entries.wgsl"))],
            &["nodes", "s.wgsl"],
            "--entry",
        ),
        case(
            "unknown entry",
            &[],
            &["nodes", "good.wgsl", "--entry", "nope"],
            "nope",
        ),
        case(
            "missing shader",
            &[],
            &["nodes", "missing.wgsl"],
            "missing.wgsl",
        ),
        case(
            "shader is a directory",
            &[],
            &["nodes", "variant"],
            "variant",
        ),
        case(
            "entry point with no output",
            &[("s.wgsl", &input("shaders/no_output.wgsl"))],
            &["nodes", "s.wgsl"],
            "s.wgsl:2:14",
        ),
        case(
            "recursion",
            &[("s.wgsl", &input("shaders/recursion.wgsl"))],
            &["nodes", "s.wgsl"],
            "s.wgsl",
        ),
        case(
            "unknown type",
            &[("s.wgsl", &input("shaders/unknown_type.wgsl"))],
            &["nodes", "s.wgsl"],
            "s.wgsl:3",
        ),
        case(
            "missing return",
            &[("s.wgsl", &input("shaders/missing_return.wgsl"))],
            &["nodes", "s.wgsl"],
            "s.wgsl:2:1",
        ),
        // Instancing.
        case(
            "unknown node",
            &[],
            &["instance", "good.wgsl", "--node", "99999", "--out", "out"],
            "no node 99999",
        ),
        case(
            "node is not a number",
            &[],
            &["instance", "good.wgsl", "--node", "abc", "--out", "out"],
            "`abc` is not a node id",
        ),
        case(
            "odd block",
            &[],
            &[
                "instance",
                "good.wgsl",
                "--node",
                "root",
                "--block",
                "3",
                "--out",
                "out",
            ],
            "block size",
        ),
        case(
            "zero refresh period",
            &[],
            &[
                "instance",
                "good.wgsl",
                "--node",
                "root",
                "--delta-n",
                "0",
                "--out",
                "out",
            ],
            "refresh period",
        ),
        case(
            "group too high",
            &[],
            &[
                "instance",
                "good.wgsl",
                "--node",
                "root",
                "--group",
                "9",
                "--out",
                "out",
            ],
            "bind group 9",
        ),
        case(
            "cache format too narrow",
            &[],
            &[
                "instance",
                "good.wgsl",
                "--node",
                "root",
                "--cache-format",
                "r32float",
                "--out",
                "out",
            ],
            "r32float",
        ),
        case(
            "unknown strategy",
            &[],
            &[
                "instance",
                "good.wgsl",
                "--node",
                "root",
                "--strategy",
                "4pass",
                "--out",
                "out",
            ],
            "4pass",
        ),
        case(
            "out is a file",
            &[],
            &[
                "instance",
                "good.wgsl",
                "--node",
                "root",
                "--out",
                "good.json",
            ],
            "good.json",
        ),
    ];
    // What a writer cannot write is refused before it is called: exit 2, one line naming the
    // variable, nothing written.
    let external = input("shaders/texture_external.wgsl");
    for (name, lang, expect) in [
        (
            "texture_external to GLSL",
            "glsl",
            "`ext` is a texture_external, which the GLSL output cannot hold",
        ),
        (
            "texture_external to SPIR-V",
            "spv",
            "`ext` is a texture_external, which the SPIR-V output cannot hold",
        ),
    ] {
        v.push(case(
            name,
            &[("ext.wgsl", &external)],
            &[
                "instance", "ext.wgsl", "--node", "root", "--out", "v3", "--lang", lang,
            ],
            expect,
        ));
    }
    // `--override` names an override constant the shader declares, with a number.
    let overridden = input("shaders/override_gain.wgsl");
    for (name, value, expect) in [
        (
            "override the shader does not declare",
            "bias=2",
            "the shader has no override constant `bias` (its overrides: gain)",
        ),
        (
            "override without a value",
            "gain",
            "`gain` is not NAME=VALUE",
        ),
        (
            "override not a number",
            "gain=fast",
            "`fast` is not a finite number",
        ),
    ] {
        v.push(case(
            name,
            &[("o.wgsl", &overridden)],
            &[
                "instance",
                "o.wgsl",
                "--node",
                "root",
                "--out",
                "v4",
                "--lang",
                "glsl",
                "--override",
                value,
            ],
            expect,
        ));
    }
    // Unreadable bytes where text belongs.
    v.push(Case {
        name: "shader not UTF-8",
        files: vec![("s.wgsl", input_bytes("shaders/not_utf8.wgsl"))],
        args: vec!["nodes", "s.wgsl"],
        expect: "s.wgsl",
    });
    v
}
