//! A glTF 2.0 scene through the real binary (`sessions/gltf_boxes.json`): `render` draws the
//! file's animated boxes through its camera, `analyze` profiles the toon shader over it, and a
//! session naming a glTF file that is not there exits 2 naming the field and the file.

use serde_json::Value;

use crate::common::{root, run};

#[test]
fn a_gltf_session_renders_and_analyzes() {
    let tmp = tempfile::tempdir().unwrap();
    let shader = root().join("tests/corpus/shaders/toon.wgsl");
    let session = root().join("sessions/gltf_boxes.json");
    let frames = tmp.path().join("frames");
    let (code, out, err) = run(
        tmp.path(),
        &[
            "render",
            shader.to_str().unwrap(),
            "--session",
            session.to_str().unwrap(),
            "--max-frames",
            "24",
            "--frames",
            frames.to_str().unwrap(),
        ],
    );
    assert_eq!(code, 0, "{out}{err}");
    let first = std::fs::read(frames.join("frame_000.png")).unwrap();
    let later = std::fs::read(frames.join("frame_023.png")).unwrap();
    assert_ne!(first, later, "the file's animation moves the boxes");

    let profile = tmp.path().join("toon.profile.json");
    let (code, out, err) = run(
        tmp.path(),
        &[
            "analyze",
            shader.to_str().unwrap(),
            "--session",
            session.to_str().unwrap(),
            "--max-frames",
            "16",
            "--max-nodes",
            "2",
            "--delta-n",
            "2,4,6",
            "--holdout",
            "3",
            "--probe-frames",
            "8",
            "--no-charts",
            "--out",
            profile.to_str().unwrap(),
        ],
    );
    assert_eq!(code, 0, "{out}{err}");
    let p: Value = serde_json::from_str(&std::fs::read_to_string(&profile).unwrap()).unwrap();
    let mu = p["hit_rate"]["mu"].as_f64().unwrap();
    assert!(
        mu > 0.5 && mu < 1.0,
        "moving boxes lose some cached pixels each frame: µ = {mu}"
    );
    assert!(!p["nodes"].as_array().unwrap().is_empty());
}

#[test]
fn a_missing_gltf_file_is_a_user_error_naming_the_field() {
    let tmp = tempfile::tempdir().unwrap();
    let mut s: Value = serde_json::from_str(
        &std::fs::read_to_string(root().join("sessions/gltf_boxes.json")).unwrap(),
    )
    .unwrap();
    s["gltf"]["path"] = "missing/scene.gltf".into();
    let file = tmp.path().join("s.json");
    std::fs::write(&file, s.to_string()).unwrap();
    let shader = root().join("tests/corpus/shaders/toon.wgsl");
    let (code, _, err) = run(
        tmp.path(),
        &[
            "render",
            shader.to_str().unwrap(),
            "--session",
            file.to_str().unwrap(),
            "--max-frames",
            "2",
        ],
    );
    assert_eq!(code, 2, "{err}");
    assert!(
        err.contains("gltf.path") && err.contains("scene.gltf"),
        "{err}"
    );
    assert!(!err.contains("panicked"), "{err}");
}
