//! Bad shaders, and what the instancer refuses: syntax and type errors with their place, missing
//! or ambiguous entry points, nodes and options `instance` cannot honour, what a writer cannot
//! write (`--lang`), `--override` values, and bytes that are not text.

use super::{Case, case, shader};

pub(super) fn cases() -> Vec<Case> {
    let mut v = vec![
        // Shaders.
        case(
            "syntax error",
            &[("s.wgsl", &shader("    return vec4<f32>(1.0,;"))],
            &["nodes", "s.wgsl"],
            "s.wgsl:3",
        ),
        case(
            "type mismatch",
            &[("s.wgsl", &shader("    return vec4<f32>(1.0, 2.0);"))],
            &["nodes", "s.wgsl"],
            "s.wgsl:3",
        ),
        case(
            "unknown identifier",
            &[("s.wgsl", &shader("    return vec4<f32>(q);"))],
            &["nodes", "s.wgsl"],
            "s.wgsl:3",
        ),
        case(
            "empty file",
            &[("s.wgsl", "")],
            &["nodes", "s.wgsl"],
            "fragment",
        ),
        case(
            "vertex only",
            &[(
                "s.wgsl",
                "@vertex fn vs() -> @builtin(position) vec4<f32> { return vec4<f32>(0.0); }\n",
            )],
            &["nodes", "s.wgsl"],
            "fragment",
        ),
        case(
            "two fragment entries",
            &[(
                "s.wgsl",
                "@fragment fn a() -> @location(0) vec4<f32> { return vec4<f32>(1.0); }\n@fragment fn b() -> @location(0) vec4<f32> { return vec4<f32>(0.5); }\n",
            )],
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
            &[(
                "s.wgsl",
                "@group(0) @binding(0) var<storage, read_write> o: array<f32>;\n@fragment fn fs(@location(0) p: vec3<f32>) { o[0] = p.x; }\n",
            )],
            &["nodes", "s.wgsl"],
            "s.wgsl:2:14",
        ),
        case(
            "recursion",
            &[(
                "s.wgsl",
                "fn f(x: f32) -> f32 { return f(x); }\n@fragment fn fs() -> @location(0) vec4<f32> { return vec4<f32>(f(1.0)); }\n",
            )],
            &["nodes", "s.wgsl"],
            "s.wgsl",
        ),
        case(
            "unknown type",
            &[(
                "s.wgsl",
                &shader("    let a: vec5<f32> = vec4<f32>(1.0);\n    return vec4<f32>(1.0);"),
            )],
            &["nodes", "s.wgsl"],
            "s.wgsl:3",
        ),
        case(
            "missing return",
            &[("s.wgsl", &shader("    let a = p;"))],
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
            "group taken",
            &[],
            &[
                "instance",
                "good.wgsl",
                "--node",
                "root",
                "--group",
                "0",
                "--out",
                "out",
            ],
            "bind group 0",
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
    const EXTERNAL: &str = "@group(0) @binding(0) var ext: texture_external;\n@group(0) @binding(1) var smp: sampler;\n@fragment\nfn fs_main(@location(0) p: vec3<f32>, @location(2) uv: vec2<f32>) -> @location(0) vec4<f32> {\n    let c = textureSampleBaseClampToEdge(ext, smp, uv).rgb;\n    return vec4<f32>(c * (sin(p * 7.0) * 0.5 + 0.5), 1.0);\n}\n";
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
            &[("ext.wgsl", EXTERNAL)],
            &[
                "instance", "ext.wgsl", "--node", "root", "--out", "v3", "--lang", lang,
            ],
            expect,
        ));
    }
    // `--override` names an override constant the shader declares, with a number.
    const OVERRIDE: &str = "override gain: f32 = 1.0;\n@fragment\nfn fs_main(@location(0) p: vec3<f32>) -> @location(0) vec4<f32> {\n    return vec4<f32>(sin(p * 7.0) * gain, 1.0);\n}\n";
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
            &[("o.wgsl", OVERRIDE)],
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
        files: vec![("s.wgsl", vec![0xff, 0xfe, 0x00, 0x41])],
        args: vec!["nodes", "s.wgsl"],
        expect: "s.wgsl",
    });
    v
}
