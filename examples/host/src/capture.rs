//! `--capture`: what the engine drew in a frame, given to `reproj-runtime`'s `SessionCapture`.
//! An engine gives its own camera, model matrices, light and uniform values; this one's come
//! from the session it plays.

use reproj_runtime::{CapturedCamera, CapturedFrame};
use reproj_scene::Session;
use reproj_scene::session::UniformValue;

/// Frame `f` as the engine draws it: the camera, every object's model matrix, the light and the
/// session's plain uniform values (a struct's or an array of structs' entries are left as the
/// session has them).
pub fn frame(session: &Session, f: u32) -> CapturedFrame {
    let st = session.frame_state(f);
    let c = &st.camera;
    CapturedFrame {
        camera: CapturedCamera {
            eye: c.eye.to_array(),
            target: c.target.to_array(),
            up: c.up.to_array(),
            fov_y_deg: c.fov_y_deg,
            near: c.near,
            far: c.far,
        },
        objects: st.models.iter().map(|m| m.to_cols_array()).collect(),
        light: Some(st.light_pos.to_array()),
        uniforms: session
            .uniforms
            .iter()
            .filter(|(_, v)| matches!(v, UniformValue::Const(_) | UniformValue::Keys { .. }))
            .map(|(name, v)| (name.clone(), v.at(f as f32)))
            .collect(),
    }
}
