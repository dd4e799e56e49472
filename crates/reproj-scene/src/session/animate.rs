//! Animation: the scene at a frame, from linearly interpolated key frames and orbits.

use glam::{Mat4, Quat, Vec3};

use super::*;

impl Scale {
    fn vec(self) -> Vec3 {
        match self {
            Scale::Uniform(s) => Vec3::splat(s),
            Scale::PerAxis(v) => Vec3::from(v),
        }
    }
}

/// Camera state of one frame.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CameraState {
    pub eye: Vec3,
    pub target: Vec3,
    pub up: Vec3,
    pub fov_y_deg: f32,
    pub near: f32,
    pub far: f32,
    pub view: Mat4,
    pub proj: Mat4,
    pub view_proj: Mat4,
}

/// Everything the scene contributes to one frame.
#[derive(Debug, Clone)]
pub struct FrameState {
    pub frame: u32,
    /// Seconds since frame 0: `frame / fps`.
    pub time: f32,
    pub camera: CameraState,
    pub light_pos: Vec3,
    /// Model matrix of each object, in `geometry.objects` order.
    pub models: Vec<Mat4>,
}

/// Interpolation position within a sorted list of key frames: (index a, index b, t).
fn segment(frames: &[f32], f: f32) -> (usize, usize, f32) {
    let n = frames.len();
    if n == 1 || f <= frames[0] {
        return (0, 0, 0.0);
    }
    if f >= frames[n - 1] {
        return (n - 1, n - 1, 0.0);
    }
    let mut i = 0;
    while i + 1 < n && frames[i + 1] <= f {
        i += 1;
    }
    if i + 1 >= n {
        return (n - 1, n - 1, 0.0);
    }
    let span = frames[i + 1] - frames[i];
    let t = if span > 0.0 {
        (f - frames[i]) / span
    } else {
        0.0
    };
    (i, i + 1, t)
}

fn lerp3(a: [f32; 3], b: [f32; 3], t: f32) -> Vec3 {
    Vec3::from(a).lerp(Vec3::from(b), t)
}

fn rotation_quat(r: &Option<Rotation>) -> Quat {
    match r {
        None => Quat::IDENTITY,
        Some(Rotation::AxisAngle { axis, deg }) => {
            let a = Vec3::from(*axis);
            if a.length_squared() == 0.0 {
                Quat::IDENTITY
            } else {
                Quat::from_axis_angle(a.normalize(), deg.to_radians())
            }
        }
        Some(Rotation::EulerDeg(e)) => Quat::from_euler(
            glam::EulerRot::ZYX,
            e[2].to_radians(),
            e[1].to_radians(),
            e[0].to_radians(),
        ),
    }
}

fn rotation_lerp(a: &Option<Rotation>, b: &Option<Rotation>, t: f32) -> Quat {
    if t == 0.0 {
        return rotation_quat(a);
    }
    match (a, b) {
        (
            Some(Rotation::AxisAngle { axis: xa, deg: da }),
            Some(Rotation::AxisAngle { axis: xb, deg: db }),
        ) => rotation_quat(&Some(Rotation::AxisAngle {
            axis: lerp3(*xa, *xb, t).into(),
            deg: da + (db - da) * t,
        })),
        (Some(Rotation::EulerDeg(ea)), Some(Rotation::EulerDeg(eb))) => {
            rotation_quat(&Some(Rotation::EulerDeg(lerp3(*ea, *eb, t).into())))
        }
        (None, Some(Rotation::AxisAngle { axis, deg })) => {
            rotation_quat(&Some(Rotation::AxisAngle {
                axis: *axis,
                deg: deg * t,
            }))
        }
        (Some(Rotation::AxisAngle { axis, deg }), None) => {
            rotation_quat(&Some(Rotation::AxisAngle {
                axis: *axis,
                deg: deg * (1.0 - t),
            }))
        }
        (None, Some(Rotation::EulerDeg(e))) => {
            rotation_quat(&Some(Rotation::EulerDeg((Vec3::from(*e) * t).into())))
        }
        (Some(Rotation::EulerDeg(e)), None) => rotation_quat(&Some(Rotation::EulerDeg(
            (Vec3::from(*e) * (1.0 - t)).into(),
        ))),
        _ => rotation_quat(a).slerp(rotation_quat(b), t),
    }
}

impl TransformKey {
    /// The key's model matrix: its `matrix` as given, or translate · rotate · scale.
    fn model(&self) -> Mat4 {
        match &self.matrix {
            Some(m) => Mat4::from_cols_array(m),
            None => Mat4::from_scale_rotation_translation(
                self.scale.vec(),
                rotation_quat(&self.rotation),
                Vec3::from(self.translation),
            ),
        }
    }
}

impl Transform {
    /// Model matrix at a (fractional) frame index. On a key it is the key's matrix exactly;
    /// between keys the parameters are interpolated, or, where either key is a `matrix`, both
    /// are taken apart into scale, rotation and translation and those interpolated (slerp).
    pub fn matrix(&self, frame: f32) -> Mat4 {
        let frames: Vec<f32> = self.keys.iter().map(|k| k.frame).collect();
        let (i, j, t) = segment(&frames, frame);
        let (a, b) = (&self.keys[i], &self.keys[j]);
        if a.matrix.is_some() || b.matrix.is_some() {
            if t == 0.0 {
                return a.model();
            }
            let (sa, ra, ta) = a.model().to_scale_rotation_translation();
            let (sb, rb, tb) = b.model().to_scale_rotation_translation();
            return Mat4::from_scale_rotation_translation(
                sa.lerp(sb, t),
                ra.slerp(rb, t),
                ta.lerp(tb, t),
            );
        }
        let tr = lerp3(a.translation, b.translation, t);
        let sc = a.scale.vec().lerp(b.scale.vec(), t);
        let rot = rotation_lerp(&a.rotation, &b.rotation, t);
        Mat4::from_scale_rotation_translation(sc, rot, tr)
    }
}

fn orbit_angle(start: f32, end: f32, frame: f32, frames: u32) -> f32 {
    let last = frames.saturating_sub(1).max(1) as f32;
    let t = (frame / last).clamp(0.0, 1.0);
    (start + (end - start) * t).to_radians()
}

impl PointPath {
    /// Position at a frame.
    pub fn position(&self, frame: f32, frames: u32) -> Vec3 {
        match self {
            PointPath::Keys(keys) => {
                let fs: Vec<f32> = keys.iter().map(|k| k.frame).collect();
                let (i, j, t) = segment(&fs, frame);
                lerp3(keys[i].position, keys[j].position, t)
            }
            PointPath::Orbit(o) => {
                let a = orbit_angle(o.start_deg, o.end_deg, frame, frames);
                Vec3::from(o.center) + Vec3::new(o.radius * a.cos(), o.height, o.radius * a.sin())
            }
        }
    }
}

impl CameraPath {
    /// Camera at a frame, for an image of `aspect` = width / height.
    pub fn state(&self, frame: f32, frames: u32, aspect: f32) -> CameraState {
        let (eye, target, up, fov, near, far) = match self {
            CameraPath::Keys(keys) => {
                let fs: Vec<f32> = keys.iter().map(|k| k.frame).collect();
                let (i, j, t) = segment(&fs, frame);
                let (a, b) = (&keys[i], &keys[j]);
                (
                    lerp3(a.eye, b.eye, t),
                    lerp3(a.target, b.target, t),
                    lerp3(a.up, b.up, t),
                    a.fov_y_deg + (b.fov_y_deg - a.fov_y_deg) * t,
                    a.near + (b.near - a.near) * t,
                    a.far + (b.far - a.far) * t,
                )
            }
            // Replaced by keys when the session is loaded (`crate::gltf::expand`); a session
            // built by hand with it gets a camera at +Z looking at the origin.
            CameraPath::Gltf => (
                Vec3::new(0.0, 0.0, 3.0),
                Vec3::ZERO,
                Vec3::Y,
                45.0,
                0.1,
                100.0,
            ),
            CameraPath::Orbit(o) => {
                let a = orbit_angle(o.start_deg, o.end_deg, frame, frames);
                let c = Vec3::from(o.center);
                (
                    c + Vec3::new(o.radius * a.cos(), o.height, o.radius * a.sin()),
                    c,
                    Vec3::from(o.up),
                    o.fov_y_deg,
                    o.near,
                    o.far,
                )
            }
        };
        let view = glam::camera::rh::view::look_at_mat4(eye, target, up);
        let proj =
            glam::camera::rh::proj::directx::perspective(fov.to_radians(), aspect, near, far);
        CameraState {
            eye,
            target,
            up,
            fov_y_deg: fov,
            near,
            far,
            view,
            proj,
            view_proj: proj * view,
        }
    }
}

impl UniformValue {
    /// Value at a frame, flattened (see [`Value::flatten`]); empty for a struct or an array of
    /// structs, whose leaves are looked up one by one ([`UniformValue::lookup`]).
    pub fn at(&self, frame: f32) -> Vec<f64> {
        match self {
            UniformValue::Struct(_) | UniformValue::Array(_) => Vec::new(),
            UniformValue::Const(v) => v.flatten(),
            UniformValue::Keys { keys } => {
                let fs: Vec<f32> = keys.iter().map(|k| k.frame).collect();
                let (i, j, t) = segment(&fs, frame);
                let a = keys[i].value.flatten();
                let b = keys[j].value.flatten();
                a.iter()
                    .zip(b.iter())
                    .map(|(x, y)| x + (y - x) * t as f64)
                    .collect()
            }
        }
    }

    /// Number of components (of the first key for key-framed values; 0 for a struct or an array
    /// of structs).
    pub fn len(&self) -> usize {
        match self {
            UniformValue::Struct(_) | UniformValue::Array(_) => 0,
            UniformValue::Const(v) => v.flatten().len(),
            UniformValue::Keys { keys } => {
                keys.first().map(|k| k.value.flatten().len()).unwrap_or(0)
            }
        }
    }

    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }
}

impl Session {
    /// The view-projection depth pass `pass` draws frame `state` with (column-major values; a
    /// value of the wrong length, which validation rejects, gives the identity).
    pub fn depth_view_proj(&self, pass: &DepthPass, state: &FrameState) -> Mat4 {
        let value = match &pass.view_proj {
            ViewProj::Camera => return state.camera.view_proj,
            ViewProj::Uniform(u) => self.uniform(u),
            ViewProj::Matrix(m) => Some(m),
        };
        let v: Vec<f32> = value
            .map(|v| v.at(state.frame as f32))
            .unwrap_or_default()
            .into_iter()
            .map(|x| x as f32)
            .collect();
        match <[f32; 16]>::try_from(v.as_slice()) {
            Ok(cols) => Mat4::from_cols_array(&cols),
            Err(_) => Mat4::IDENTITY,
        }
    }

    /// Width / height.
    pub fn aspect(&self) -> f32 {
        self.resolution[0] as f32 / self.resolution[1] as f32
    }

    /// The scene at frame `frame` (any index; paths clamp outside their keys).
    pub fn frame_state(&self, frame: u32) -> FrameState {
        let f = frame as f32;
        FrameState {
            frame,
            time: f / self.fps,
            camera: self.camera.state(f, self.frames, self.aspect()),
            light_pos: self.light.position(f, self.frames),
            models: self
                .geometry
                .objects
                .iter()
                .map(|o| o.transform.matrix(f))
                .collect(),
        }
    }
}
