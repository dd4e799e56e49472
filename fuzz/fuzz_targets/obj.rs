//! Arbitrary bytes as an OBJ mesh: `reproj_scene::mesh::obj_mesh` (the finite-number check,
//! tobj's reader with triangulation and one index per vertex, index checks, smooth normals,
//! tangents), at scale 1 and at a scale that takes large coordinates past the f32 range.
#![no_main]

use std::path::Path;

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    for scale in [1.0, 1e30] {
        match reproj_scene::mesh::obj_mesh(Path::new("fuzz.obj"), data, scale) {
            Ok(mesh) => {
                assert!(!mesh.indices.is_empty());
                assert!(mesh.indices.iter().all(|&i| (i as usize) < mesh.vertices.len()));
            }
            Err(e) => assert!(e.contains("fuzz.obj"), "the message names the file: {e}"),
        }
    }
});
