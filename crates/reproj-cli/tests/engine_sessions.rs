//! Engine-like sessions through the real binary: the four corpus shaders that need nested uniform
//! structs, texture arrays, storage buffers, depth passes and comparison samplers render, and what
//! the session gives for each construct reaches the image (changing it changes the frames).

use std::path::{Path, PathBuf};

use serde_json::Value;

use crate::common::{root, run};

fn session_json(name: &str) -> Value {
    let p = root().join(format!("tests/corpus/sessions/{name}.json"));
    serde_json::from_str(&std::fs::read_to_string(p).unwrap()).unwrap()
}

/// Render the original of corpus shader `name` over `session` (written beside the corpus
/// session, so relative paths hold) for two frames; the PNG frames' bytes.
fn frames(name: &str, session: &Value, tmp: &Path, tag: &str) -> Vec<Vec<u8>> {
    let file = tmp.join(format!("{name}-{tag}.json"));
    std::fs::write(&file, session.to_string()).unwrap();
    let out = tmp.join(format!("frames-{name}-{tag}"));
    let shader = root().join(format!("tests/corpus/shaders/{name}.wgsl"));
    let (code, _, err) = run(
        tmp,
        &[
            "render",
            shader.to_str().unwrap(),
            "--session",
            file.to_str().unwrap(),
            "--max-frames",
            "2",
            "--frames",
            out.to_str().unwrap(),
        ],
    );
    assert_eq!(code, 0, "{name} ({tag}): {err}");
    let mut files: Vec<PathBuf> = std::fs::read_dir(&out)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "png"))
        .collect();
    files.sort();
    assert_eq!(files.len(), 2, "{name} ({tag}): {files:?}");
    files.iter().map(|f| std::fs::read(f).unwrap()).collect()
}

/// The frames of `name` with its session as committed differ from those with `change` applied.
fn check_reaches_the_image(name: &str, change: impl FnOnce(&mut Value)) {
    let tmp = tempfile::tempdir().unwrap();
    let s = session_json(name);
    let base = frames(name, &s, tmp.path(), "base");
    let mut changed = s.clone();
    change(&mut changed);
    let other = frames(name, &changed, tmp.path(), "changed");
    assert_ne!(base, other, "{name}: the change does not reach the frames");
}

#[test]
fn nested_uniform_structs_reach_the_shader() {
    check_reaches_the_image("height_fog", |s| {
        s["uniforms"]["sun"]["color"] = serde_json::json!([0.2, 0.3, 1.0]);
    });
}

#[test]
fn texture_array_layers_reach_the_shader() {
    check_reaches_the_image("terrain_splat", |s| {
        s["textures"]["layer_albedo"]["layers"][1] =
            serde_json::json!({"kind": "solid", "size": 128, "params": {"color": [1, 0, 0, 1]}});
    });
}

#[test]
fn the_shadow_pass_casts_shadows() {
    // Drawing the shadow map from a view that sees nothing leaves every pixel lit.
    check_reaches_the_image("shadow_pcf", |s| {
        s["depth_passes"]["shadow_map"]["view_proj"] = serde_json::json!({"matrix": [
            1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 100, 100, 0, 1]});
    });
}

#[test]
fn storage_buffer_lights_and_the_depth_pre_pass_reach_the_shader() {
    check_reaches_the_image("deferred_lighting", |s| {
        s["buffers"]["lights_buffer"]["count"] = serde_json::json!(1);
    });
}

#[test]
fn a_variant_renders_over_a_shadow_pass_and_a_storage_buffer() {
    let tmp = tempfile::tempdir().unwrap();
    for name in ["shadow_pcf", "deferred_lighting"] {
        let shader = root().join(format!("tests/corpus/shaders/{name}.wgsl"));
        let session = root().join(format!("tests/corpus/sessions/{name}.json"));
        let (code, out, err) = run(
            tmp.path(),
            &[
                "render",
                shader.to_str().unwrap(),
                "--session",
                session.to_str().unwrap(),
                "--node",
                "root",
                "--delta-n",
                "4",
                "--max-frames",
                "4",
                "--json",
            ],
        );
        assert_eq!(code, 0, "{name}: {err}");
        let report: Value = serde_json::from_str(&out).expect("render --json");
        let hit = report["hit_rate"].as_f64().unwrap();
        assert!(hit > 0.0 && hit < 1.0, "{name}: hit rate {hit}");
    }
}

#[test]
fn a_missing_depth_pass_is_named() {
    let tmp = tempfile::tempdir().unwrap();
    let mut s = session_json("shadow_pcf");
    s.as_object_mut().unwrap().remove("depth_passes");
    let file = tmp.path().join("s.json");
    std::fs::write(&file, s.to_string()).unwrap();
    let shader = root().join("tests/corpus/shaders/shadow_pcf.wgsl");
    let (code, _, err) = run(
        tmp.path(),
        &[
            "render",
            shader.to_str().unwrap(),
            "--session",
            file.to_str().unwrap(),
            "--max-frames",
            "1",
        ],
    );
    assert_eq!(code, 2, "{err}");
    assert!(
        err.contains("depth texture `shadow_map` (in `depth_passes`)"),
        "{err}"
    );
}
