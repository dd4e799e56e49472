//! Engine-like sessions without a GPU: nested uniform structs, texture arrays, storage buffers
//! and depth passes, on the corpus shaders that need them (`tests/corpus/shaders/`).

use std::path::{Path, PathBuf};

use reproj_scene::reflect::{self, ResourceKind, StorageLayout, TexDim, UniformField};
use reproj_scene::uniforms::{field_values, storage_bytes, storage_fields, uniform_bytes};
use reproj_scene::{Session, SessionError, textures};

fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

fn interface(shader: &str) -> reflect::Interface {
    let shader =
        reproj_front::load_file(&root().join("tests/corpus/shaders").join(shader)).unwrap();
    let entry = shader.fragment_entry(None).unwrap();
    reflect::reflect(&shader.module, &shader.info, entry).unwrap()
}

fn session(name: &str) -> Session {
    Session::load(root().join("tests/corpus/sessions").join(name)).unwrap()
}

fn resource<'a>(iface: &'a reflect::Interface, name: &str) -> &'a ResourceKind {
    &iface
        .resources
        .iter()
        .find(|r| r.name == name)
        .unwrap_or_else(|| panic!("no resource `{name}`"))
        .kind
}

fn floats(bytes: &[u8]) -> Vec<f32> {
    bytes
        .chunks_exact(4)
        .map(|b| f32::from_le_bytes([b[0], b[1], b[2], b[3]]))
        .collect()
}

fn leaf<'a>(fields: &'a [UniformField], name: &str) -> &'a UniformField {
    fields
        .iter()
        .find(|f| f.name == name)
        .unwrap_or_else(|| panic!("no leaf `{name}` in {:?}", names(fields)))
}

fn names(fields: &[UniformField]) -> Vec<&str> {
    fields.iter().map(|f| f.name.as_str()).collect()
}

#[test]
fn nested_uniform_structs_are_laid_out_by_naga_and_filled_from_nested_objects() {
    let iface = interface("height_fog.wgsl");
    let ResourceKind::Uniform { size, fields } = resource(&iface, "scene") else {
        panic!("scene is a uniform")
    };
    // Scene: camera_pos, time, light_pos, _pad0 (32 bytes), then DirectionalLight (32), FogSettings (32).
    assert_eq!(*size, 96);
    assert_eq!(leaf(fields, "sun.color").offset, 32);
    assert_eq!(leaf(fields, "sun.intensity").offset, 44);
    assert_eq!(leaf(fields, "sun.shininess").offset, 60);
    assert_eq!(leaf(fields, "fog.color").offset, 64);
    assert_eq!(leaf(fields, "fog.height_falloff").offset, 92);

    let s = session("height_fog.json");
    let st = s.frame_state(47);
    let v = floats(&uniform_bytes(&s, &st, *size, fields));
    assert_eq!(&v[8..11], &[1.0, 0.92, 0.8], "sun.color");
    assert_eq!(v[15], 32.0, "sun.shininess");
    assert!((v[19] - 0.45).abs() < 1e-6, "fog.density's last key");
    assert_eq!(
        &v[0..3],
        &st.camera.eye.to_array(),
        "camera_pos is automatic"
    );
}

#[test]
fn arrays_of_structs_in_uniforms_are_indexed_leaves() {
    let src = "struct L { p: vec3<f32>, r: f32 };
        struct U { n: u32, lights: array<L, 2>, m: mat3x3<f32> };
        @group(0) @binding(0) var<uniform> u: U;
        @fragment fn fs() -> @location(0) vec4<f32> {
            return vec4<f32>(u.lights[1].p * u.lights[0].r * f32(u.n), u.m[2].x);
        }";
    let shader = reproj_front::parse_shader(Path::new("t.wgsl"), src.to_owned()).unwrap();
    let iface = reflect::reflect(&shader.module, &shader.info, 0).unwrap();
    let ResourceKind::Uniform { fields, .. } = resource(&iface, "u") else {
        panic!("uniform")
    };
    assert_eq!(
        names(fields),
        [
            "n",
            "lights[0].p",
            "lights[0].r",
            "lights[1].p",
            "lights[1].r",
            "m"
        ]
    );
    assert_eq!(leaf(fields, "lights[1].r").offset, 16 + 16 + 12);
    let text = serde_json::json!({
        "schema": "reproj.session", "version": 1, "resolution": [8, 8], "frames": 2,
        "geometry": {"objects": [{"mesh": {"cube": {"size": [1, 1, 1]}}}]},
        "camera": {"orbit": {"radius": 3}}, "light": {"keys": [{"position": [1, 1, 1]}]},
        "uniforms": {"n": 2, "lights": [{"p": [1, 2, 3], "r": 4}, {"p": [5, 6, 7], "r": 8}],
                     "m": [1, 0, 0, 0, 1, 0, 0, 0, 1]}
    });
    let s = Session::from_json(&text.to_string(), Path::new("t.json"), Path::new(".")).unwrap();
    let st = s.frame_state(0);
    assert_eq!(
        field_values(&s, &st, leaf(fields, "lights[1].p")),
        [5.0, 6.0, 7.0]
    );
    assert_eq!(field_values(&s, &st, leaf(fields, "lights[0].r")), [4.0]);
}

#[test]
fn a_bad_uniform_value_names_the_field_and_what_was_expected() {
    let text =
        std::fs::read_to_string(root().join("tests/corpus/sessions/height_fog.json")).unwrap();
    let mut v: serde_json::Value = serde_json::from_str(&text).unwrap();
    v["uniforms"]["sun"]["intensity"] = serde_json::json!("bright");
    let e = Session::from_json(&v.to_string(), Path::new("fog.json"), Path::new("."))
        .unwrap_err()
        .to_string();
    assert!(e.contains("uniforms.sun"), "{e}");
    assert!(e.contains("member `intensity`"), "{e}");
    assert!(e.contains("expected a number"), "{e}");
    assert!(e.contains("found a string"), "{e}");
    assert!(!e.contains("untagged"), "{e}");
}

#[test]
fn texture_arrays_stack_their_layers() {
    let iface = interface("terrain_splat.wgsl");
    assert_eq!(
        resource(&iface, "layer_albedo"),
        &ResourceKind::Texture {
            dim: TexDim::D2Array
        }
    );
    let s = session("terrain_splat.json");
    let spec = &s.textures["layer_albedo"];
    let d = textures::build(&s, "layer_albedo", spec, TexDim::D2Array).unwrap();
    assert_eq!((d.width, d.height, d.layers), (128, 128, 4));
    assert_eq!(d.levels[0].len(), 128 * 128 * 4);
    assert_eq!(d.levels.len(), 8, "one mip chain for the array");
    assert_eq!(d.level_size(7), (1, 1, 4));
    // Each layer is its own texture: layer 1 is layer 1's spec built alone.
    let mut one = spec.layers.as_ref().unwrap()[1].clone();
    one.mipmaps = false;
    let alone = textures::build(&s, "l1", &one, TexDim::D2).unwrap();
    assert_eq!(&d.levels[0][128 * 128..2 * 128 * 128], &alone.levels[0][..]);

    // Layers of different sizes, and an array without layers, are refused by name.
    let mut bad = spec.clone();
    bad.layers.as_mut().unwrap()[2].size = 64;
    let e = textures::build(&s, "layer_albedo", &bad, TexDim::D2Array).unwrap_err();
    assert!(
        e.contains("layer_albedo.layers[2]") && e.contains("one size"),
        "{e}"
    );
    let e = textures::build(&s, "x", &one, TexDim::D2Array).unwrap_err();
    assert!(
        e.contains("texture_2d_array") && e.contains("`layers`"),
        "{e}"
    );
    let e = textures::build(&s, "x", spec, TexDim::D2).unwrap_err();
    assert!(e.contains("texture_2d_array"), "{e}");
}

#[test]
fn a_layer_with_layers_is_refused() {
    let text =
        std::fs::read_to_string(root().join("tests/corpus/sessions/terrain_splat.json")).unwrap();
    let mut v: serde_json::Value = serde_json::from_str(&text).unwrap();
    v["textures"]["layer_albedo"]["layers"][0] = serde_json::json!({"layers": [{"kind": "solid"}]});
    match Session::from_json(&v.to_string(), Path::new("t.json"), Path::new(".")).unwrap_err() {
        SessionError::Invalid { field, .. } => {
            assert_eq!(field, "textures.layer_albedo.layers[0].layers")
        }
        e => panic!("{e}"),
    }
}

#[test]
fn storage_buffers_size_their_runtime_array_from_the_session() {
    let iface = interface("deferred_lighting.wgsl");
    let ResourceKind::Storage(layout) = resource(&iface, "lights_buffer") else {
        panic!("lights_buffer is a storage buffer")
    };
    let StorageLayout {
        fields, runtime, ..
    } = layout;
    assert_eq!(names(fields), ["count"]);
    let rt = runtime.as_ref().unwrap();
    assert_eq!((rt.name.as_str(), rt.offset, rt.stride), ("lights", 16, 32));
    assert_eq!(
        names(&rt.element),
        ["position", "radius", "color", "intensity"]
    );

    let s = session("deferred_lighting.json");
    let (size, leaves) = storage_fields(&s, "lights_buffer", layout).unwrap();
    assert_eq!(size, 16 + 3 * 32);
    assert_eq!(
        leaf(&leaves, "lights[2].intensity").offset,
        16 + 2 * 32 + 28
    );
    let last = s.frames - 1;
    let bytes = storage_bytes(&s, &s.frame_state(last), "lights_buffer", size, &leaves);
    assert_eq!(u32::from_le_bytes(bytes[0..4].try_into().unwrap()), 3);
    let v = floats(&bytes);
    assert_eq!(
        &v[4..8],
        &[1.2, 0.5, -1.0, 2.5],
        "lights[0] at its last key"
    );
    assert_eq!(&v[12..16], &[0.8, 0.6, 0.9, 2.0]);

    // A missing member and a wrong length are named.
    let mut bad = s.clone();
    let mut b = serde_json::to_value(&bad.buffers["lights_buffer"]).unwrap();
    b["lights"][1].as_object_mut().unwrap().remove("radius");
    b["lights"][2]["color"] = serde_json::json!([1, 1]);
    bad.buffers.insert(
        "lights_buffer".into(),
        reproj_scene::session::UniformValue::from_json(b).unwrap(),
    );
    let e = storage_fields(&bad, "lights_buffer", layout).unwrap_err();
    assert!(e.contains("`lights[1].radius` (f32) is missing"), "{e}");
    assert!(
        e.contains("`lights[2].color` is vec3<f32> (3 values) but the session gives 2 values"),
        "{e}"
    );
}

#[test]
fn depth_passes_draw_with_the_uniform_or_the_camera() {
    let s = session("shadow_pcf.json");
    let st = s.frame_state(5);
    let vp = s.depth_view_proj(&s.depth_passes["shadow_map"], &st);
    let u: Vec<f32> = s.uniforms["light_view_proj"]
        .at(5.0)
        .into_iter()
        .map(|x| x as f32)
        .collect();
    assert_eq!(vp.to_cols_array().to_vec(), u);
    // The sphere's centre lands inside the shadow map's clip volume.
    let c = vp * glam::Vec4::new(0.0, 0.7, 0.0, 1.0);
    assert!(
        c.x.abs() < 1.0 && c.y.abs() < 1.0 && (0.0..1.0).contains(&c.z),
        "{c}"
    );

    let d = session("deferred_lighting.json");
    let st = d.frame_state(0);
    assert_eq!(
        d.depth_view_proj(&d.depth_passes["gbuffer_depth"], &st),
        st.camera.view_proj
    );
    let iface = interface("shadow_pcf.wgsl");
    assert_eq!(resource(&iface, "shadow_map"), &ResourceKind::DepthTexture);
    assert_eq!(
        resource(&iface, "shadow_sampler"),
        &ResourceKind::Sampler { comparison: true }
    );
}

#[test]
fn a_depth_pass_needs_a_16_value_matrix() {
    let text =
        std::fs::read_to_string(root().join("tests/corpus/sessions/shadow_pcf.json")).unwrap();
    let mut v: serde_json::Value = serde_json::from_str(&text).unwrap();
    v["depth_passes"]["shadow_map"]["view_proj"] = serde_json::json!({"uniform": "light_color"});
    match Session::from_json(&v.to_string(), Path::new("t.json"), Path::new(".")).unwrap_err() {
        SessionError::Invalid { field, message, .. } => {
            assert_eq!(field, "depth_passes.shadow_map.view_proj");
            assert!(message.contains("16 numbers"), "{message}");
        }
        e => panic!("{e}"),
    }
    v["depth_passes"]["shadow_map"]["view_proj"] = serde_json::json!({"uniform": "nope"});
    let e = Session::from_json(&v.to_string(), Path::new("t.json"), Path::new("."))
        .unwrap_err()
        .to_string();
    assert!(e.contains("no `nope`"), "{e}");
}
