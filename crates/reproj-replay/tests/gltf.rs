//! A glTF 2.0 scene in a session, rendered (needs lavapipe or a GPU): its animated boxes move and
//! the rest holds still (`sessions/gltf_boxes.json`; the import itself: reproj-scene's
//! `tests/gltf.rs`).

use std::path::{Path, PathBuf};

use reproj_replay::{RenderOptions, Renderer, RendererOptions};
use reproj_scene::{Session, SessionError};

fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

/// `sessions/gltf_boxes.json` with `edit` applied to its JSON, loaded as if it were that file
/// (so the glTF path still resolves).
fn edited(edit: impl FnOnce(&mut serde_json::Value)) -> Result<Session, SessionError> {
    let path = root().join("sessions/gltf_boxes.json");
    let mut v: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&path).unwrap()).unwrap();
    edit(&mut v);
    Session::from_json(&v.to_string(), &path, &root().join("sessions"))
}

#[test]
fn the_animated_boxes_move_and_the_rest_holds_still() {
    let r = match Renderer::new(&RendererOptions::default()) {
        Ok(r) => r,
        Err(e) => panic!("{e}"),
    };
    let shader = reproj_front::load_file(&root().join("tests/corpus/shaders/toon.wgsl")).unwrap();
    let entry = shader.fragment_entry(None).unwrap();
    // A light that holds still, so only the glTF animation changes the frames.
    let mut s = edited(|v| {
        v["light"] = serde_json::json!({"keys": [{"frame": 0, "position": [2, 4, 3]}]});
    })
    .unwrap();
    s.resolution = [64, 64];
    let opts = RenderOptions {
        max_frames: Some(41),
        ..Default::default()
    };
    let reference = r.render_original(&shader, entry, &s, &opts).unwrap();
    let (first, last) = (&reference.frames[0], &reference.frames[40]);
    let changed = first
        .chunks_exact(4)
        .zip(last.chunks_exact(4))
        .filter(|(a, b)| a.iter().zip(*b).any(|(p, q)| (p - q).abs() > 1e-3))
        .count();
    assert!(changed > 64 * 64 / 50, "only {changed} pixels changed");
    assert!(
        changed < 64 * 64 / 2,
        "{changed} pixels changed: the camera moved?"
    );
    // Every pixel is covered by the ground or a box at the bottom of the frame.
    let w = 64;
    let bottom_row = &reference.depth[0][(63 * w)..(64 * w)];
    assert!(bottom_row.iter().all(|&d| d < 1.0));
    // The static box (top middle) keeps its pixels.
    let px = |f: &[f32], x: usize, y: usize| f[(y * w + x) * 4..(y * w + x) * 4 + 3].to_vec();
    assert_eq!(px(first, 32, 22), px(last, 32, 22));
}
