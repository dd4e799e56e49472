//! CPU-side scene data of a frame, GPU-free: the bytes of the shader's own uniform buffers.
//!
//! The replay's renderer and any other host that renders a session itself (such as
//! `examples/host`, which runs an emitted variant from its manifest alone) fill the shader's
//! uniforms with these functions, so both draw the same recorded scene. The rest of the scene is
//! public elsewhere: geometry from [`crate::mesh::build`], texels from [`crate::textures::build`],
//! camera and object matrices from [`Session::frame_state`], the uniform layouts from
//! [`crate::reflect::reflect`].
//!
//! A uniform field is filled by name: from the session's `uniforms` when it has the name, else
//! automatically for the names in [`AUTOMATIC_FIELDS`] (`camera_pos`: the camera's eye;
//! `light_pos`; `time`: seconds since frame 0; `frame`: the frame index; `resolution`: width and
//! height in pixels; vectors wider than the value are padded with 0, and a 4th component of 1 for
//! positions), else with zeros. Fields whose name starts with `_` are padding.

use crate::reflect::UniformField;
use crate::session::{FrameState, Session};

/// Uniform field names filled from the scene when the session's `uniforms` does not give them.
pub const AUTOMATIC_FIELDS: [&str; 5] = ["camera_pos", "light_pos", "time", "frame", "resolution"];

/// Whether the session must provide field `name` in its `uniforms` (it is neither padding nor
/// one of the [`AUTOMATIC_FIELDS`]).
pub fn session_must_provide(name: &str) -> bool {
    !name.starts_with('_') && !AUTOMATIC_FIELDS.contains(&name)
}

/// The values (column-major, arrays flattened) of uniform field `field` on the frame `state`.
pub fn field_values(session: &Session, state: &FrameState, field: &UniformField) -> Vec<f64> {
    if let Some(v) = session.uniforms.get(&field.name) {
        return v.at(state.frame as f32);
    }
    let pad = |mut v: Vec<f64>, w: f64| {
        while v.len() < field.len() {
            v.push(if v.len() == 3 { w } else { 0.0 });
        }
        v
    };
    match field.name.as_str() {
        "camera_pos" => pad(state.camera.eye.to_array().map(f64::from).to_vec(), 1.0),
        "light_pos" => pad(state.light_pos.to_array().map(f64::from).to_vec(), 1.0),
        "time" => pad(vec![f64::from(state.time)], 0.0),
        "frame" => pad(vec![f64::from(state.frame)], 0.0),
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
