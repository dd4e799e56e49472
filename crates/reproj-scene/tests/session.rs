//! The scene's logic: session loading, validation and animation, reflection of a fragment
//! interface, and the published session schema.

use std::path::{Path, PathBuf};

use reproj_scene::reflect::{self, ResourceKind, ScalarTy};
use reproj_scene::session::{CameraPath, PointPath};
use reproj_scene::{Session, SessionError};

fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

fn data(p: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../reproj-replay/tests/data")
        .join(p)
}

fn tiny_json() -> serde_json::Value {
    let text = std::fs::read_to_string(data("tiny_moving.json")).unwrap();
    serde_json::from_str(&text).unwrap()
}

fn parse(v: &serde_json::Value) -> Result<Session, SessionError> {
    Session::from_json(&v.to_string(), Path::new("test.json"), Path::new("."))
}

fn invalid_field(e: SessionError) -> String {
    match e {
        SessionError::Invalid { field, .. } => field,
        other => panic!("expected an invalid field, got {other}"),
    }
}

#[test]
fn loading_sorts_keys_and_validate_checks_the_order() {
    let mut v = tiny_json();
    // Light keys written last frame first.
    v["light"]["keys"] = serde_json::json!([
        { "frame": 3, "position": [2, 3, 4] },
        { "frame": 0, "position": [3, 3, 3] },
    ]);
    let s = parse(&v).unwrap();
    let PointPath::Keys(keys) = &s.light else {
        panic!("light is key-framed")
    };
    assert_eq!(keys.iter().map(|k| k.frame).collect::<Vec<_>>(), [0.0, 3.0]);
    s.validate().unwrap();

    // A session changed in code with its keys out of order is refused, naming the field...
    let mut unsorted = s.clone();
    if let PointPath::Keys(keys) = &mut unsorted.light {
        keys.reverse();
    }
    assert_eq!(
        invalid_field(unsorted.validate().unwrap_err()),
        "light.keys"
    );
    // ...and accepted once sorted.
    unsorted.sort_keys();
    unsorted.validate().unwrap();
}

#[test]
fn validation_names_the_field_at_fault() {
    let cases: [(&str, serde_json::Value, &str); 4] = [
        ("resolution", serde_json::json!([0, 64]), "resolution"),
        ("frames", serde_json::json!(0), "frames"),
        (
            "camera",
            serde_json::json!({ "keys": [ { "frame": 0, "eye": [1, 1, 1], "target": [1, 1, 1] } ] }),
            "camera.keys[0]",
        ),
        (
            "uniforms",
            serde_json::json!({ "gain": { "keys": [
                { "frame": 0, "value": 1 }, { "frame": 1, "value": [1, 2] } ] } }),
            "uniforms.gain.keys",
        ),
    ];
    for (key, value, field) in cases {
        let mut v = tiny_json();
        v[key] = value;
        assert_eq!(invalid_field(parse(&v).unwrap_err()), field, "{key}");
    }
}

#[test]
fn key_frames_interpolate_linearly_and_clamp() {
    let s = parse(&tiny_json()).unwrap();
    // Light: (3,3,3) at frame 0, (2,3,4) at frame 3.
    let at = |f: u32| s.frame_state(f).light_pos.to_array();
    assert_eq!(at(0), [3.0, 3.0, 3.0]);
    let mid = s.light.position(1.5, s.frames).to_array();
    assert!(
        (mid[0] - 2.5).abs() < 1e-6 && (mid[2] - 3.5).abs() < 1e-6,
        "{mid:?}"
    );
    assert_eq!(at(3), [2.0, 3.0, 4.0]);
    assert_eq!(at(40), [2.0, 3.0, 4.0], "held after the last key");
    // Time is frame / fps.
    assert!((s.frame_state(15).time - 0.5).abs() < 1e-6);
    // One model matrix per object; frame 0's rotation is the identity.
    let f0 = s.frame_state(0);
    assert_eq!(f0.models.len(), 1);
    assert!(f0.models[0].abs_diff_eq(glam::Mat4::IDENTITY, 1e-6));
}

/// A `matrix` transform key is the model matrix exactly on its frame; between a matrix key and
/// another the scale, rotation and translation are interpolated; a matrix that is not affine or
/// comes with translation, rotation or scale is refused, naming the key.
#[test]
fn matrix_transform_keys_are_exact_on_their_frames() {
    let a = glam::Mat4::from_scale_rotation_translation(
        glam::Vec3::splat(2.0),
        glam::Quat::from_rotation_y(0.3),
        glam::Vec3::new(1.0, 0.0, 0.0),
    );
    let b = glam::Mat4::from_scale_rotation_translation(
        glam::Vec3::splat(2.0),
        glam::Quat::from_rotation_y(0.7),
        glam::Vec3::new(3.0, 0.0, 0.0),
    );
    let mut v = tiny_json();
    v["geometry"]["objects"][0]["transform"] = serde_json::json!({ "keys": [
        { "frame": 0, "matrix": a.to_cols_array() },
        { "frame": 2, "matrix": b.to_cols_array() },
    ] });
    let s = parse(&v).unwrap();
    assert_eq!(s.frame_state(0).models[0], a, "exact on a key");
    assert_eq!(s.frame_state(2).models[0], b, "exact on a key");
    let mid = glam::Mat4::from_scale_rotation_translation(
        glam::Vec3::splat(2.0),
        glam::Quat::from_rotation_y(0.5),
        glam::Vec3::new(2.0, 0.0, 0.0),
    );
    assert!(s.frame_state(1).models[0].abs_diff_eq(mid, 1e-5));

    let mut projective = a.to_cols_array();
    projective[3] = 0.5;
    let mut both = serde_json::json!({ "frame": 0, "matrix": a.to_cols_array() });
    both["translation"] = serde_json::json!([1, 0, 0]);
    for (key, message) in [
        (serde_json::json!({ "matrix": projective }), "affine"),
        (both, "give one or the others"),
    ] {
        let mut v = tiny_json();
        v["geometry"]["objects"][0]["transform"] = serde_json::json!({ "keys": [key] });
        let e = parse(&v).unwrap_err();
        assert!(e.to_string().contains(message), "{e}");
        assert_eq!(
            invalid_field(e),
            "geometry.objects[0].transform.keys[0].matrix"
        );
    }
}

#[test]
fn orbit_camera_keeps_its_radius_and_height() {
    let s = parse(&tiny_json()).unwrap();
    let CameraPath::Orbit(o) = &s.camera else {
        panic!("the tiny session orbits")
    };
    for f in 0..s.frames {
        let c = s.frame_state(f).camera;
        let d = c.eye - glam::Vec3::from(o.center);
        assert!((d.y - o.height).abs() < 1e-5, "frame {f}");
        assert!(
            (glam::Vec2::new(d.x, d.z).length() - o.radius).abs() < 1e-4,
            "frame {f}"
        );
        assert!(c.view_proj.abs_diff_eq(c.proj * c.view, 1e-5), "frame {f}");
    }
}

fn tiny_interface() -> reflect::Interface {
    let shader = reproj_front::load_file(&data("tiny.wgsl")).unwrap();
    let entry = shader.fragment_entry(None).unwrap();
    reflect::reflect(&shader.module, &shader.info, entry).unwrap()
}

#[test]
fn reflection_reads_inputs_and_uniform_layout() {
    let iface = tiny_interface();
    assert_eq!(iface.entry, "fs_main");
    let inputs: Vec<(u32, u32, &str)> = iface
        .inputs
        .iter()
        .map(|i| (i.location, i.components, i.name.as_str()))
        .collect();
    assert_eq!(
        inputs,
        [(0, 3, "world_pos"), (1, 3, "normal"), (2, 2, "uv")]
    );
    assert_eq!(iface.groups(), [0, 1]);
    let scene = iface.resources.iter().find(|r| r.name == "scene").unwrap();
    let ResourceKind::Uniform { size, fields } = &scene.kind else {
        panic!("scene is a uniform")
    };
    assert_eq!(*size, 48);
    let layout: Vec<(&str, u32, u32)> = fields
        .iter()
        .map(|f| (f.name.as_str(), f.offset, f.rows))
        .collect();
    assert_eq!(
        layout,
        [
            ("camera_pos", 0, 3),
            ("time", 12, 1),
            ("light_pos", 16, 3),
            ("gain", 28, 1),
            ("tint", 32, 3),
        ]
    );
    assert!(fields.iter().all(|f| f.scalar == ScalarTy::F32));
    let map = iface
        .resources
        .iter()
        .find(|r| r.name == "albedo_map")
        .unwrap();
    assert_eq!((map.group, map.binding), (1, 0));
    assert!(matches!(map.kind, ResourceKind::Texture { .. }));
    let smp = iface
        .resources
        .iter()
        .find(|r| r.name == "albedo_sampler")
        .unwrap();
    assert!(matches!(smp.kind, ResourceKind::Sampler { .. }));
}

#[test]
fn reflection_refuses_a_vertex_entry() {
    let src = "@vertex fn vs() -> @builtin(position) vec4<f32> { return vec4<f32>(0.0); }";
    let module = naga::front::wgsl::parse_str(src).unwrap();
    let info = reproj_front::validator().validate(&module).unwrap();
    let e = reflect::reflect(&module, &info, 0).unwrap_err();
    assert!(e.to_string().contains("not a @fragment"), "{e}");
}

/// A push-constant block (naga's immediates: GLSL's `layout(push_constant)`) is refused by name
/// at reflection — `render`, `analyze` and `session init` exit 2 with it — instead of by wgpu's
/// pipeline validation (exit 1, several lines).
#[test]
fn reflection_refuses_push_constants_by_name() {
    let src = "struct Push { tint: vec4<f32> }
var<immediate> push: Push;
@fragment fn fs(@location(0) p: vec3<f32>) -> @location(0) vec4<f32> { return push.tint * p.x; }";
    let module = naga::front::wgsl::parse_str(src).unwrap();
    let info = reproj_front::validator().validate(&module).unwrap();
    let e = reflect::reflect(&module, &info, 0).unwrap_err();
    assert!(
        e.to_string()
            .contains("`push` is a push-constant block (naga's immediates)"),
        "{e}"
    );
    // A block the entry point does not read is refused too (the whole module is created on the
    // device, and wgpu refuses it there, exit 1), saying that it is unused.
    let src = "struct Push { tint: vec4<f32> }
var<immediate> push: Push;
@fragment fn fs(@location(0) p: vec3<f32>) -> @location(0) vec4<f32> { return vec4(p, 1.0); }";
    let module = naga::front::wgsl::parse_str(src).unwrap();
    let info = reproj_front::validator().validate(&module).unwrap();
    let e = reflect::reflect(&module, &info, 0).unwrap_err();
    assert!(
        e.to_string()
            .contains("`push` is a push-constant block (naga's immediates) (declared, though this entry point does not read it)"),
        "{e}"
    );
}

/// A resource without @group/@binding (a host that binds by name, as Blade's WGSL is written) is
/// refused by name at reflection, not by wgpu's shader validation (exit 1).
#[test]
fn reflection_refuses_a_resource_without_a_binding_by_name() {
    let src = "struct P { tint: vec4<f32> }
var<uniform> params: P;
@fragment fn fs(@location(0) p: vec3<f32>) -> @location(0) vec4<f32> { return params.tint * p.x; }";
    let module = naga::front::wgsl::parse_str(src).unwrap();
    let info = naga::valid::Validator::new(
        naga::valid::ValidationFlags::all() - naga::valid::ValidationFlags::BINDINGS,
        naga::valid::Capabilities::all(),
    )
    .validate(&module)
    .unwrap();
    let e = reflect::reflect(&module, &info, 0).unwrap_err();
    assert!(
        e.to_string()
            .contains("`params` has no @group/@binding (its host binds it by name)"),
        "{e}"
    );
}

/// An integer input (flat) is read with its scalar, for the replay to feed it 0.
#[test]
fn reflection_reads_an_integer_input_with_its_scalar() {
    let src = "struct V { @builtin(position) p: vec4<f32>, @location(0) n: vec3<f32>, @location(6) @interpolate(flat) i: u32, @location(7) @interpolate(flat) j: vec2<i32> }
@fragment fn fs(v: V) -> @location(0) vec4<f32> { return vec4(v.n * f32(v.i + u32(v.j.x)), 1.0); }";
    let module = naga::front::wgsl::parse_str(src).unwrap();
    let info = reproj_front::validator().validate(&module).unwrap();
    let iface = reflect::reflect(&module, &info, 0).unwrap();
    let by = |l: u32| iface.inputs.iter().find(|i| i.location == l).unwrap();
    assert_eq!(
        (by(0).scalar, by(0).components),
        (reflect::InputScalar::F32, 3)
    );
    assert_eq!(
        (by(6).scalar, by(6).components),
        (reflect::InputScalar::U32, 1)
    );
    assert_eq!(
        (by(7).scalar, by(7).components),
        (reflect::InputScalar::I32, 2)
    );
    assert_eq!(by(7).scalar.wgsl_type(2), "vec2<i32>");
}

/// An override without a default (WebGPU samples' `override canvasSizeWidth: f32;`) is refused by
/// name at reflection, not when wgpu creates the pipeline (exit 1).
#[test]
fn reflection_refuses_an_override_without_a_default_by_name() {
    let src = "override width: f32;
@fragment fn fs(@location(0) p: vec3<f32>) -> @location(0) vec4<f32> { return vec4(p / width, 1.0); }";
    let module = naga::front::wgsl::parse_str(src).unwrap();
    let info = reproj_front::validator().validate(&module).unwrap();
    let e = reflect::reflect(&module, &info, 0).unwrap_err();
    assert!(
        e.to_string().contains(
            "override `width` has no default value, and the replay sets no pipeline constants"
        ),
        "{e}"
    );
}

/// `docs/session.schema.json` is what the session types generate. It is published at that path
/// (editors read it), so it is not an insta snapshot, but it is updated the way snapshots are:
/// after changing the types, `INSTA_UPDATE=always cargo test -p reproj-scene --test integration
/// session::` rewrites it, and `git diff` reviews it.
#[test]
fn the_published_session_schema_is_current_and_every_session_validates() {
    let path = root().join("docs/session.schema.json");
    let mut text = serde_json::to_string_pretty(&reproj_scene::session::session_schema()).unwrap();
    text.push('\n');
    if std::env::var("INSTA_UPDATE").as_deref() == Ok("always") {
        std::fs::write(&path, &text).unwrap();
    }
    let published = std::fs::read_to_string(&path).unwrap_or_default();
    assert!(
        published == text,
        "docs/session.schema.json is out of date: run `INSTA_UPDATE=always cargo test -p \
         reproj-scene --test integration session::` and review the diff"
    );
    let schema: serde_json::Value = serde_json::from_str(&published).unwrap();
    let validator = jsonschema::validator_for(&schema).unwrap();
    // Every session of the repository, as written (not as loaded: defaults left out must pass).
    let mut files = Vec::new();
    let mut dirs = vec![root().join("sessions")];
    while let Some(dir) = dirs.pop() {
        for e in std::fs::read_dir(dir).unwrap() {
            let p = e.unwrap().path();
            if p.is_dir() {
                dirs.push(p);
            } else if p.extension().is_some_and(|x| x == "json") {
                files.push(p);
            }
        }
    }
    assert!(files.len() >= 10, "{files:?}");
    for f in &files {
        let value: serde_json::Value =
            serde_json::from_str(&std::fs::read_to_string(f).unwrap()).unwrap();
        if value["schema"] != "reproj.session" {
            continue;
        }
        let errors: Vec<String> = validator
            .iter_errors(&value)
            .map(|e| format!("{e} at {}", e.instance_path()))
            .collect();
        assert!(errors.is_empty(), "{}: {errors:?}", f.display());
    }
    // A typo'd field, a wrong schema name and prose where numbers belong are caught, as the
    // loader catches them.
    let good: serde_json::Value = serde_json::from_str(
        &std::fs::read_to_string(root().join("sessions/marble.json")).unwrap(),
    )
    .unwrap();
    let mut typo = good.clone();
    typo["camera"]["orbit"]["radus"] = serde_json::json!(2);
    assert!(!validator.is_valid(&typo));
    let mut other = good.clone();
    other["schema"] = serde_json::json!("reproj.profile");
    assert!(!validator.is_valid(&other));
    let mut prose = good;
    prose["resolution"] = serde_json::json!("256x256");
    assert!(!validator.is_valid(&prose));
}

/// An OBJ's vertex, normal or texture coordinate that is NaN, infinite or past the f32 range is
/// refused naming the file, the line and the number (it used to give a mesh that covers no
/// pixel, the NaN never named); a finite one loads.
#[test]
fn an_obj_with_a_non_finite_number_is_refused_naming_line_and_value() {
    let dir = tempfile::tempdir().unwrap();
    let mut v = tiny_json();
    v["geometry"]["objects"][0]["mesh"] = serde_json::json!({"obj": {"path": "m.obj"}});
    let session =
        Session::from_json(&v.to_string(), &dir.path().join("s.json"), dir.path()).unwrap();
    let mesh = &session.geometry.objects[0].mesh;
    let good = "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 0 1\nf 1/1 2/2 3/3\n";
    std::fs::write(dir.path().join("m.obj"), good).unwrap();
    reproj_scene::mesh::build(&session, mesh).unwrap();
    for (bad, line, value) in [
        ("v 0 0 0\nv nan 0 0\nv 0 1 0\nf 1 2 3\n", 2, "nan"),
        ("v 0 0 0\nv 1 0 0\nv 0 1e39 0\nf 1 2 3\n", 3, "1e39"),
        (
            "v 0 0 0\nv 1 0 0\nv 0 1 0\nvn 0 0 -inf\nf 1//1 2//1 3//1\n",
            4,
            "-inf",
        ),
        (
            "v 0 0 0\nv 1 0 0\nv 0 1 0\n# c\nvt NaN 0\nf 1/1 2/1 3/1\n",
            5,
            "NaN",
        ),
    ] {
        std::fs::write(dir.path().join("m.obj"), bad).unwrap();
        let e = reproj_scene::mesh::build(&session, mesh).unwrap_err();
        assert!(
            e.contains(&format!("m.obj:{line}:")) && e.contains(&format!("`{value}`")),
            "{e}"
        );
        assert!(e.contains("not a finite number"), "{e}");
    }
    // Finite in the file, past the f32 range once scaled.
    v["geometry"]["objects"][0]["mesh"] =
        serde_json::json!({"obj": {"path": "m.obj", "scale": 1e30}});
    let session =
        Session::from_json(&v.to_string(), &dir.path().join("s.json"), dir.path()).unwrap();
    std::fs::write(
        dir.path().join("m.obj"),
        "v 0 0 0\nv 1e10 0 0\nv 0 1 0\nf 1 2 3\n",
    )
    .unwrap();
    let e = reproj_scene::mesh::build(&session, &session.geometry.objects[0].mesh).unwrap_err();
    assert!(
        e.contains("m.obj: vertex 1") && e.contains("scaled by"),
        "{e}"
    );
}
