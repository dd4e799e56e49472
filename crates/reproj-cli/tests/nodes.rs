//! `reproj nodes` through the real binary: snapshots of every sample shader and the error paths.

use std::path::PathBuf;
use std::process::Command;

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../..")
}

fn reproj(args: &[&str]) -> (i32, String, String) {
    let out = Command::new(env!("CARGO_BIN_EXE_reproj"))
        .args(args)
        .current_dir(root())
        .output()
        .expect("run reproj");
    (
        out.status.code().unwrap_or(-1),
        String::from_utf8_lossy(&out.stdout).into_owned(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

fn sample_shaders() -> Vec<String> {
    let mut v: Vec<String> = std::fs::read_dir(root().join("shaders"))
        .unwrap()
        .filter_map(|e| {
            let p = e.unwrap().path();
            (p.extension()? == "wgsl")
                .then(|| p.file_stem().unwrap().to_string_lossy().into_owned())
        })
        .collect();
    v.sort();
    v
}

#[test]
fn json_snapshots_of_every_sample_shader() {
    let shaders = sample_shaders();
    assert!(shaders.len() >= 5, "{shaders:?}");
    for name in shaders {
        let (code, out, err) = reproj(&["nodes", &format!("shaders/{name}.wgsl"), "--json"]);
        assert_eq!(code, 0, "{err}");
        let v: serde_json::Value = serde_json::from_str(&out).unwrap();
        assert_eq!(v["entry"], "fs_main");
        assert!(
            v["nodes"]
                .as_array()
                .unwrap()
                .iter()
                .all(|n| n["cacheable"] == true)
        );
        insta::assert_snapshot!(format!("nodes_{name}"), out);
    }
}

#[test]
fn table_lists_root() {
    let (code, out, _) = reproj(&["nodes", "shaders/marble.wgsl"]);
    assert_eq!(code, 0);
    assert!(
        out.lines()
            .next()
            .unwrap()
            .starts_with("marble.wgsl (fs_main): ")
    );
    assert!(out.contains("[root]"));
}

#[test]
fn all_adds_culled_nodes_with_reasons() {
    let (code, out, _) = reproj(&["nodes", "shaders/ambient_occlusion.wgsl", "--json", "--all"]);
    assert_eq!(code, 0);
    let v: serde_json::Value = serde_json::from_str(&out).unwrap();
    let nodes = v["nodes"].as_array().unwrap();
    let in_loop = nodes.iter().filter(|n| n["reason"] == "in-loop").count();
    assert!(in_loop > 0);
    for n in nodes {
        assert_eq!(n["cacheable"].as_bool().unwrap(), n["reason"].is_null());
    }
}

#[test]
fn invalid_wgsl_shows_naga_diagnostic_and_exits_2() {
    let dir = tempfile::tempdir().unwrap();
    let bad = dir.path().join("bad.wgsl");
    std::fs::write(
        &bad,
        "@fragment\nfn fs_main() -> @location(0) vec4<f32> {\n    return vec4<f32>(1.0, 2.0);\n}\n",
    )
    .unwrap();
    let (code, out, err) = reproj(&["nodes", bad.to_str().unwrap()]);
    assert_eq!(code, 2);
    assert!(out.is_empty());
    assert!(err.contains("bad.wgsl:3:"), "{err}");
    assert!(err.contains('^'), "{err}");
}

#[test]
fn missing_file_exits_2() {
    let (code, _, err) = reproj(&["nodes", "no/such/file.wgsl"]);
    assert_eq!(code, 2);
    assert_eq!(err.lines().count(), 1, "{err}");
    assert!(err.contains("no/such/file.wgsl"));
}

#[test]
fn entry_point_errors_exit_2() {
    let dir = tempfile::tempdir().unwrap();
    let none = dir.path().join("none.wgsl");
    std::fs::write(
        &none,
        "@vertex fn vs() -> @builtin(position) vec4<f32> { return vec4<f32>(0.0); }\n",
    )
    .unwrap();
    let (code, _, err) = reproj(&["nodes", none.to_str().unwrap()]);
    assert_eq!(code, 2);
    assert!(err.contains("no @fragment entry point"), "{err}");

    let two = dir.path().join("two.wgsl");
    std::fs::write(
        &two,
        "@fragment fn a() -> @location(0) vec4<f32> { return vec4<f32>(1.0); }\n\
         @fragment fn b() -> @location(0) vec4<f32> { return vec4<f32>(0.5); }\n",
    )
    .unwrap();
    let (code, _, err) = reproj(&["nodes", two.to_str().unwrap()]);
    assert_eq!(code, 2);
    assert!(err.contains("a, b") && err.contains("--entry"), "{err}");
    let (code, out, _) = reproj(&["nodes", two.to_str().unwrap(), "--entry", "b", "--all"]);
    assert_eq!(code, 0);
    assert!(out.starts_with("two.wgsl (b)"));
    let (code, _, err) = reproj(&["nodes", two.to_str().unwrap(), "--entry", "c"]);
    assert_eq!(code, 2);
    assert!(err.contains("`c`"), "{err}");
}

#[test]
fn unsupported_construct_exits_2_with_location_line_and_caret() {
    let dir = tempfile::tempdir().unwrap();
    // An early return in a helper is normalized away (one exit per function) and accepted.
    let f = dir.path().join("early.wgsl");
    std::fs::write(
        &f,
        "fn g(x: f32) -> f32 {\n    if x > 0.0 { return 1.0; }\n    return x;\n}\n\
         @fragment fn fs(@location(0) p: vec3<f32>) -> @location(0) vec4<f32> { return vec4<f32>(g(p.x)); }\n",
    )
    .unwrap();
    let (code, _, err) = reproj(&["nodes", f.to_str().unwrap()]);
    assert_eq!(code, 0, "{err}");
    // An output struct filled inside a branch is built member by member and accepted.
    let f = dir.path().join("branchy.wgsl");
    std::fs::write(
        &f,
        "struct O {\n    @location(0) c: vec4<f32>,\n};\n\
         @fragment fn fs(@location(0) p: vec3<f32>) -> O {\n    var o: O;\n\
         \x20   if p.x > 0.0 { o.c = vec4<f32>(1.0); return o; }\n\
         \x20   o.c = vec4<f32>(p, 1.0);\n    return o;\n}\n",
    )
    .unwrap();
    let (code, _, err) = reproj(&["nodes", f.to_str().unwrap()]);
    assert_eq!(code, 0, "{err}");
    // An integer output color is refused, at the value written.
    let f = dir.path().join("int.wgsl");
    std::fs::write(
        &f,
        "struct O {\n    @location(0) c: vec4<i32>,\n};\n\
         @fragment fn fs(@location(0) p: vec3<f32>) -> O {\n    var o: O;\n\
         \x20   o.c = vec4<i32>(vec3<i32>(p * 4.0), 1);\n    return o;\n}\n",
    )
    .unwrap();
    let (code, _, err) = reproj(&["nodes", f.to_str().unwrap()]);
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("int.wgsl:6:11"), "{err}");
    // The source line and a caret under the construct, as for parse errors.
    assert!(
        err.contains("6 │     o.c = vec4<i32>(vec3<i32>(p * 4.0), 1);"),
        "{err}"
    );
    assert!(err.contains("^^^^^^^^^^^^^^^^"), "{err}");
}

fn json_nodes(shader: &str, all: bool) -> Vec<serde_json::Value> {
    let mut args = vec!["nodes", shader, "--json"];
    if all {
        args.push("--all");
    }
    let (code, out, err) = reproj(&args);
    assert_eq!(code, 0, "{err}");
    let v: serde_json::Value = serde_json::from_str(&out).unwrap();
    v["nodes"].as_array().unwrap().clone()
}

#[test]
fn marble_octaves_and_partial_sums_are_separate_cacheable_nodes() {
    let nodes = json_nodes("shaders/marble.wgsl", false);
    let texts: Vec<&str> = nodes.iter().map(|n| n["text"].as_str().unwrap()).collect();
    for want in [
        "n0 + n1",
        "s1 + n2",
        "s2 + n3",
        "s3 + n4",
        "abs(gradient_noise(p))",
    ] {
        assert!(texts.contains(&want), "`{want}` is not a cacheable node");
    }
    // Five octaves, each `abs(gradient_noise(...))`, all cacheable.
    assert_eq!(
        texts
            .iter()
            .filter(|t| t.starts_with("abs(gradient_noise(") && t.ends_with("))"))
            .count(),
        5
    );
}

#[test]
fn ambient_occlusion_loop_bodies_are_culled_and_post_loop_sums_cacheable() {
    let nodes = json_nodes("shaders/ambient_occlusion.wgsl", true);
    // The sums read after their loops are cacheable, while the same variable read inside its loop
    // is not.
    for var in ["static_ao", "moving_ao"] {
        let reads: Vec<&serde_json::Value> = nodes.iter().filter(|n| n["text"] == var).collect();
        assert!(
            reads.iter().any(|n| n["cacheable"] == true),
            "the value of `{var}` after its loop should be cacheable"
        );
        assert!(
            reads.iter().any(|n| n["reason"] == "in-loop"),
            "`{var}` inside its loop should be in-loop"
        );
    }
}

#[test]
fn instance_errors_exit_2_and_write_nothing() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("v");
    let o = out.to_str().unwrap();
    let (code, _, err) = reproj(&[
        "instance",
        "shaders/marble.wgsl",
        "--node",
        "999999",
        "--out",
        o,
    ]);
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("no node 999999"), "{err}");
    let culled = json_nodes("shaders/marble.wgsl", true)
        .into_iter()
        .find(|n| n["cacheable"] == false)
        .unwrap();
    let id = culled["id"].to_string();
    let (code, _, err) = reproj(&["instance", "shaders/marble.wgsl", "--node", &id, "--out", o]);
    assert_eq!(code, 2);
    assert!(err.contains("culled as"), "{err}");
    let (code, _, err) = reproj(&[
        "instance",
        "shaders/marble.wgsl",
        "--node",
        "seven",
        "--out",
        o,
    ]);
    assert_eq!(code, 2);
    assert!(err.contains("not a node id"), "{err}");
    assert!(!out.exists(), "nothing is written on error");
    // An output path under a file cannot be created.
    let file = dir.path().join("file");
    std::fs::write(&file, "x").unwrap();
    let (code, _, err) = reproj(&[
        "instance",
        "shaders/marble.wgsl",
        "--node",
        "root",
        "--out",
        file.join("v").to_str().unwrap(),
    ]);
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("cannot write"), "{err}");
    // And a good run writes the four files.
    let (code, stdout, err) = reproj(&[
        "instance",
        "shaders/marble.wgsl",
        "--node",
        "root",
        "--out",
        o,
    ]);
    assert_eq!(code, 0, "{err}");
    assert!(stdout.contains("pass1_reproject.wgsl"));
    assert!(out.join("manifest.json").exists());
}

#[test]
fn emit_without_profile_explains_what_to_do() {
    let dir = tempfile::tempdir().unwrap();
    let out = Command::new(env!("CARGO_BIN_EXE_reproj"))
        .args(["emit", "--max-error", "0.01"])
        .current_dir(dir.path())
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(2));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("reproj analyze"), "{err}");
}

#[test]
fn bad_session_names_the_field() {
    let dir = tempfile::tempdir().unwrap();
    let s = dir.path().join("s.json");
    let mut v: serde_json::Value = serde_json::from_str(
        &std::fs::read_to_string(root().join("sessions/test_static.json")).unwrap(),
    )
    .unwrap();
    v["resolution"] = serde_json::json!([64, "wide"]);
    std::fs::write(&s, serde_json::to_vec(&v).unwrap()).unwrap();
    let (code, _, err) = reproj(&[
        "render",
        "shaders/marble.wgsl",
        "--session",
        s.to_str().unwrap(),
    ]);
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("resolution"), "{err}");
}

/// GLSL input by extension: marble's GLSL twin (through glslang) has about as many nodes as the
/// WGSL one.
#[test]
fn glsl_marble_nodes() {
    let count = |shader: &str| {
        let (code, out, err) = reproj(&["nodes", shader, "--json"]);
        assert_eq!(code, 0, "{err}");
        let v: serde_json::Value = serde_json::from_str(&out).unwrap();
        v["nodes"].as_array().unwrap().len() as f64
    };
    let (w, g) = (
        count("shaders/marble.wgsl"),
        count("shaders/glsl/marble.frag"),
    );
    // glslang's SPIR-V spells a few values in more steps than naga's WGSL.
    assert!(g >= w && g <= 1.1 * w, "GLSL {g}, WGSL {w}");
    // `--lang-in` reads a file whatever its extension.
    let dir = tempfile::tempdir().unwrap();
    let renamed = dir.path().join("marble.txt");
    std::fs::copy(root().join("shaders/glsl/marble.frag"), &renamed).unwrap();
    let renamed = renamed.to_str().unwrap();
    let (code, out, err) = reproj(&["nodes", renamed, "--lang-in", "glsl"]);
    assert_eq!(code, 0, "{err}");
    assert!(out.contains("411 cacheable"), "{out}");
}

/// A shader with no cacheable node says why, one line per reason, and exits 0.
#[test]
fn no_cacheable_node_says_why() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("flat.wgsl");
    std::fs::write(
        &path,
        "@fragment fn fs(@location(0) p: vec3<f32>) -> @location(0) vec4<f32> {\n\
         \x20   if length(sin(p * 9.0)) > 0.5 { discard; }\n\
         \x20   return vec4<f32>(p, 1.0);\n}\n",
    )
    .unwrap();
    let (code, out, err) = reproj(&["nodes", path.to_str().unwrap()]);
    assert_eq!(code, 0, "{err}");
    let lines: Vec<&str> = out.lines().collect();
    assert!(lines[0].contains("no cacheable node"), "{out}");
    assert!(lines.contains(&"  discontinuous: 3"), "{out}");
    assert!(lines.iter().any(|l| l.starts_with("  trivial: ")), "{out}");
    assert!(lines.iter().any(|l| l.starts_with("hint: ")), "{out}");
}

/// `analyze` on a shader with nothing worth caching writes no profile and says so (before any
/// GPU work); the `emit` a user runs next says why there is none.
#[test]
fn nothing_to_cache_analyze_then_emit_say_why() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("flat.wgsl");
    std::fs::write(
        &path,
        "@fragment fn fs(@location(0) p: vec3<f32>) -> @location(0) vec4<f32> {\n\
         \x20   return vec4<f32>(p, 1.0);\n}\n",
    )
    .unwrap();
    let session = root().join("sessions/marble.json");
    let run = |args: &[&str]| {
        let out = Command::new(env!("CARGO_BIN_EXE_reproj"))
            .args(args)
            .current_dir(dir.path())
            .output()
            .expect("run reproj");
        (
            out.status.code().unwrap_or(-1),
            String::from_utf8_lossy(&out.stdout).into_owned(),
            String::from_utf8_lossy(&out.stderr).into_owned(),
        )
    };
    let (code, out, err) = run(&[
        "analyze",
        "flat.wgsl",
        "--session",
        session.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{err}");
    assert!(out.contains("no cacheable node"), "{out}");
    assert!(
        out.contains("no profile written: keep the original shader"),
        "{out}"
    );
    assert!(!dir.path().join("flat.profile.json").exists());
    let (code, out, err) = run(&["emit", "--max-error", "0.01"]);
    assert_eq!(code, 2, "{out}{err}");
    assert!(
        err.contains("nothing worth caching") && err.contains("reproj nodes"),
        "{err}"
    );
}

/// A GLSL shader whose output cannot be traced to the entry's return: exit 2, one message.
#[test]
fn untraceable_glsl_output_exits_2() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("unwritten.frag");
    std::fs::write(
        &path,
        "#version 450\nlayout(location = 0) in vec3 p;\nlayout(location = 0) out vec4 c;\n\
         void main() {\n    vec3 unused = sin(p);\n}\n",
    )
    .unwrap();
    let (code, out, err) = reproj(&["nodes", path.to_str().unwrap()]);
    assert_eq!(code, 2, "{out}{err}");
    assert!(
        err.contains("unwritten.frag") && err.contains("never written"),
        "{err}"
    );
    assert!(out.is_empty(), "{out}");
}

/// `instance --lang`: the passes in GLSL, HLSL, MSL and SPIR-V beside the WGSL, from a GLSL input.
#[test]
fn instance_writes_other_languages() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("v");
    let (code, stdout, err) = reproj(&[
        "instance",
        "shaders/glsl/marble.frag",
        "--node",
        "root",
        "--strategy",
        "2pass",
        "--lang",
        "glsl,hlsl,msl,spv",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{err}");
    for stem in ["pass1_shade_hits", "pass2_shade_misses"] {
        for ext in ["wgsl", "frag", "hlsl", "metal", "spv"] {
            let f = out.join(format!("{stem}.{ext}"));
            assert!(f.is_file(), "{} missing; {stdout}", f.display());
        }
    }
}

/// Vulkan GLSL with combined image samplers (`sampler2D`, read through glslang): `nodes` lists
/// nodes at their GLSL lines and columns, and `nodes --json` names the image and sampler bindings
/// it split.
#[test]
fn glsl_with_combined_samplers_nodes() {
    let shader = "tests/corpus/shaders/glsl/normal_map.frag";
    let (code, out, err) = reproj(&["nodes", shader]);
    assert_eq!(code, 0, "{err}");
    // `vec3 color = texture(samplerColor, inUV).rgb` is line 31 of the file: the read and its
    // swizzle at column 18, each with its own text.
    for text in [
        "texture(samplerColor, inUV)",
        "texture(samplerColor, inUV).rgb",
    ] {
        assert!(
            out.lines()
                .any(|l| l.contains(" 31:18 ") && l.trim_end().ends_with(&format!(" {text}"))),
            "{out}"
        );
    }
    let (code, out, err) = reproj(&["nodes", shader, "--json"]);
    assert_eq!(code, 0, "{err}");
    let v: serde_json::Value = serde_json::from_str(&out).unwrap();
    assert!(!v["nodes"].as_array().unwrap().is_empty(), "{out}");
}

/// `override` constants: every `--lang` output is written with the defaults, or with the values
/// `--override` gives.
#[test]
fn instance_resolves_override_constants_for_other_languages() {
    let dir = tempfile::tempdir().unwrap();
    let shader = dir.path().join("o.wgsl");
    std::fs::write(
        &shader,
        "override gain: f32 = 1.0;\n@id(7) override bias: f32;\n@fragment\nfn fs_main(@location(0) p: vec3<f32>) -> @location(0) vec4<f32> {\n    return vec4<f32>(sin(p * 7.0) * gain + bias, 1.0);\n}\n",
    )
    .unwrap();
    let out = dir.path().join("v");
    let run = |extra: &[&str]| {
        let mut args = vec![
            "instance",
            shader.to_str().unwrap(),
            "--node",
            "root",
            "--lang",
            "glsl,hlsl,msl,spv",
            "--out",
            out.to_str().unwrap(),
        ];
        args.extend_from_slice(extra);
        reproj(&args)
    };
    // `bias` has no default: without a value the backends cannot write it.
    let (code, _, err) = run(&[]);
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("`bias` (@id(7)) has no default"), "{err}");
    let (code, _, err) = run(&["--override", "7=0.25", "--override", "gain=2"]);
    assert_eq!(code, 0, "{err}");
    // The pass that computes the root holds the values as constants.
    let glsl = std::fs::read_to_string(out.join("pass2_recompute.frag")).unwrap();
    assert!(
        glsl.contains("const float gain = 2.0;") && glsl.contains("const float bias = 0.25;"),
        "{glsl}"
    );
}

/// Without glslang, naga's GLSL front end reads the file and its error says what needs glslang.
#[test]
fn glsl_without_glslang_names_what_needs_it() {
    let out = Command::new(env!("CARGO_BIN_EXE_reproj"))
        .args(["nodes", "tests/corpus/shaders/glsl/normal_map.frag"])
        .env("REPROJ_GLSLANG", "/nonexistent/glslangValidator")
        .current_dir(root())
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{err}");
    assert!(
        err.contains("combined image samplers (sampler2D, samplerCube, ...)")
            && err.contains("need glslang"),
        "{err}"
    );
}
