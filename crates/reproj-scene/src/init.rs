//! A starting session for a shader (`reproj session init`): everything the shader's interface
//! needs, so that `reproj render` runs at once and the author edits values instead of writing
//! JSON from SESSION.md.
//!
//! From the fragment entry point's reflected interface ([`crate::reflect::reflect`]): a torus
//! turning under an orbiting camera and an orbiting light; every uniform leaf the scene does not
//! fill itself ([`crate::uniforms::session_must_provide`]) with a value guessed from its type and name
//! (colours 0.8, scales 1, counts 4, matrices the identity, else 0.5); every texture generated
//! (noise, a normal map by name, an environment for a cube); every storage buffer with four
//! elements in its runtime-sized array; every depth texture as a depth pre-pass from the camera;
//! fragment inputs past the shaders/README.md convention mapped by name. Each guess is listed in
//! the notes, so nothing is silently assumed. GPU-free.

use std::collections::BTreeMap;

use serde_json::{Value, json};

use crate::reflect::{FragInput, Interface, ResourceKind, ScalarTy, TexDim, UniformField};
use crate::session::{PathStep, Session, SessionError, path_steps};
use crate::uniforms::session_must_provide;

/// What [`starter_session`] is asked for.
#[derive(Debug, Clone, PartialEq)]
pub struct StarterOptions {
    pub resolution: [u32; 2],
    pub frames: u32,
    /// Free text for the session's `description` (the shader's name, say).
    pub description: String,
}

impl Default for StarterOptions {
    fn default() -> Self {
        StarterOptions {
            resolution: [256, 256],
            frames: 60,
            description: String::new(),
        }
    }
}

/// A starting session.
#[derive(Debug, Clone)]
pub struct Starter {
    pub session: Session,
    /// One line per guess (`uniforms.noise_scale = 1: a scale, from its name`), in the order the
    /// interface lists them.
    pub notes: Vec<String>,
}

/// Why no starting session can be written.
#[derive(Debug, thiserror::Error)]
pub enum StarterError {
    /// A binding the replay cannot provide (a read-write storage buffer, a storage texture…).
    #[error("`{name}` (@group({group}) @binding({binding})): {what}; the replay cannot provide it")]
    Unsupported {
        name: String,
        group: u32,
        binding: u32,
        what: String,
    },
    /// A fragment input whose attribute cannot be told from its location or its name.
    #[error(
        "fragment input `{name}` at @location({location}): no vertex attribute by the convention (0 position, 1 normal, 2 uv, 3 tangent, 4 object_position) or by its name; map it in the session's `inputs`"
    )]
    Input { name: String, location: u32 },
    /// The session built does not load back (a bug: reported, never written).
    #[error("the starting session does not validate: {0}")]
    Invalid(#[from] SessionError),
}

/// A session that drives the fragment entry point `iface` (see the module docs).
pub fn starter_session(iface: &Interface, opts: &StarterOptions) -> Result<Starter, StarterError> {
    let mut notes = Vec::new();
    let mut uniforms = Value::Null;
    let mut buffers = serde_json::Map::new();
    let mut textures = serde_json::Map::new();
    let mut depth_passes = serde_json::Map::new();
    for r in &iface.resources {
        match &r.kind {
            ResourceKind::Uniform { fields, .. } => {
                for f in fields {
                    if session_must_provide(&f.name) {
                        let (value, why) = guess(f);
                        notes.push(format!("uniforms.{} = {value}: {why}", f.name));
                        insert(&mut uniforms, &path_steps(&f.name), value);
                    } else if let Some(a) = f
                        .name
                        .rsplit('.')
                        .next()
                        .and_then(|m| crate::uniforms::automatic_name(m.split('[').next()?))
                    {
                        notes.push(format!(
                            "uniforms.{}: filled by the replay every frame as `{a}` (a name it knows)",
                            f.name
                        ));
                    }
                }
            }
            ResourceKind::Storage(layout) => {
                let (_, fields) = layout.with_len(4);
                let mut root = Value::Null;
                for f in &fields {
                    let (value, _) = guess(f);
                    insert(&mut root, &path_steps(&f.name), value);
                }
                let runtime = layout.runtime.as_ref().map_or(String::new(), |_| {
                    ", 4 elements in its runtime-sized array".into()
                });
                notes.push(format!(
                    "buffers.{}: every member guessed as uniforms are{runtime}",
                    r.name
                ));
                buffers.insert(r.name.clone(), root);
            }
            ResourceKind::Texture { dim } => {
                let (spec, what) = texture(&r.name, *dim);
                notes.push(format!("textures.{}: {what}", r.name));
                textures.insert(r.name.clone(), spec);
            }
            ResourceKind::DepthTexture => {
                notes.push(format!(
                    "depth_passes.{}: a depth pre-pass from the camera (a shadow map wants {{\"view_proj\": {{\"uniform\": \"light_view_proj\"}}}})",
                    r.name
                ));
                depth_passes.insert(r.name.clone(), json!({ "view_proj": "camera" }));
            }
            ResourceKind::Sampler { .. } => {}
            ResourceKind::Unsupported(what) => {
                return Err(StarterError::Unsupported {
                    name: r.name.clone(),
                    group: r.group,
                    binding: r.binding,
                    what: what.clone(),
                });
            }
        }
    }
    let inputs = inputs(&iface.inputs, &mut notes)?;
    let last = opts.frames.max(1) - 1;
    let doc = json!({
        "schema": "reproj.session",
        "version": 1,
        "description": opts.description,
        "resolution": opts.resolution,
        "frames": opts.frames.max(1),
        "fps": 30,
        "geometry": { "objects": [{
            "name": "object",
            "mesh": { "torus": { "major_radius": 0.75, "minor_radius": 0.35, "segments": 48, "sides": 24 } },
            "transform": { "keys": [
                { "frame": 0, "rotation": { "axis_angle": { "axis": [0.3, 1, 0.2], "deg": 0 } } },
                { "frame": last, "rotation": { "axis_angle": { "axis": [0.3, 1, 0.2], "deg": 30 } } }
            ] }
        }] },
        "camera": { "orbit": {
            "center": [0, 0, 0], "radius": 2.3, "height": 1.2, "start_deg": 60, "end_deg": 90,
            "fov_y_deg": 40, "near": 0.1, "far": 20
        } },
        "light": { "orbit": { "center": [0, 0, 0], "radius": 4, "height": 3, "start_deg": 30, "end_deg": 90 } },
        "uniforms": if uniforms.is_null() { json!({}) } else { uniforms },
        "textures": textures,
        "buffers": buffers,
        "depth_passes": depth_passes,
        "inputs": inputs,
    });
    let text = serde_json::to_string(&doc).expect("a JSON value serializes");
    let session = Session::from_json(
        &text,
        std::path::Path::new("<session init>"),
        std::path::Path::new("."),
    )?;
    Ok(Starter { session, notes })
}

/// A value for the leaf `f` and why: by its member name, then its type.
fn guess(f: &UniformField) -> (Value, &'static str) {
    let name = f
        .name
        .rsplit('.')
        .next()
        .unwrap_or(&f.name)
        .split('[')
        .next()
        .unwrap_or_default()
        .to_ascii_lowercase();
    let has = |words: &[&str]| words.iter().any(|w| name.contains(w));
    let comps = (f.rows * f.cols) as usize;
    let (one, why): (Vec<f64>, &'static str) = if f.cols > 1 {
        let identity = (0..f.cols)
            .flat_map(|c| (0..f.rows).map(move |r| if r == c { 1.0 } else { 0.0 }))
            .collect();
        (identity, "the identity (a matrix)")
    } else if f.scalar != ScalarTy::F32 {
        if has(&["count", "octave", "step", "sample", "iter", "num", "lights"]) {
            (vec![4.0; comps], "4 (a count, from its name)")
        } else {
            (vec![1.0; comps], "1 (an integer)")
        }
    } else if has(&[
        "color", "colour", "albedo", "tint", "diffuse", "specular", "emissive",
    ]) {
        let mut c = vec![0.8; comps];
        if comps == 4 {
            c[3] = 1.0;
        }
        (c, "a light grey (a colour, from its name)")
    } else if has(&["shininess", "gloss", "exponent"]) {
        (vec![32.0; comps], "32 (a specular exponent, from its name)")
    } else if has(&["roughness"]) {
        (vec![0.5; comps], "0.5 (a roughness, from its name)")
    } else if has(&["metal"]) {
        (vec![0.0; comps], "0 (a metalness, from its name)")
    } else if has(&["dir", "direction", "axis"]) && comps >= 3 {
        let mut d = vec![0.0; comps];
        (d[0], d[1], d[2]) = (0.408, 0.816, 0.408);
        (
            d,
            "a unit vector up and to the side (a direction, from its name)",
        )
    } else if has(&[
        "scale",
        "intensity",
        "strength",
        "amount",
        "power",
        "exposure",
        "gain",
        "weight",
        "density",
        "frequency",
        "speed",
    ]) {
        (vec![1.0; comps], "1 (a scale, from its name)")
    } else {
        (
            vec![0.5; comps],
            "0.5 (no hint in its name: set what the shader expects)",
        )
    };
    let value = if f.count > 1 {
        Value::from((0..f.count).flat_map(|_| one.clone()).collect::<Vec<f64>>())
    } else if comps == 1 {
        Value::from(one[0])
    } else {
        Value::from(one)
    };
    (value, why)
}

/// Put `value` at `steps` in the tree `at` (objects for members, lists for indices).
fn insert(at: &mut Value, steps: &[PathStep<'_>], value: Value) {
    let Some((first, rest)) = steps.split_first() else {
        *at = value;
        return;
    };
    match first {
        PathStep::Member(m) => {
            if !at.is_object() {
                *at = Value::Object(serde_json::Map::new());
            }
            let map = at.as_object_mut().expect("made an object above");
            insert(map.entry(m.to_string()).or_insert(Value::Null), rest, value);
        }
        PathStep::Index(i) => {
            if !at.is_array() {
                *at = Value::Array(Vec::new());
            }
            let list = at.as_array_mut().expect("made a list above");
            if list.len() <= *i {
                list.resize(*i + 1, Value::Null);
            }
            insert(&mut list[*i], rest, value);
        }
    }
}

/// A generated texture for the variable `name` of dimension `dim`, and what it is.
fn texture(name: &str, dim: TexDim) -> (Value, &'static str) {
    let lower = name.to_ascii_lowercase();
    match dim {
        TexDim::Cube => (
            json!({ "kind": "environment" }),
            "a generated sky environment (a cube)",
        ),
        TexDim::D2Array => (
            json!({ "layers": [{ "kind": "noise" }, { "kind": "checker" }] }),
            "two generated layers, noise and a checker",
        ),
        TexDim::D3 => (
            json!({ "kind": "noise", "size": 64 }),
            "generated noise, 64³",
        ),
        TexDim::D2 if lower.contains("normal") => (
            json!({ "kind": "normal_map" }),
            "a generated normal map (from its name)",
        ),
        TexDim::D2 => (
            json!({ "kind": "noise" }),
            "generated noise (give an image: {\"file\": \"albedo.png\"})",
        ),
    }
}

/// The vertex attribute an input's name says, when it says one (`world_position`, `tex_coords`,
/// `v_normal`, `obj_pos`, …), checked against its width: a two-wide input is only texture
/// coordinates, a position or normal is three or four wide.
fn attribute_by_name(name: &str, components: u32) -> Option<&'static str> {
    let n = name.to_ascii_lowercase();
    let has = |words: &[&str]| words.iter().any(|w| n.contains(w));
    let object = has(&["obj", "local", "model_pos", "model_norm"]);
    let attribute = if has(&["uv", "texcoord", "tex_coord", "texcoords", "st0", "tc"]) {
        "uv"
    } else if has(&["tangent"]) {
        "tangent"
    } else if has(&["normal", "nrm", "norm"]) {
        if object { "object_normal" } else { "normal" }
    } else if has(&["pos", "world", "frag_p", "vertex_p"]) {
        if object {
            "object_position"
        } else {
            "position"
        }
    } else {
        return None;
    };
    let fits = match attribute {
        "uv" => components == 2,
        "tangent" => components >= 3,
        _ => components >= 3,
    };
    fits.then_some(attribute)
}

/// The attribute for an input the name says nothing of: the shaders/README.md convention by
/// location where its width fits, else by its width alone.
fn attribute_by_location(location: u32, components: u32) -> Option<&'static str> {
    let convention = match location {
        0 => Some("position"),
        1 => Some("normal"),
        2 => Some("uv"),
        3 => Some("tangent"),
        4 => Some("object_position"),
        _ => None,
    };
    let width = |a: &str| if a == "uv" { 2 } else { 3 };
    match convention {
        Some(a) if (width(a) == 2) == (components == 2) => Some(a),
        _ if location <= 4 => Some(match components {
            2 => "uv",
            4 => "tangent",
            _ => "position",
        }),
        _ => None,
    }
}

/// The `inputs` table: each input by its name where the name says an attribute of its width,
/// else by the convention for locations 0–4 (or its width); every choice in the notes.
fn inputs(used: &[FragInput], notes: &mut Vec<String>) -> Result<Value, StarterError> {
    let mut map: BTreeMap<String, &str> = [
        (0, "position"),
        (1, "normal"),
        (2, "uv"),
        (3, "tangent"),
        (4, "object_position"),
    ]
    .into_iter()
    .map(|(l, a)| (l.to_string(), a))
    .collect();
    for i in used {
        if i.scalar.is_integer() {
            // No attribute: the replay feeds an integer input 0 (the one instance drawn).
            notes.push(format!(
                "inputs.{}: `{}` ({}) is an integer input, fed 0 (the one instance drawn, the first index)",
                i.location,
                i.name,
                i.scalar.wgsl_type(i.components)
            ));
            map.remove(&i.location.to_string());
            continue;
        }
        let (attribute, why) = match attribute_by_name(&i.name, i.components) {
            Some(a) => (a, "from its name"),
            None => match attribute_by_location(i.location, i.components) {
                Some(a) if i.location <= 4 && map.get(&i.location.to_string()) == Some(&a) => {
                    (a, "by its location (the shaders/README.md convention)")
                }
                Some(a) => (a, "by its width (its name and location say nothing)"),
                None => {
                    return Err(StarterError::Input {
                        name: i.name.clone(),
                        location: i.location,
                    });
                }
            },
        };
        notes.push(format!(
            "inputs.{} = {attribute}: `{}` ({} wide), {why}",
            i.location, i.name, i.components
        ));
        map.insert(i.location.to_string(), attribute);
    }
    Ok(serde_json::to_value(map).expect("a map serializes"))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn field(name: &str, scalar: ScalarTy, rows: u32, cols: u32, count: u32) -> UniformField {
        UniformField {
            name: name.into(),
            offset: 0,
            scalar,
            rows,
            cols,
            col_stride: 16,
            count,
            stride: 16,
            ty: String::new(),
        }
    }

    #[test]
    fn leaves_are_guessed_by_name_then_type() {
        let g = |f: UniformField| guess(&f).0;
        assert_eq!(
            g(field("light_color", ScalarTy::F32, 3, 1, 1)),
            json!([0.8, 0.8, 0.8])
        );
        assert_eq!(
            g(field("tint", ScalarTy::F32, 4, 1, 1)),
            json!([0.8, 0.8, 0.8, 1.0])
        );
        assert_eq!(g(field("noise_scale", ScalarTy::F32, 1, 1, 1)), json!(1.0));
        assert_eq!(g(field("octaves", ScalarTy::I32, 1, 1, 1)), json!(4.0));
        assert_eq!(g(field("mode", ScalarTy::U32, 1, 1, 1)), json!(1.0));
        assert_eq!(g(field("wobble", ScalarTy::F32, 1, 1, 1)), json!(0.5));
        assert_eq!(
            g(field("model", ScalarTy::F32, 2, 2, 1)),
            json!([1.0, 0.0, 0.0, 1.0])
        );
        // A fixed-size array: the value repeated per element, flattened.
        assert_eq!(
            g(field("weights", ScalarTy::F32, 1, 1, 3)),
            json!([1.0, 1.0, 1.0])
        );
    }

    fn input(location: u32, components: u32, name: &str) -> FragInput {
        FragInput {
            scalar: crate::reflect::InputScalar::F32,
            location,
            components,
            interpolation: None,
            sampling: None,
            name: name.into(),
        }
    }

    #[test]
    fn inputs_go_by_name_before_location() {
        let mut notes = Vec::new();
        // Texture coordinates first and the world position second: by name, not by location.
        let used = [
            input(0, 2, "tex_coords"),
            input(1, 3, "world_position"),
            input(2, 3, "world_normal"),
            input(3, 4, "v_tangent"),
            input(5, 3, "obj_pos"),
        ];
        let map = inputs(&used, &mut notes).unwrap();
        assert_eq!(map["0"], "uv");
        assert_eq!(map["1"], "position");
        assert_eq!(map["2"], "normal");
        assert_eq!(map["3"], "tangent");
        assert_eq!(map["5"], "object_position");
        assert_eq!(notes.len(), 5, "{notes:?}");
        assert!(
            notes.iter().all(|n| n.contains("from its name")),
            "{notes:?}"
        );
        // A name that says nothing: the convention where the width fits, else the width.
        let mut notes = Vec::new();
        let map = inputs(&[input(0, 3, "a"), input(2, 3, "b")], &mut notes).unwrap();
        assert_eq!(map["0"], "position");
        assert_eq!(map["2"], "position");
        assert!(
            notes[0].contains("convention") && notes[1].contains("width"),
            "{notes:?}"
        );
        // Past the convention with no name to go by: refused, naming it.
        assert!(inputs(&[input(7, 1, "q")], &mut Vec::new()).is_err());
    }

    #[test]
    fn leaf_paths_become_nested_objects_and_lists() {
        let mut root = Value::Null;
        insert(&mut root, &path_steps("shininess"), json!(32));
        insert(&mut root, &path_steps("sun.color"), json!([1, 1, 1]));
        insert(
            &mut root,
            &path_steps("lights[1].position"),
            json!([0, 1, 0]),
        );
        insert(
            &mut root,
            &path_steps("lights[0].position"),
            json!([1, 0, 0]),
        );
        assert_eq!(
            root,
            json!({
                "shininess": 32,
                "sun": { "color": [1, 1, 1] },
                "lights": [{ "position": [1, 0, 0] }, { "position": [0, 1, 0] }]
            })
        );
    }
}
