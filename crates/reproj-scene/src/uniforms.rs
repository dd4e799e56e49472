//! CPU-side scene data of a frame, GPU-free: the bytes of the shader's own uniform buffers.
//!
//! The replay's renderer and any other host that renders a session itself (such as
//! `examples/host`, which runs an emitted variant from its manifest alone) fill the shader's
//! uniforms with these functions, so both draw the same recorded scene. The rest of the scene is
//! public elsewhere: geometry from [`crate::mesh::build`], texels from [`crate::textures::build`],
//! camera and object matrices from [`Session::frame_state`], the uniform layouts from
//! [`crate::reflect::reflect`].
//!
//! A uniform field is filled by name: from the session's `uniforms` when it has the name (a
//! member of a nested struct by its path, `sun.color` from `{"sun": {"color": ...}}`), else
//! automatically by its member name for the names in [`AUTOMATIC_FIELDS`] (`camera_pos`: the camera's eye;
//! `light_pos`; `time`: seconds since frame 0; `frame`: the frame index; `resolution`: width and
//! height in pixels; `view_proj` and `inv_view_proj`: the camera's view-projection and its inverse;
//! vectors wider than the value are padded with 0, and a 4th component of 1 for positions), else
//! with zeros. Fields whose name starts with `_` are padding.

use crate::reflect::{StorageLayout, UniformField};
use crate::session::{FrameState, Session, UniformValue, path_steps};

/// Uniform field names filled from the scene when the session's `uniforms` does not give them.
pub const AUTOMATIC_FIELDS: [&str; 7] = [
    "camera_pos",
    "light_pos",
    "time",
    "frame",
    "resolution",
    "view_proj",
    "inv_view_proj",
];

/// Other names engines give the eye and the light's position, filled as `camera_pos` and
/// `light_pos` are (engine shaders as they sit in their repositories say `view_pos`,
/// `eye_position`, `world_camera_position`, `light_position`…).
pub const FIELD_ALIASES: [(&str, &str); 14] = [
    ("view_pos", "camera_pos"),
    ("view_position", "camera_pos"),
    ("eye_pos", "camera_pos"),
    ("eye_position", "camera_pos"),
    ("eye", "camera_pos"),
    ("camera_position", "camera_pos"),
    ("cam_pos", "camera_pos"),
    ("world_camera_pos", "camera_pos"),
    ("world_camera_position", "camera_pos"),
    ("view_world_position", "camera_pos"),
    ("light_position", "light_pos"),
    ("world_light_pos", "light_pos"),
    ("light_world_pos", "light_pos"),
    ("light_pos_ws", "light_pos"),
];

/// The automatic field a member name stands for: itself, or what [`FIELD_ALIASES`] maps it to
/// (case-insensitive), when it is one.
pub fn automatic_name(member: &str) -> Option<&'static str> {
    let lower = member.to_ascii_lowercase();
    AUTOMATIC_FIELDS
        .iter()
        .copied()
        .find(|a| *a == lower)
        .or_else(|| {
            FIELD_ALIASES
                .iter()
                .find(|(alias, _)| *alias == lower)
                .map(|(_, a)| *a)
        })
}

/// The last member name of a leaf path (`color` of `sun.color`, `position` of
/// `lights[2].position`): what padding and the [`AUTOMATIC_FIELDS`] are recognized by.
fn member_name(path: &str) -> &str {
    let last = path.rsplit('.').next().unwrap_or(path);
    last.split('[').next().unwrap_or(last)
}

/// Whether the session must provide field `name` (a leaf path, see
/// [`crate::reflect::UniformField::name`]) in its `uniforms`: its member name is neither padding
/// nor one of the [`AUTOMATIC_FIELDS`] or their [`FIELD_ALIASES`].
pub fn session_must_provide(name: &str) -> bool {
    let m = member_name(name);
    !m.starts_with('_') && automatic_name(m).is_none()
}

/// The values (column-major, arrays flattened) of uniform field `field` on the frame `state`.
pub fn field_values(session: &Session, state: &FrameState, field: &UniformField) -> Vec<f64> {
    if let Some(v) = session.uniform(&field.name) {
        return v.at(state.frame as f32);
    }
    let pad = |mut v: Vec<f64>, w: f64| {
        while v.len() < field.len() {
            v.push(if v.len() == 3 { w } else { 0.0 });
        }
        v
    };
    match automatic_name(member_name(&field.name)).unwrap_or_default() {
        "camera_pos" => pad(state.camera.eye.to_array().map(f64::from).to_vec(), 1.0),
        "light_pos" => pad(state.light_pos.to_array().map(f64::from).to_vec(), 1.0),
        "time" => pad(vec![f64::from(state.time)], 0.0),
        "frame" => pad(vec![f64::from(state.frame)], 0.0),
        "view_proj" => state
            .camera
            .view_proj
            .to_cols_array()
            .map(f64::from)
            .to_vec(),
        "inv_view_proj" => state
            .camera
            .view_proj
            .inverse()
            .to_cols_array()
            .map(f64::from)
            .to_vec(),
        "resolution" => pad(
            vec![
                f64::from(session.resolution[0]),
                f64::from(session.resolution[1]),
            ],
            0.0,
        ),
        _ => vec![0.0; field.len()],
    }
}

/// The session's value of storage buffer `buffer`'s leaf `leaf` (a path below the buffer).
fn storage_value<'a>(session: &'a Session, buffer: &str, leaf: &str) -> Option<&'a UniformValue> {
    session.buffers.get(buffer)?.lookup(&path_steps(leaf))
}

/// The size and leaves of storage buffer `buffer` (laid out as `layout`) for the session's
/// contents: a runtime-sized array gets as many elements as the session's list has. The error
/// names every leaf the session does not give, or gives with the wrong number of values.
pub fn storage_fields(
    session: &Session,
    buffer: &str,
    layout: &StorageLayout,
) -> Result<(u32, Vec<UniformField>), String> {
    let n = match &layout.runtime {
        None => 0,
        Some(rt) => match storage_value(session, buffer, &rt.name) {
            Some(UniformValue::Array(items)) => items.len() as u32,
            Some(v) if v.is_leaf() => {
                let per = rt.element.first().map_or(1, UniformField::len).max(1);
                (v.len() / per) as u32
            }
            _ => {
                return Err(format!(
                    "storage buffer `{buffer}`: the session gives no list for its runtime-sized array `{}`",
                    if rt.name.is_empty() { buffer } else { &rt.name }
                ));
            }
        },
    };
    let (size, fields) = layout.with_len(n);
    let mut bad = Vec::new();
    for f in &fields {
        if f.name
            .rsplit('.')
            .next()
            .is_some_and(|m| m.starts_with('_'))
        {
            continue;
        }
        let shown = if f.name.is_empty() { buffer } else { &f.name };
        match storage_value(session, buffer, &f.name) {
            None => bad.push(format!("`{shown}` ({}) is missing", f.ty)),
            Some(v) if !v.is_leaf() || v.len() != f.len() => bad.push(format!(
                "`{shown}` is {} ({} values) but the session gives {}",
                f.ty,
                f.len(),
                if v.is_leaf() {
                    format!("{} values", v.len())
                } else {
                    "an object or a list of objects".into()
                }
            )),
            Some(_) => {}
        }
    }
    if bad.is_empty() {
        Ok((size, fields))
    } else {
        Err(format!("storage buffer `{buffer}`: {}", bad.join(", ")))
    }
}

/// The contents of storage buffer `buffer` of `size` bytes with `fields` (from
/// [`storage_fields`]) on the frame `state`.
pub fn storage_bytes(
    session: &Session,
    state: &FrameState,
    buffer: &str,
    size: u32,
    fields: &[UniformField],
) -> Vec<u8> {
    let mut bytes = vec![0u8; size.max(16) as usize];
    for f in fields {
        let values = storage_value(session, buffer, &f.name)
            .map(|v| v.at(state.frame as f32))
            .unwrap_or_default();
        f.write(&mut bytes, &values);
    }
    bytes
}

/// The contents of a uniform buffer of `size` bytes (at least 16) with `fields` on the frame
/// `state`: what the host writes to the buffer before drawing that frame.
pub fn uniform_bytes(
    session: &Session,
    state: &FrameState,
    size: u32,
    fields: &[UniformField],
) -> Vec<u8> {
    let mut bytes = vec![0u8; size.max(16) as usize];
    for f in fields {
        f.write(&mut bytes, &field_values(session, state, f));
    }
    bytes
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::reflect::ScalarTy;

    fn field(name: &str, offset: u32, rows: u32) -> UniformField {
        UniformField {
            name: name.into(),
            offset,
            scalar: ScalarTy::F32,
            rows,
            cols: 1,
            col_stride: 16,
            count: 1,
            stride: 16,
            ty: "f32".into(),
        }
    }

    fn floats(bytes: &[u8]) -> Vec<f32> {
        bytes
            .chunks_exact(4)
            .map(|b| f32::from_le_bytes([b[0], b[1], b[2], b[3]]))
            .collect()
    }

    #[test]
    fn fields_come_from_the_session_then_the_scene() {
        let path = concat!(env!("CARGO_MANIFEST_DIR"), "/../../sessions/marble.json");
        let session = Session::load(path).unwrap();
        let st = session.frame_state(3);
        let fields = [
            field("camera_pos", 0, 4),
            field("frame", 16, 1),
            field("shininess", 20, 1),
            field("_pad", 24, 1),
            field("resolution", 32, 2),
            field("unknown", 40, 1),
        ];
        assert!(!session_must_provide("camera_pos") && !session_must_provide("_pad"));
        assert!(session_must_provide("shininess"));
        let v = floats(&uniform_bytes(&session, &st, 48, &fields));
        assert_eq!(v.len(), 12);
        assert_eq!(&v[0..3], &st.camera.eye.to_array());
        assert_eq!(v[3], 1.0, "a position's fourth component is 1");
        assert_eq!(v[4], 3.0);
        assert_eq!(v[5], 60.0, "from the session's uniforms");
        assert_eq!(v[6], 0.0);
        assert_eq!(&v[8..10], &[256.0, 256.0]);
        assert_eq!(v[10], 0.0, "a field nobody gives is zero");
    }
}
