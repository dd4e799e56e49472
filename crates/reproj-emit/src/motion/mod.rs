//! Motion: how fast a session moves on screen, from its geometry, transforms and camera alone (no
//! rendering, no GPU: [`measure`], here), and what `emit` does with it — [`carry`] takes the
//! records to a session of other motion (`carry.rs`), [`select_adaptive`] chooses for a Δn that
//! follows the motion frame by frame (`adaptive.rs`), and [`segments`] splits a session of uneven
//! motion into halves so that one session can fit the motion exponent (`segments.rs`).
//!
//! Per frame, a sample of each object's vertices (at most [`SAMPLES_PER_OBJECT`]) is projected
//! with this frame's and the previous frame's transforms; a vertex counts where it is on screen
//! and faces the camera now (it stands for the visible surface). The figures are the mean
//! on-screen distance it moved, in pixels, and how far the directions from it to the camera and
//! to the light turned in the object's own frame, in degrees.

mod adaptive;
mod carry;
mod segments;

pub use adaptive::{
    AdaptiveReport, AdaptiveSession, BandError, PeriodChoice, adaptive_periods, choose_adaptive,
    select_adaptive,
};
pub use carry::{
    Carried, MotionReport, ProfiledSession, SessionMotion, TargetSession, carry, manifest_schedule,
};
pub use segments::{NodeFrames, Segment, profile_segments, segments};

use glam::{Mat3, Mat4, Vec3};
use reproj_models::motion::Motion;

use reproj_scene::Session;
use reproj_scene::session::{Cull, FrameState};

/// Vertices sampled per object (evenly through its vertex list).
pub const SAMPLES_PER_OBJECT: usize = 2000;

/// Measure `session`'s motion over its first `frames` frames (all: `None`). An object whose mesh
/// cannot be built is left out; `None` when nothing could be sampled.
pub fn measure(session: &Session, frames: Option<u32>) -> Option<Motion> {
    let frames = frames.map_or(session.frames, |f| f.min(session.frames));
    // Per object: its index (for its transform), sampled (position, normal), two-sided.
    type Sampled = (usize, Vec<(Vec3, Vec3)>, bool);
    let objects: Vec<Sampled> = session
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
    if objects.iter().all(|(_, p, _)| p.is_empty()) {
        return None;
    }
    let [w, h] = session.resolution.map(|v| v as f32);
    let mut per_frame = vec![0.0f64; frames as usize];
    let (mut view_sum, mut light_sum, mut counted) = (0.0f64, 0.0f64, 0u32);
    let mut prev = session.frame_state(0);
    for f in 1..frames {
        let now = session.frame_state(f);
        let (mut px, mut view, mut light, mut n) = (0.0f64, 0.0f64, 0.0f64, 0u64);
        for (i, points, two_sided) in &objects {
            let (m1, m0) = (now.models[*i], prev.models[*i]);
            let (inv1, inv0) = (m1.inverse(), m0.inverse());
            let normal1 = Mat3::from_mat4(inv1).transpose();
            // Camera and light in the object's frame, now and before.
            let eye1 = inv1.transform_point3(now.camera.eye);
            let eye0 = inv0.transform_point3(prev.camera.eye);
            let light1 = inv1.transform_point3(now.light_pos);
            let light0 = inv0.transform_point3(prev.light_pos);
            for &(p, normal) in points {
                let Some(s1) = screen(&now, m1, p, [w, h]) else {
                    continue;
                };
                let world = m1.transform_point3(p);
                if !two_sided && (normal1 * normal).dot(now.camera.eye - world) <= 0.0 {
                    continue;
                }
                let Some(s0) = screen(&prev, m0, p, [w, h]) else {
                    continue;
                };
                px += f64::from((s1 - s0).length());
                view += angle_deg(eye1 - p, eye0 - p);
                light += angle_deg(light1 - p, light0 - p);
                n += 1;
            }
        }
        if n > 0 {
            let n = n as f64;
            per_frame[f as usize] = px / n;
            view_sum += view / n;
            light_sum += light / n;
            counted += 1;
        }
        prev = now;
    }
    let frames = f64::from(counted.max(1));
    let pixels = per_frame.iter().sum::<f64>() / frames;
    Some(Motion {
        pixels_per_frame: pixels,
        per_frame,
        view_deg_per_frame: view_sum / frames,
        light_deg_per_frame: light_sum / frames,
    })
}

/// Pixel position of object-space point `p` at frame state `st`; `None` behind the camera or off
/// screen.
fn screen(st: &FrameState, model: Mat4, p: Vec3, [w, h]: [f32; 2]) -> Option<glam::Vec2> {
    let clip = st.camera.view_proj * model * p.extend(1.0);
    if clip.w <= 1e-6 {
        return None;
    }
    let ndc = clip.truncate() / clip.w;
    if ndc.x.abs() > 1.0 || ndc.y.abs() > 1.0 {
        return None;
    }
    Some(glam::Vec2::new(
        (ndc.x + 1.0) * 0.5 * w,
        (1.0 - ndc.y) * 0.5 * h,
    ))
}

/// The angle between two directions, degrees (0 when either is degenerate).
fn angle_deg(a: Vec3, b: Vec3) -> f64 {
    let (a, b) = (a.normalize_or_zero(), b.normalize_or_zero());
    if a == Vec3::ZERO || b == Vec3::ZERO {
        return 0.0;
    }
    // atan2 of sine and cosine: exact near 0, where acos of a rounded dot product is not.
    f64::from(a.cross(b).length().atan2(a.dot(b)).to_degrees())
}
