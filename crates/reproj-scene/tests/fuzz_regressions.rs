//! Inputs the `obj` fuzz target (fuzz/) found a crash with, kept: each file of
//! `tests/fuzz_regressions/` goes through `mesh::obj_mesh` at the scales the target uses, and
//! must load or be refused with a message naming the file, never panic.

use std::path::Path;

#[test]
fn every_kept_obj_input_loads_or_is_refused() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fuzz_regressions");
    let mut n = 0;
    for e in std::fs::read_dir(&dir).unwrap() {
        let path = e.unwrap().path();
        if path.extension().and_then(|x| x.to_str()) != Some("obj") {
            continue;
        }
        let bytes = std::fs::read(&path).unwrap();
        for scale in [1.0, 1e30] {
            if let Err(e) = reproj_scene::mesh::obj_mesh(Path::new("fuzz.obj"), &bytes, scale) {
                assert!(e.contains("fuzz.obj"), "{}: {e}", path.display());
            }
        }
        n += 1;
    }
    assert!(n > 0, "no .obj file in {}", dir.display());
}

/// An index counting back past the first texture coordinate wrapped in tobj and overflowed (the
/// first crash the `obj` target found); one past the end, and a huge one, are refused too.
#[test]
fn a_face_index_past_the_data_is_refused_naming_line_and_index() {
    let tri = "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 1 1\nvn 0 0 1\n";
    for (face, expect) in [
        (
            "f 1/1 2/-11 3/1",
            "`-11` names no texture coordinate (1 defined",
        ),
        ("f 1 2 4", "`4` names no vertex position (3 defined"),
        ("f 1//1 2//1 3//9223372036854775807", "names no normal"),
        ("l 1 -4", "`-4` names no vertex position"),
    ] {
        let text = format!("{tri}{face}\n");
        let e = reproj_scene::mesh::obj_mesh(Path::new("m.obj"), text.as_bytes(), 1.0).unwrap_err();
        assert!(
            e.starts_with("OBJ m.obj:6: ") && e.contains(expect),
            "{face}: {e}"
        );
    }
    let ok = format!("{tri}f 1/1/1 2/-1/-1 -1/1/1\n");
    reproj_scene::mesh::obj_mesh(Path::new("m.obj"), ok.as_bytes(), 1.0).unwrap();
}
