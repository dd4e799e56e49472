//! `reproj session init`: a starting session for a shader that `reproj render`
//! runs at once, for every shader of the test bed; an existing file is not replaced without
//! `--force`; what the replay cannot provide is refused with exit 2 and nothing written.

use crate::common::{root, run};

#[test]
fn every_test_bed_shader_renders_with_its_starting_session() {
    let tmp = tempfile::tempdir().unwrap();
    let shaders: Vec<_> = std::fs::read_dir(root().join("shaders"))
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "wgsl"))
        .collect();
    assert!(shaders.len() >= 6, "{shaders:?}");
    for shader in &shaders {
        let name = shader.file_stem().unwrap().to_string_lossy().into_owned();
        let session = tmp.path().join(format!("{name}.json"));
        let (s, o) = (shader.to_str().unwrap(), session.to_str().unwrap());
        let (code, _, err) = run(
            &root(),
            &["session", "init", s, "--out", o, "--frames", "2"],
        );
        assert_eq!(code, 0, "{name}: {err}");
        assert!(err.contains(&format!("next: reproj render {s}")), "{err}");
        let (code, out, err) = run(&root(), &["render", s, "--session", o, "--json"]);
        assert_eq!(code, 0, "{name}: {err}");
        let report: serde_json::Value = serde_json::from_str(&out).unwrap();
        assert_eq!(report["frames"].as_array().unwrap().len(), 2, "{name}");
        // Something was drawn: the torus covers pixels in every frame.
        assert!(
            report["frames"]
                .as_array()
                .unwrap()
                .iter()
                .all(|f| f["covered"].as_u64().unwrap() > 1000),
            "{name}: {out}"
        );
    }
}

#[test]
fn the_guesses_are_listed_and_the_automatic_fields_left_out() {
    // marble: `shininess`, `light_color`, `noise_scale` are the session's; `camera_pos`, `time`
    // and `light_pos` the scene fills.
    let (code, out, err) = run(&root(), &["session", "init", "shaders/marble.wgsl"]);
    assert_eq!(code, 0, "{err}");
    let session: serde_json::Value = serde_json::from_str(&out).unwrap();
    let uniforms = session["uniforms"].as_object().unwrap();
    let mut names: Vec<&str> = uniforms.keys().map(String::as_str).collect();
    names.sort_unstable();
    assert_eq!(names, ["light_color", "noise_scale", "shininess"]);
    assert_eq!(session["schema"], "reproj.session");
    for name in names {
        assert!(err.contains(&format!("uniforms.{name} = ")), "{err}");
    }
}

#[test]
fn an_existing_file_stays_without_force_and_unsupported_bindings_are_refused() {
    let tmp = tempfile::tempdir().unwrap();
    let out = tmp.path().join("s.json");
    std::fs::write(&out, "mine").unwrap();
    let o = out.to_str().unwrap();
    let (code, _, err) = run(
        &root(),
        &["session", "init", "shaders/marble.wgsl", "--out", o],
    );
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("--force"), "{err}");
    assert_eq!(std::fs::read_to_string(&out).unwrap(), "mine");
    let (code, _, err) = run(
        &root(),
        &[
            "session",
            "init",
            "shaders/marble.wgsl",
            "--out",
            o,
            "--force",
        ],
    );
    assert_eq!(code, 0, "{err}");
    assert!(
        std::fs::read_to_string(&out)
            .unwrap()
            .contains("reproj.session")
    );
    // A read-write storage buffer: the replay cannot provide it.
    let shader = tmp.path().join("rw.wgsl");
    std::fs::write(
        &shader,
        "@group(0) @binding(0) var<storage, read_write> counts: array<u32>;\n\
         @fragment fn main(@location(0) p: vec3<f32>) -> @location(0) vec4<f32> {\n\
             counts[0] = 1u;\n    return vec4<f32>(p, 1.0);\n}\n",
    )
    .unwrap();
    let target = tmp.path().join("rw.json");
    let (code, _, err) = run(
        tmp.path(),
        &[
            "session",
            "init",
            "rw.wgsl",
            "--out",
            target.to_str().unwrap(),
        ],
    );
    assert_eq!(code, 2, "{err}");
    assert!(
        err.contains("`counts`") && err.contains("cannot provide"),
        "{err}"
    );
    assert!(!target.exists());
}

/// Write `source` as `file` in a fresh folder, give it a starting session, and check that
/// `session init` says `said` and that the original and a 2pass variant of the root render.
fn starts_and_renders(file: &str, source: &str, said: &str) {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    std::fs::write(dir.join(file), source).unwrap();
    let (code, _, err) = run(dir, &["session", "init", file, "-o", "s.json"]);
    assert_eq!(code, 0, "{err}");
    assert!(err.contains(said), "{err}");
    for extra in [&[][..], &["--node", "root", "--strategy", "2pass"][..]] {
        let render = [
            "render",
            file,
            "--session",
            "s.json",
            "--max-frames",
            "3",
            "-q",
        ];
        let (code, _, err) = run(dir, &[&render[..], extra].concat());
        assert_eq!(code, 0, "{extra:?}: {err}");
    }
}

/// A shader whose text leaves its resources' bindings to the host (Blade binds by name) or its
/// integer varyings' `flat` to an older naga is filled in when read (a warning names each binding
/// chosen), and a device gets the filled-in module, not the text: its starting session renders,
/// original and variant, where wgpu refused the text itself (exit 1).
#[test]
fn a_shader_without_bindings_renders_with_the_bindings_it_was_read_with() {
    starts_and_renders(
        "blit.wgsl",
        "struct Params { tint: vec4<f32> }
var<uniform> params: Params;
var input: texture_2d<f32>;
var samp: sampler;
@fragment
fn fs(@location(0) normal: vec3<f32>, @location(2) uv: vec2<f32>) -> @location(0) vec4<f32> {
    let lit = max(dot(normalize(normal), vec3(0.0, 0.0, 1.0)), 0.1);
    return textureSample(input, samp, uv) * params.tint * lit;
}
",
        "`input` in blit.wgsl has no @group/@binding (its host binds it by name)",
    );
}

/// An integer fragment input (Bevy's `instance_index`, a texture-array index: flat) takes no
/// vertex attribute: `session init` says it is fed 0, and the original and a variant render.
#[test]
fn an_integer_input_is_fed_zero_and_renders() {
    starts_and_renders(
        "instanced.wgsl",
        "struct Mesh { tint: vec4<f32> }
@group(1) @binding(0) var<storage, read> meshes: array<Mesh>;
struct VertexOutput {
    @builtin(position) position: vec4<f32>,
    @location(1) world_normal: vec3<f32>,
    @location(6) @interpolate(flat) instance_index: u32,
}
@fragment
fn fragment(in: VertexOutput) -> @location(0) vec4<f32> {
    let lit = max(dot(normalize(in.world_normal), vec3(0.0, 0.0, 1.0)), 0.1);
    return meshes[in.instance_index].tint * lit;
}
",
        "`instance_index` (u32) is an integer input, fed 0",
    );
}
