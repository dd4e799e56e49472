//! Arbitrary text as a session (`reproj.session` JSON): the versioned-JSON reader, glTF expansion,
//! key sorting and validation (`Session::from_json`), then what reproj-scene computes from a session
//! without a GPU: the scene's state (camera, light, object transforms, depth passes' matrices) at
//! a few frames, and every uniform's value there. Relative paths resolve against an empty
//! temporary folder and paths leaving it are refused (the default), so a file a session names
//! (OBJ, glTF, image) is never found. Errors are fine; a panic is a bug (build with
//! `--features session`: reproj-scene pulls in glTF and image decoding).
#![no_main]

use std::path::{Path, PathBuf};
use std::sync::OnceLock;

use libfuzzer_sys::fuzz_target;
use reproj_scene::Session;

fn base_dir() -> &'static Path {
    static DIR: OnceLock<(tempfile::TempDir, PathBuf)> = OnceLock::new();
    &DIR.get_or_init(|| {
        let dir = tempfile::tempdir().expect("a temporary folder");
        let path = dir.path().to_owned();
        (dir, path)
    })
    .1
}

fuzz_target!(|data: &[u8]| {
    let Ok(text) = std::str::from_utf8(data) else {
        return;
    };
    let session = match Session::from_json(text, Path::new("s.json"), base_dir()) {
        Ok(s) => s,
        Err(e) => {
            let _ = e.to_string();
            return;
        }
    };
    let _ = session.display_name();
    let _ = session.aspect();
    let last = session.frames.saturating_sub(1);
    for frame in [0, 1, last / 2, last, session.frames, u32::MAX] {
        let state = session.frame_state(frame);
        for pass in session.depth_passes.values() {
            let _ = session.depth_view_proj(pass, &state);
        }
        for value in session.uniforms.values().chain(session.buffers.values()) {
            let _ = value.at(frame as f32);
        }
    }
    // Uniform paths as the replay looks them up (`light.color`, `lights[1].position`).
    for name in session.uniforms.keys() {
        let _ = session.uniform(name);
        let _ = session.uniform(&format!("{name}.x[1]"));
    }
});
