//! How fast a session moves on screen, from its geometry, transforms and camera alone (no
//! rendering, no GPU): the input of the motion-aware error model (`reproj_models::motion`); and
//! [`carry`], which takes `emit`'s records to a session of other motion.
//!
//! Per frame, a sample of each object's vertices (at most [`SAMPLES_PER_OBJECT`]) is projected
//! with this frame's and the previous frame's transforms; a vertex counts where it is on screen
//! and faces the camera now (it stands for the visible surface). The figures are the mean
//! on-screen distance it moved, in pixels, and how far the directions from it to the camera and
//! to the light turned in the object's own frame, in degrees.

use glam::{Mat3, Mat4, Vec3};
use reproj_models::motion::{
    ExponentSource, Motion, MotionExponent, MotionRange, STATIC_PIXELS, fit_exponent, period_scale,
};
use reproj_select::motion::{Profiled, cross_predictions};
use reproj_select::{NodeRecord, SetRecord};
use serde::{Deserialize, Serialize};

use reproj_replay::Session;
use reproj_replay::session::{Cull, FrameState};

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
            let mesh = reproj_replay::mesh::build(session, &o.mesh).ok()?;
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

/// The session a variant is meant for, when it is not one of the profiled ones (`emit --verify
/// --session NEW`): its name and motion.
#[derive(Debug, Clone)]
pub struct TargetSession {
    pub name: String,
    /// Its content hash (`reproj_models::content_hash` of the file): the same file as a profiled
    /// session needs no carrying over.
    pub hash: String,
    pub motion: Motion,
}

/// One session's motion as `emit` reports it.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SessionMotion {
    pub session: String,
    pub pixels_per_frame: f64,
    pub view_deg_per_frame: f64,
}

/// What `emit` knew of motion (`report.json`'s `motion`, report version 4).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct MotionReport {
    /// Each profiled session's motion (`null` entries are left out: profiles before version 8).
    pub profiled: Vec<SessionMotion>,
    /// The session the choice was carried to, when one was given that no profile covers.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub target: Option<SessionMotion>,
    /// The profile it was carried from (the nearest in motion) and the factor on the period's
    /// age, `r = (target / profiled)^β`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub carried_from: Option<String>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub period_scale: Option<f64>,
    /// The motion exponent, where it came from, and what it rests on.
    pub exponent: MotionExponent,
    /// The target's predicted error for the choice (in the budget's metric), before rendering.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub target_predicted_error: Option<f64>,
    /// Said to the user: a target outside the profiled motions, an assumed exponent.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub warnings: Vec<String>,
}

/// One profiled session for [`carry`]: its name, content hash, motion and records.
#[derive(Debug, Clone, Copy)]
pub struct ProfiledSession<'a> {
    pub name: &'a str,
    pub hash: &'a str,
    pub motion: Option<&'a Motion>,
    pub nodes: &'a [NodeRecord],
    pub sets: &'a [SetRecord],
}

/// A profile's records carried to the target's motion: the extra scene `emit` selects over.
#[derive(Debug, Clone)]
pub struct Carried {
    /// Index of the profiled session it comes from.
    pub from: usize,
    pub nodes: Vec<NodeRecord>,
    pub sets: Vec<SetRecord>,
}

/// Fit the motion exponent across the profiled sessions, and carry the nearest one (in log
/// motion) to `target` when it is given and is none of them. The report says what was done and
/// warns where the prediction rests on less than a measurement: a target outside the profiled
/// motions, an exponent assumed rather than fitted, a profile without motion.
pub fn carry(
    profiled: &[ProfiledSession<'_>],
    target: Option<&TargetSession>,
) -> (MotionReport, Option<Carried>) {
    let with_motion: Vec<(usize, f64)> = profiled
        .iter()
        .enumerate()
        .filter_map(|(i, p)| Some((i, p.motion?.pixels_per_frame)))
        .collect();
    let fit_input: Vec<Profiled> = with_motion
        .iter()
        .map(|&(i, m)| Profiled {
            motion: m,
            nodes: profiled[i].nodes,
        })
        .collect();
    let exponent = fit_exponent(|beta| cross_predictions(&fit_input, beta));
    let mut report = MotionReport {
        profiled: profiled
            .iter()
            .filter_map(|p| {
                Some(SessionMotion {
                    session: p.name.to_string(),
                    pixels_per_frame: p.motion?.pixels_per_frame,
                    view_deg_per_frame: p.motion?.view_deg_per_frame,
                })
            })
            .collect(),
        target: None,
        carried_from: None,
        period_scale: None,
        exponent,
        target_predicted_error: None,
        warnings: Vec::new(),
    };
    let Some(target) = target else {
        return (report, None);
    };
    if profiled.iter().any(|p| p.hash == target.hash) {
        return (report, None);
    }
    report.target = Some(SessionMotion {
        session: target.name.clone(),
        pixels_per_frame: target.motion.pixels_per_frame,
        view_deg_per_frame: target.motion.view_deg_per_frame,
    });
    let m = target.motion.pixels_per_frame;
    let log_distance = |p: f64| (p.max(STATIC_PIXELS) / m.max(STATIC_PIXELS)).ln().abs();
    let Some(&(from, from_motion)) = with_motion
        .iter()
        .min_by(|a, b| log_distance(a.1).total_cmp(&log_distance(b.1)))
    else {
        report.warnings.push(format!(
            "the profile records no motion (made before profile version 8): {} cannot be predicted for its own motion; re-run `reproj analyze`",
            target.name
        ));
        return (report, None);
    };
    let range = MotionRange::of(with_motion.iter().map(|p| p.1)).expect("one motion at least");
    if !range.covers(m) {
        report.warnings.push(format!(
            "{} moves {m:.2} px/frame, outside the profiled {:.2}–{:.2} px/frame: its prediction is carried beyond what was measured; profile a session like it (`analyze --session`) to be sure",
            target.name,
            range.min,
            range.max
        ));
    }
    if report.exponent.source == ExponentSource::Assumed
        && log_distance(from_motion) > 0.1f64.ln_1p()
    {
        report.warnings.push(
            "how the error follows motion is assumed (β = 1: proportional), not fitted: profile two sessions of different motion to fit it"
                .into(),
        );
    }
    let r = period_scale(from_motion, m, report.exponent.beta);
    let source = &profiled[from];
    report.carried_from = Some(source.name.to_string());
    report.period_scale = Some(r);
    let carried = Carried {
        from,
        nodes: source.nodes.iter().map(|n| n.at_motion(r)).collect(),
        sets: source.sets.iter().map(|s| s.at_motion(r)).collect(),
    };
    (report, Some(carried))
}

/// The manifest's run-time Δn schedule (`params.schedule`) for a chosen node or set, from its
/// record in each profiled session (`per_profile`: that profile's motion and record, either
/// missing where the profile lacks it) and the motion exponent `beta`
/// ([`reproj_select::motion::schedule`]).
pub fn manifest_schedule(
    per_profile: impl IntoIterator<Item = (Option<f64>, Option<NodeRecord>)>,
    beta: f64,
    opts: &reproj_select::SelectOptions,
) -> Vec<reproj_instance::DeltaNBand> {
    let found: Vec<(f64, NodeRecord)> = per_profile
        .into_iter()
        .filter_map(|(m, r)| Some((m?, r?)))
        .collect();
    let refs: Vec<(f64, &NodeRecord)> = found.iter().map(|(m, r)| (*m, r)).collect();
    reproj_select::motion::schedule(&refs, beta, opts)
        .into_iter()
        .map(|(up_to, delta_n)| reproj_instance::DeltaNBand {
            up_to_pixels_per_frame: up_to,
            delta_n,
        })
        .collect()
}
