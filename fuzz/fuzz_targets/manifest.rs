//! Arbitrary text as a variant's `manifest.json`: the versioned-JSON reader into
//! `reproj_instance::Manifest` (what `render --variant` and `bench` read), every pass file
//! resolved as `VariantInput::from_dir` resolves it (inside the variant's folder, an empty
//! temporary one; a path leaving it is refused), the run-time Δn schedule at a few motions, and
//! a write → read round trip that must give the same manifest.
#![no_main]

use std::path::{Path, PathBuf};
use std::sync::OnceLock;

use libfuzzer_sys::fuzz_target;
use reproj_instance::{MANIFEST_KIND, Manifest};

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
    let manifest: Manifest = match reproj_io::parse_json(text, Path::new("manifest.json"), &MANIFEST_KIND) {
        Ok(m) => m,
        Err(e) => {
            let _ = e.to_string();
            return;
        }
    };
    for p in &manifest.passes {
        if let Ok(full) =
            reproj_scene::session::resolve_inside(base_dir(), Path::new(&p.file), "manifest")
        {
            assert!(full.starts_with(base_dir()), "{} left the folder", full.display());
        }
    }
    for motion in [0.0, 0.5, 1.0, 7.0, 1e9, f64::INFINITY, f64::NAN, -1.0] {
        let _ = manifest.params.delta_n_for(motion);
    }
    let written = serde_json::to_string(&manifest).expect("a manifest serializes");
    let again: Manifest = serde_json::from_str(&written).expect("a written manifest reads back");
    assert_eq!(again, manifest, "the round trip changed the manifest");
});
