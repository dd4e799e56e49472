//! The engine's own measure of a frame's motion, for the manifest's run-time Δn schedule: the
//! mean on-screen distance, in pixels, that a visible surface point moved since the previous
//! frame. A sample of each object's vertices is projected with this frame's and the previous
//! frame's transforms; a vertex counts where it is on screen now and faces the camera (two-sided
//! objects: always). This is the definition the schedule's bands are in (`manifest.json`
//! `params.schedule`, SCHEMAS.md), so an engine computes it from what it already has: its
//! meshes, model matrices and camera.

use glam::{Mat3, Mat4, Vec2, Vec3};
use reproj_scene::session::{Cull, FrameState, Session};

/// Vertices sampled per object (evenly through its vertex list), as reproj measures sessions.
const SAMPLES_PER_OBJECT: usize = 2000;

/// One object's sample: its index in the session, sampled (position, normal), two-sided.
type Sampled = (usize, Vec<(Vec3, Vec3)>, bool);

/// Sampled vertices of each drawn object.
pub struct MotionProbe {
    objects: Vec<Sampled>,
    size: Vec2,
}

impl MotionProbe {
    pub fn new(session: &Session) -> MotionProbe {
        let objects = session
            .geometry
            .objects
            .iter()
            .enumerate()
            .filter_map(|(i, o)| {
                let mesh = reproj_scene::mesh::build(session, &o.mesh).ok()?;
                let step = mesh.vertices.len().div_ceil(SAMPLES_PER_OBJECT).max(1);
                let points = mesh
                    .vertices
                    .iter()
                    .step_by(step)
                    .map(|v| (Vec3::from(v.position), Vec3::from(v.normal)))
                    .collect();
                Some((i, points, o.cull == Cull::None))
            })
            .collect();
        let [w, h] = session.resolution;
        MotionProbe {
            objects,
            size: Vec2::new(w as f32, h as f32),
        }
    }

    /// Pixels per frame from `prev` to `now` (0 when nothing visible was sampled).
    pub fn pixels(&self, prev: &FrameState, now: &FrameState) -> f64 {
        let (mut sum, mut n) = (0.0f64, 0u64);
        for (i, points, two_sided) in &self.objects {
            let (m1, m0) = (now.models[*i], prev.models[*i]);
            let normal1 = Mat3::from_mat4(m1.inverse()).transpose();
            for &(p, normal) in points {
                let Some(s1) = self.screen(now, m1, p) else {
                    continue;
                };
                let world = m1.transform_point3(p);
                if !two_sided && (normal1 * normal).dot(now.camera.eye - world) <= 0.0 {
                    continue;
                }
                let Some(s0) = self.screen(prev, m0, p) else {
                    continue;
                };
                sum += f64::from((s1 - s0).length());
                n += 1;
            }
        }
        if n == 0 { 0.0 } else { sum / n as f64 }
    }

    fn screen(&self, st: &FrameState, model: Mat4, p: Vec3) -> Option<Vec2> {
        let clip = st.camera.view_proj * model * p.extend(1.0);
        if clip.w <= 1e-6 {
            return None;
        }
        let ndc = clip.truncate() / clip.w;
        if ndc.x.abs() > 1.0 || ndc.y.abs() > 1.0 {
            return None;
        }
        Some(Vec2::new(
            (ndc.x + 1.0) * 0.5 * self.size.x,
            (1.0 - ndc.y) * 0.5 * self.size.y,
        ))
    }
}
