//! glTF 2.0 scenes in sessions (`sessions/gltf_boxes.json`, whose file `sessions/gltf/boxes.gltf`
//! `scripts/make-gltf-boxes.py` writes): the import into objects, transform keys and camera keys,
//! the material texture, and the errors (the rendering: reproj-replay's `tests/gltf.rs`).

use std::path::{Path, PathBuf};

use glam::Vec3;
use reproj_scene::reflect::TexDim;
use reproj_scene::session::{CameraPath, Mesh, TexFormat};
use reproj_scene::{Session, SessionError, textures};

fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

fn boxes() -> Session {
    Session::load(root().join("sessions/gltf_boxes.json")).unwrap()
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

fn object<'a>(s: &'a Session, name: &str) -> &'a reproj_scene::session::Object {
    s.geometry
        .objects
        .iter()
        .find(|o| o.name.as_deref() == Some(name))
        .unwrap_or_else(|| panic!("no object {name}"))
}

#[test]
fn a_gltf_scene_becomes_objects_with_keys_and_a_camera() {
    let s = boxes();
    let names: Vec<_> = s
        .geometry
        .objects
        .iter()
        .map(|o| o.name.clone().unwrap())
        .collect();
    assert_eq!(names, ["ground/0", "spinner/0", "slider/0", "static/0"]);
    for o in &s.geometry.objects {
        assert!(matches!(&o.mesh, Mesh::Gltf { path, .. } if path.ends_with("boxes.gltf")));
    }
    // Static nodes get one key, animated ones one per frame.
    assert_eq!(object(&s, "ground/0").transform.keys.len(), 1);
    assert_eq!(object(&s, "static/0").transform.keys.len(), 1);
    assert_eq!(object(&s, "spinner/0").transform.keys.len(), 48);
    assert_eq!(object(&s, "slider/0").transform.keys.len(), 48);

    // The slider sits in its group (translation [1.2, 0, 0]): its own translation goes from
    // [0, 0.3, -1.2] to [0, 0.3, 1.2] over 1.6 s (LINEAR); its scale steps 0.6 → 0.9 at 0.8 s.
    let slider = s
        .geometry
        .objects
        .iter()
        .position(|o| o.name.as_deref() == Some("slider/0"))
        .unwrap();
    let at = |frame: u32| s.frame_state(frame).models[slider];
    let origin = |frame: u32| at(frame).transform_point3(Vec3::ZERO);
    assert!(
        origin(0).abs_diff_eq(Vec3::new(1.2, 0.3, -1.2), 1e-5),
        "{}",
        origin(0)
    );
    let t = 30.0 / 30.0 / 1.6;
    let z = -1.2 + 2.4 * t;
    assert!(
        origin(30).abs_diff_eq(Vec3::new(1.2, 0.3, z), 1e-4),
        "{}",
        origin(30)
    );
    let scale = |frame: u32| at(frame).transform_vector3(Vec3::X).length();
    assert!((scale(23) - 0.6).abs() < 1e-5, "STEP holds before 0.8 s");
    assert!((scale(24) - 0.9).abs() < 1e-5, "STEP switches at 0.8 s");

    // The spinner turns 90° about Y in 0.8 s.
    let spinner = s
        .geometry
        .objects
        .iter()
        .position(|o| o.name.as_deref() == Some("spinner/0"))
        .unwrap();
    let x_axis = s.frame_state(24).models[spinner].transform_vector3(Vec3::X);
    assert!(x_axis.abs_diff_eq(Vec3::NEG_Z, 1e-4), "{x_axis}");

    // The file's camera: at [0, 2.6, 5.2], pitched down 24°.
    let CameraPath::Keys(keys) = &s.camera else {
        panic!("the glTF camera becomes keys")
    };
    assert_eq!(keys.len(), 48);
    let cam = s.frame_state(10).camera;
    assert!(cam.eye.abs_diff_eq(Vec3::new(0.0, 2.6, 5.2), 1e-5));
    let forward = (cam.target - cam.eye).normalize();
    assert!(
        (forward.y - (-24f32).to_radians().sin()).abs() < 1e-4,
        "{forward}"
    );
}

#[test]
fn a_material_texture_is_read_from_the_file_as_srgb() {
    let s = boxes();
    let spec = &s.textures["albedo_map"];
    let t = textures::build(&s, "albedo_map", spec, TexDim::D2).unwrap();
    assert_eq!((t.width, t.height), (8, 8));
    assert_eq!(t.format, TexFormat::Rgba8unormSrgb);
    assert!(t.levels.len() > 1, "mipmapped");
    // The checker's two colors, as stored (the GPU decodes sRGB).
    let a = [230.0 / 255.0, 190.0 / 255.0, 90.0 / 255.0, 1.0];
    let b = [60.0 / 255.0, 90.0 / 255.0, 160.0 / 255.0, 1.0];
    let l0 = &t.levels[0];
    let close = |x: [f32; 4], y: [f32; 4]| x.iter().zip(y).all(|(p, q)| (p - q).abs() < 1e-6);
    assert!(close(l0[0], b), "{:?}", l0[0]);
    assert!(close(l0[1], a), "{:?}", l0[1]);
    assert!(textures::build(&s, "albedo_map", spec, TexDim::Cube).is_err());
}

#[test]
fn errors_name_the_field() {
    let field = |r: Result<Session, SessionError>| match r {
        Err(SessionError::Invalid { field, message, .. }) => format!("{field}: {message}"),
        Err(e) => panic!("{e}"),
        Ok(_) => panic!("accepted"),
    };
    let missing = field(edited(|v| v["gltf"]["path"] = "gltf/nope.gltf".into()));
    assert!(
        missing.starts_with("gltf.path: ") && missing.contains("nope.gltf"),
        "{missing}"
    );
    let scene = field(edited(|v| v["gltf"]["scene"] = 3.into()));
    assert!(scene.starts_with("gltf.scene: "), "{scene}");
    let camera = field(edited(|v| {
        v.as_object_mut().unwrap().remove("gltf");
    }));
    assert!(camera.starts_with("camera: "), "{camera}");
    // A texture naming a material the file lacks fails when the texture is built, by name.
    let s = edited(|v| v["textures"]["albedo_map"]["gltf"]["material"] = 4.into()).unwrap();
    let e = textures::build(&s, "albedo_map", &s.textures["albedo_map"], TexDim::D2).unwrap_err();
    assert!(e.contains("albedo_map") && e.contains("material 4"), "{e}");
    // A session's own objects stay, before the file's.
    let s = edited(|v| {
        v["geometry"] = serde_json::json!({"objects": [{"mesh": {"sphere": {"radius": 0.2}}}]});
    })
    .unwrap();
    assert_eq!(s.geometry.objects.len(), 5);
    assert!(matches!(s.geometry.objects[0].mesh, Mesh::Sphere { .. }));
}

#[test]
fn double_sided_materials_are_not_culled() {
    use reproj_scene::session::Cull;
    assert!(
        boxes()
            .geometry
            .objects
            .iter()
            .all(|o| o.cull == Cull::Back)
    );
    // The same file with its material double-sided (its buffers are data URIs: it moves freely).
    let tmp = tempfile::tempdir().unwrap();
    let mut g: serde_json::Value = serde_json::from_str(
        &std::fs::read_to_string(root().join("sessions/gltf/boxes.gltf")).unwrap(),
    )
    .unwrap();
    g["materials"][0]["doubleSided"] = true.into();
    std::fs::write(tmp.path().join("two_sided.gltf"), g.to_string()).unwrap();
    let mut v: serde_json::Value = serde_json::from_str(
        &std::fs::read_to_string(root().join("sessions/gltf_boxes.json")).unwrap(),
    )
    .unwrap();
    v["gltf"]["path"] = "two_sided.gltf".into();
    v["textures"]["albedo_map"]["gltf"]["path"] = "two_sided.gltf".into();
    let path = tmp.path().join("s.json");
    let s = Session::from_json(&v.to_string(), &path, tmp.path()).unwrap();
    assert_eq!(s.geometry.objects.len(), 4);
    assert!(s.geometry.objects.iter().all(|o| o.cull == Cull::None));
}
