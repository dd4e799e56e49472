//! The bad-input corpus: malformed shaders, sessions, manifests, profiles and arguments, each run
//! through the real binary. Every case must exit 2 with one clear message naming what is wrong
//! (the expected text), never panic, and write nothing.
//!
//! Each case runs in a fresh directory holding `good.wgsl` and `good.json` (a valid shader and
//! session), `good.profile.json` (their profile), `variant/` (a written variant), plus the case's
//! own files.

use std::collections::BTreeSet;
use std::path::{Path, PathBuf};

mod common;
use common::{root, run};

fn files(dir: &Path) -> BTreeSet<PathBuf> {
    let mut out = BTreeSet::new();
    let mut stack = vec![dir.to_owned()];
    while let Some(d) = stack.pop() {
        for e in std::fs::read_dir(&d).unwrap() {
            let p = e.unwrap().path();
            if p.is_dir() {
                stack.push(p.clone());
            }
            out.insert(p);
        }
    }
    out
}

fn copy_dir(from: &Path, to: &Path) {
    std::fs::create_dir_all(to).unwrap();
    for e in std::fs::read_dir(from).unwrap() {
        let p = e.unwrap().path();
        let dest = to.join(p.file_name().unwrap());
        if p.is_dir() {
            copy_dir(&p, &dest);
        } else {
            std::fs::copy(&p, &dest).unwrap();
        }
    }
}

/// One bad input: its own files (name, contents), the arguments, and text the message must hold.
struct Case {
    name: &'static str,
    files: Vec<(&'static str, Vec<u8>)>,
    args: Vec<&'static str>,
    expect: &'static str,
}

fn case(
    name: &'static str,
    files: &[(&'static str, &str)],
    args: &[&'static str],
    expect: &'static str,
) -> Case {
    Case {
        name,
        files: files
            .iter()
            .map(|(n, c)| (*n, c.as_bytes().to_vec()))
            .collect(),
        args: args.to_vec(),
        expect,
    }
}

const FRAG_HEAD: &str =
    "@fragment\nfn fs_main(@location(0) p: vec3<f32>) -> @location(0) vec4<f32> {\n";

fn shader(body: &str) -> String {
    format!("{FRAG_HEAD}{body}\n}}\n")
}

fn cases(good_session: &serde_json::Value, good_profile: &serde_json::Value) -> Vec<Case> {
    let session = |edit: &dyn Fn(&mut serde_json::Value)| {
        let mut v = good_session.clone();
        edit(&mut v);
        serde_json::to_string(&v).unwrap()
    };
    let profile = |edit: &dyn Fn(&mut serde_json::Value)| {
        let mut v = good_profile.clone();
        edit(&mut v);
        serde_json::to_string(&v).unwrap()
    };
    let render_with = |file: &'static str| -> Vec<&'static str> {
        vec![
            "render",
            "good.wgsl",
            "--session",
            file,
            "--max-frames",
            "2",
        ]
    };
    let emit_with = |file: &'static str| -> Vec<&'static str> {
        vec![
            "emit",
            "--max-error",
            "0.01",
            "--profile",
            file,
            "--out",
            "out",
        ]
    };
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
        // Sessions.
        case(
            "missing session",
            &[],
            &["render", "good.wgsl", "--session", "missing.json"],
            "missing.json",
        ),
        case(
            "session not JSON",
            &[("s.json", "{ not json")],
            &render_with("s.json"),
            "s.json",
        ),
        case(
            "session empty",
            &[("s.json", "")],
            &render_with("s.json"),
            "s.json",
        ),
        case(
            "session of another schema",
            &[(
                "s.json",
                &session(&|v| v["schema"] = "reproj.profile".into()),
            )],
            &render_with("s.json"),
            "schema",
        ),
        case(
            "session version 99",
            &[("s.json", &session(&|v| v["version"] = 99.into()))],
            &render_with("s.json"),
            "version",
        ),
        case(
            "session without resolution",
            &[(
                "s.json",
                &session(&|v| {
                    v.as_object_mut().unwrap().remove("resolution");
                }),
            )],
            &render_with("s.json"),
            "resolution",
        ),
        case(
            "session resolution zero",
            &[(
                "s.json",
                &session(&|v| v["resolution"] = serde_json::json!([0, 64])),
            )],
            &render_with("s.json"),
            "resolution",
        ),
        case(
            "session resolution huge",
            &[(
                "s.json",
                &session(&|v| v["resolution"] = serde_json::json!([100000, 64])),
            )],
            &render_with("s.json"),
            "resolution",
        ),
        case(
            "session frames as text",
            &[("s.json", &session(&|v| v["frames"] = "ten".into()))],
            &render_with("s.json"),
            "frames",
        ),
        case(
            "session negative fps",
            &[("s.json", &session(&|v| v["fps"] = (-30).into()))],
            &render_with("s.json"),
            "fps",
        ),
        case(
            "session unknown field",
            &[("s.json", &session(&|v| v["colour"] = 1.into()))],
            &render_with("s.json"),
            "colour",
        ),
        case(
            "session without the shader's texture",
            &[(
                "s.json",
                &session(&|v| {
                    v["textures"].as_object_mut().unwrap().clear();
                }),
            )],
            &render_with("s.json"),
            "albedo_map",
        ),
        case(
            "session without the shader's uniform",
            &[(
                "s.json",
                &session(&|v| {
                    v["uniforms"].as_object_mut().unwrap().remove("gain");
                }),
            )],
            &render_with("s.json"),
            "gain",
        ),
        case(
            "session camera without keys",
            &[(
                "s.json",
                &session(&|v| v["camera"] = serde_json::json!({"keys": []})),
            )],
            &render_with("s.json"),
            "camera",
        ),
        // Written variants.
        case(
            "variant missing",
            &[],
            &[
                "render",
                "good.wgsl",
                "--session",
                "good.json",
                "--variant",
                "nowhere",
            ],
            "nowhere",
        ),
        case(
            "variant manifest not JSON",
            &[("v/manifest.json", "{")],
            &[
                "render",
                "good.wgsl",
                "--session",
                "good.json",
                "--variant",
                "v",
            ],
            "manifest.json",
        ),
        case(
            "variant manifest version 2",
            &[(
                "v/manifest.json",
                "{\"schema\": \"reproj.manifest\", \"version\": 2}",
            )],
            &[
                "render",
                "good.wgsl",
                "--session",
                "good.json",
                "--variant",
                "v",
            ],
            "version 2",
        ),
        case(
            "variant manifest missing passes",
            &[(
                "v/manifest.json",
                "{\"schema\": \"reproj.manifest\", \"version\": 3}",
            )],
            &[
                "render",
                "good.wgsl",
                "--session",
                "good.json",
                "--variant",
                "v",
            ],
            "manifest.json",
        ),
        // Arguments.
        case(
            "render zero refresh period",
            &[],
            &[
                "render",
                "good.wgsl",
                "--session",
                "good.json",
                "--node",
                "root",
                "--delta-n",
                "0",
            ],
            "refresh period",
        ),
        case(
            "analyze period 1",
            &[],
            &[
                "analyze",
                "good.wgsl",
                "--session",
                "good.json",
                "--delta-n",
                "1,4",
            ],
            "refresh period",
        ),
        case(
            "analyze period not a number",
            &[],
            &[
                "analyze",
                "good.wgsl",
                "--session",
                "good.json",
                "--delta-n",
                "a",
            ],
            "--delta-n",
        ),
        case(
            "analyze unknown node",
            &[],
            &[
                "analyze",
                "good.wgsl",
                "--session",
                "good.json",
                "--nodes",
                "99999",
                "--delta-n",
                "2,4",
                "--holdout",
                "3",
            ],
            "no node 99999",
        ),
        case(
            "analyze shard out of range",
            &[],
            &[
                "analyze",
                "good.wgsl",
                "--session",
                "good.json",
                "--shard",
                "3/3",
            ],
            "3/3",
        ),
        case(
            "analyze shard not a shard",
            &[],
            &[
                "analyze",
                "good.wgsl",
                "--session",
                "good.json",
                "--shard",
                "half",
            ],
            "half",
        ),
        case(
            "analyze set search over fewer than two nodes",
            &[],
            &[
                "analyze",
                "good.wgsl",
                "--session",
                "good.json",
                "--set-top",
                "1",
            ],
            "--set-top",
        ),
        case(
            "analyze no sets and a set option",
            &[],
            &[
                "analyze",
                "good.wgsl",
                "--session",
                "good.json",
                "--no-sets",
                "--set-max-nodes",
                "2",
            ],
            "--no-sets",
        ),
        case(
            "emit negative budget",
            &[],
            &[
                "emit",
                "--max-error",
                "-1",
                "--profile",
                "good.profile.json",
                "--out",
                "out",
            ],
            "--max-error",
        ),
        case(
            "emit NaN budget",
            &[],
            &[
                "emit",
                "--max-error",
                "NaN",
                "--profile",
                "good.profile.json",
                "--out",
                "out",
            ],
            "--max-error",
        ),
        case(
            "emit node is not a number",
            &[],
            &[
                "emit",
                "--max-error",
                "0.01",
                "--profile",
                "good.profile.json",
                "--node",
                "abc",
                "--out",
                "out",
            ],
            "--node abc",
        ),
        case(
            "emit motion without a session",
            &[],
            &[
                "emit",
                "--max-error",
                "0.01",
                "--profile",
                "good.profile.json",
                "--motion",
                "ignore",
                "--out",
                "out",
            ],
            "--session",
        ),
        case(
            "render adaptive without a variant",
            &[],
            &[
                "render",
                "good.wgsl",
                "--session",
                "good.json",
                "--adaptive",
            ],
            "--variant",
        ),
        case(
            "profile is a directory",
            &[],
            &[
                "emit",
                "--max-error",
                "0.01",
                "--profile",
                "variant",
                "--out",
                "out",
            ],
            "variant",
        ),
        case(
            "unknown subcommand",
            &[],
            &["optimize", "good.wgsl"],
            "optimize",
        ),
        // Profiles.
        case(
            "missing profile",
            &[],
            &emit_with("missing.profile.json"),
            "missing.profile.json",
        ),
        case(
            "profile not JSON",
            &[("p.json", "[1, 2")],
            &emit_with("p.json"),
            "p.json",
        ),
        case(
            "profile of another schema",
            &[(
                "p.json",
                &profile(&|v| v["schema"] = "reproj.session".into()),
            )],
            &emit_with("p.json"),
            "schema",
        ),
        case(
            "profile version 99",
            &[("p.json", &profile(&|v| v["version"] = 99.into()))],
            &emit_with("p.json"),
            "version",
        ),
        case(
            "profile without nodes",
            &[(
                "p.json",
                &profile(&|v| {
                    v.as_object_mut().unwrap().remove("nodes");
                }),
            )],
            &emit_with("p.json"),
            "nodes",
        ),
        case(
            "profile with a text frame time",
            &[(
                "p.json",
                &profile(&|v| v["original"]["frame_ms"] = "fast".into()),
            )],
            &emit_with("p.json"),
            "original.frame_ms",
        ),
        case(
            "profile of a changed shader",
            &[(
                "p.json",
                &profile(&|v| v["shader"]["ir_hash"] = "0123456789abcdef".into()),
            )],
            &emit_with("p.json"),
            "changed since",
        ),
        case(
            "profile's shader missing",
            &[(
                "p.json",
                &profile(&|v| v["shader"]["path"] = "gone.wgsl".into()),
            )],
            &emit_with("p.json"),
            "gone.wgsl",
        ),
        case(
            "merge a whole profile",
            &[],
            &["merge", "good.profile.json", "--out", "m.json"],
            "not a shard",
        ),
        case(
            "merge a missing file",
            &[],
            &["merge", "nope.json", "--out", "m.json"],
            "nope.json",
        ),
    ];
    // Numbers checked at the door (exit 2 naming the flag and the range), before any rendering.
    let analyze = |extra: &[&'static str]| -> Vec<&'static str> {
        let mut a = vec!["analyze", "good.wgsl", "--session", "good.json"];
        a.extend_from_slice(extra);
        a
    };
    for (name, extra, expect) in [
        ("analyze odd block", &["--block", "3"][..], "--block"),
        ("analyze zero block", &["--block", "0"][..], "--block"),
        ("analyze huge block", &["--block", "4096"][..], "--block"),
        (
            "analyze zero frames",
            &["--max-frames", "0"][..],
            "--max-frames",
        ),
        (
            "analyze negative epsilon",
            &["--depth-epsilon=-1"][..],
            "--depth-epsilon",
        ),
        (
            "analyze NaN epsilon",
            &["--depth-epsilon", "NaN"][..],
            "--depth-epsilon",
        ),
        (
            "analyze repeated period",
            &["--delta-n", "2,2,2"][..],
            "named twice",
        ),
        (
            "analyze period also held out",
            &["--delta-n", "2,4", "--holdout", "4"][..],
            "named twice",
        ),
        (
            "analyze period far too long",
            &["--delta-n", "1000000"][..],
            "--delta-n",
        ),
        (
            "analyze period past ten sessions",
            &["--delta-n", "2,4", "--holdout", "3,100"][..],
            "more than 10 times",
        ),
        ("analyze no nodes", &["--max-nodes", "0"][..], "--max-nodes"),
        (
            "analyze saving above 1",
            &["--min-saving", "2"][..],
            "--min-saving",
        ),
    ] {
        v.push(case(name, &[], &analyze(extra), expect));
    }
    v.extend([
        case(
            "emit zero longest period",
            &[],
            &[
                "emit",
                "--max-error",
                "0.01",
                "--profile",
                "good.profile.json",
                "--max-delta-n",
                "0",
                "--out",
                "out",
            ],
            "--max-delta-n",
        ),
        case(
            "emit NaN budget",
            &[],
            &[
                "emit",
                "--max-error",
                "NaN",
                "--profile",
                "good.profile.json",
                "--out",
                "out",
            ],
            "--max-error",
        ),
        case(
            "emit NaN min speedup",
            &[],
            &[
                "emit",
                "--max-error",
                "0.01",
                "--profile",
                "good.profile.json",
                "--min-speedup",
                "NaN",
                "--out",
                "out",
            ],
            "--min-speedup",
        ),
        case(
            "instance NaN epsilon",
            &[],
            &[
                "instance",
                "good.wgsl",
                "--node",
                "root",
                "--out",
                "v2",
                "--depth-epsilon",
                "NaN",
            ],
            "--depth-epsilon",
        ),
        case(
            "instance period 0",
            &[],
            &[
                "instance",
                "good.wgsl",
                "--node",
                "root",
                "--out",
                "v2",
                "--delta-n",
                "0",
            ],
            "--delta-n",
        ),
        case(
            "render zero frames",
            &[],
            &[
                "render",
                "good.wgsl",
                "--session",
                "good.json",
                "--max-frames",
                "0",
            ],
            "--max-frames",
        ),
        case(
            "compare zero longest period",
            &[],
            &[
                "compare",
                "good.wgsl",
                "--session",
                "good.json",
                "--speedup",
                "2",
                "--max-delta-n",
                "1",
            ],
            "--max-delta-n",
        ),
        // Other people's files: refused before any work, left as they were.
        case(
            "analyze over a user's file",
            &[("u.txt", "my notes\n")],
            &analyze(&["--out", "u.txt"]),
            "not a reproj.profile",
        ),
        case(
            "analyze over a user's chart name",
            &[("p2.tradeoff.svg", "my notes\n")],
            &analyze(&["--out", "p2.json"]),
            "p2.tradeoff.svg",
        ),
        case(
            "analyze into a directory",
            &[("d/keep.txt", "mine\n")],
            &analyze(&["--out", "d"]),
            "is a directory",
        ),
        case(
            "analyze under a file",
            &[("f", "mine\n")],
            &analyze(&["--out", "f/p.json"]),
            "f/p.json",
        ),
        case(
            "merge over a user's file",
            &[("u.txt", "my notes\n")],
            &["merge", "good.profile.json", "--out", "u.txt"],
            "not a reproj.profile",
        ),
        case(
            "merge over a session",
            &[],
            &["merge", "good.profile.json", "--out", "good.json"],
            "not a reproj.profile",
        ),
        case(
            "report over a user's page",
            &[("u.html", "<html><title>mine</title></html>\n")],
            &["report", "good.profile.json", "--out", "u.html"],
            "u.html",
        ),
    ]);
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
    // What a session or a profile may name: files beside it, never other files of the machine
    // (and their contents never shown).
    v.extend([
        case(
            "session mesh outside its folder",
            &[(
                "s.json",
                &session(&|v| {
                    v["geometry"]["objects"][0]["mesh"] =
                        serde_json::json!({"obj": {"path": "/etc/passwd"}})
                }),
            )],
            &render_with("s.json"),
            "outside the session's folder",
        ),
        case(
            "session texture above its folder",
            &[(
                "s.json",
                &session(&|v| {
                    v["textures"]["albedo_map"] =
                        serde_json::json!({"file": "../../../../../../etc/passwd"})
                }),
            )],
            &render_with("s.json"),
            "outside the session's folder",
        ),
        case(
            "profile names a file that is no shader",
            &[(
                "p.json",
                &profile(&|v| v["shader"]["path"] = "/etc/passwd".into()),
            )],
            &emit_with("p.json"),
            "not a shader file",
        ),
    ]);
    // Work too large for the adapter or the machine: refused before allocating.
    v.extend([
        case(
            "resolution past the largest texture",
            &[(
                "s.json",
                &session(&|v| v["resolution"] = serde_json::json!([40000, 64])),
            )],
            &render_with("s.json"),
            "1..=8192",
        ),
        case(
            "frames past the machine's memory",
            &[(
                "s.json",
                &session(&|v| {
                    v["resolution"] = serde_json::json!([8192, 8192]);
                    v["frames"] = serde_json::json!(400);
                }),
            )],
            &["render", "good.wgsl", "--session", "s.json"],
            "GiB are available",
        ),
    ]);
    // A profile's numbers are data: checked on read, naming the field.
    v.extend([
        case(
            "profile negative original time",
            &[(
                "p.json",
                &profile(&|v| v["original"]["frame_ms"] = (-1.0).into()),
            )],
            &emit_with("p.json"),
            "original.frame_ms",
        ),
        case(
            "profile zero original time",
            &[(
                "p.json",
                &profile(&|v| v["original"]["frame_ms"] = 0.0.into()),
            )],
            &emit_with("p.json"),
            "original.frame_ms",
        ),
        case(
            "profile absurd original time",
            &[(
                "p.json",
                &profile(&|v| v["original"]["frame_ms"] = 1e308.into()),
            )],
            &emit_with("p.json"),
            "original.frame_ms",
        ),
        case(
            "profile negative error",
            &[(
                "p.json",
                &profile(&|v| v["nodes"][0]["measurements"][0]["error"] = (-0.5).into()),
            )],
            &emit_with("p.json"),
            "nodes[0].measurements[0].error",
        ),
        case(
            "profile hit rate above 1",
            &[(
                "p.json",
                &profile(&|v| v["nodes"][0]["measurements"][0]["hit_rate"] = 2.0.into()),
            )],
            &emit_with("p.json"),
            "hit_rate",
        ),
    ]);
    // Silent wrong answers: nothing on screen is an error, not PSNR 100; a variant runs only with
    // its own shader.
    v.extend([
        case(
            "camera up along its view",
            &[(
                "s.json",
                &session(&|v| {
                    v["camera"] = serde_json::json!({"keys": [
                        {"eye": [0, 3, 0], "target": [0, 0, 0], "up": [0, 1, 0]}
                    ]})
                }),
            )],
            &render_with("s.json"),
            "covers no pixel",
        ),
        case(
            "object scaled to nothing",
            &[(
                "s.json",
                &session(&|v| {
                    v["geometry"]["objects"][0]["transform"] =
                        serde_json::json!({"keys": [{"scale": 0.0}]})
                }),
            )],
            &render_with("s.json"),
            "covers no pixel",
        ),
        case(
            "variant of another shader",
            &[("other.wgsl", &shader("    return vec4<f32>(p, 1.0);"))],
            &[
                "render",
                "other.wgsl",
                "--session",
                "good.json",
                "--variant",
                "variant",
                "--max-frames",
                "2",
            ],
            "is a variant of good.wgsl",
        ),
        case(
            "bench a variant of another shader",
            &[("other.wgsl", &shader("    return vec4<f32>(p, 1.0);"))],
            &[
                "bench",
                "other.wgsl",
                "--session",
                "good.json",
                "variant",
                "--max-frames",
                "2",
            ],
            "is a variant of good.wgsl",
        ),
    ]);
    // Unreadable bytes where text belongs.
    v.push(Case {
        name: "shader not UTF-8",
        files: vec![("s.wgsl", vec![0xff, 0xfe, 0x00, 0x41])],
        args: vec!["nodes", "s.wgsl"],
        expect: "s.wgsl",
    });
    v.push(Case {
        name: "session not UTF-8",
        files: vec![("s.json", vec![0xff, 0xfe, 0x00, 0x41])],
        args: render_with("s.json"),
        expect: "s.json",
    });
    v
}

#[test]
fn every_bad_input_exits_2_with_one_clear_message_and_writes_nothing() {
    let base = tempfile::tempdir().unwrap();
    let good = base.path().join("good");
    std::fs::create_dir_all(&good).unwrap();
    let data = root().join("crates/reproj-replay/tests/data");
    std::fs::copy(data.join("tiny.wgsl"), good.join("good.wgsl")).unwrap();
    std::fs::copy(data.join("tiny_moving.json"), good.join("good.json")).unwrap();
    let (code, _, err) = run(
        &good,
        &[
            "analyze",
            "good.wgsl",
            "--session",
            "good.json",
            "--out",
            "good.profile.json",
            "--delta-n",
            "2,4",
            "--holdout",
            "3",
            "--max-nodes",
            "2",
            "--strategy",
            "3pass",
            "--no-charts",
        ],
    );
    assert_eq!(code, 0, "{err}");
    let (code, _, err) = run(
        &good,
        &[
            "instance",
            "good.wgsl",
            "--node",
            "root",
            "--out",
            "variant",
        ],
    );
    assert_eq!(code, 0, "{err}");
    let read = |n: &str| -> serde_json::Value {
        serde_json::from_str(&std::fs::read_to_string(good.join(n)).unwrap()).unwrap()
    };
    let all = cases(&read("good.json"), &read("good.profile.json"));
    assert!(all.len() >= 50, "{} cases", all.len());
    let mut failures = Vec::new();
    for (i, c) in all.iter().enumerate() {
        let dir = base.path().join(format!("case{i}"));
        copy_dir(&good, &dir);
        for (name, bytes) in &c.files {
            let p = dir.join(name);
            std::fs::create_dir_all(p.parent().unwrap()).unwrap();
            std::fs::write(p, bytes).unwrap();
        }
        let before = files(&dir);
        let (code, _, err) = run(&dir, &c.args);
        let after = files(&dir);
        let mut wrong = Vec::new();
        if code != 2 {
            wrong.push(format!("exit {code}"));
        }
        if err.contains("panicked") || err.contains("RUST_BACKTRACE") {
            wrong.push("panic".into());
        }
        if err.contains("root:x:0:0") {
            wrong.push("echoed /etc/passwd".into());
        }
        if !err.contains(c.expect) {
            wrong.push(format!("no `{}` in the message", c.expect));
        }
        let errors = err.lines().filter(|l| l.starts_with("error")).count();
        if errors != 1 {
            wrong.push(format!("{errors} `error` lines"));
        }
        for (name, bytes) in &c.files {
            if std::fs::read(dir.join(name)).ok().as_deref() != Some(bytes.as_slice()) {
                wrong.push(format!("changed {name}"));
            }
        }
        let new: Vec<_> = after.difference(&before).collect();
        if !new.is_empty() {
            wrong.push(format!("wrote {new:?}"));
        }
        if !wrong.is_empty() {
            failures.push(format!("{}: {} — stderr:\n{err}", c.name, wrong.join(", ")));
        }
    }
    assert!(
        failures.is_empty(),
        "{} of {} bad inputs misbehave:\n{}",
        failures.len(),
        all.len(),
        failures.join("\n")
    );
}
