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
    /// Segments of the profiled sessions (a slower and a faster half of each session of uneven
    /// motion, profile version 9) the exponent was fitted on, in place of their whole sessions.
    #[serde(default, skip_serializing_if = "is_zero")]
    pub segments: usize,
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
    /// Its slower and faster halves ([`segments`]; empty: none usable).
    pub segments: &'a [Segment],
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
    // Segments of one session (a slower and a faster half) stand for their profile where they
    // exist: they also tell how the error follows motion, from one session alone.
    let segmented = profiled.iter().any(|p| !p.segments.is_empty());
    let fit_input: Vec<Profiled> = with_motion
        .iter()
        .filter(|&&(i, _)| !segmented || profiled[i].segments.is_empty())
        .map(|&(i, m)| Profiled {
            motion: m,
            nodes: profiled[i].nodes,
        })
        .chain(profiled.iter().flat_map(|p| {
            p.segments.iter().map(|s| Profiled {
                motion: s.motion,
                nodes: &s.nodes,
            })
        }))
        .collect();
    let exponent = fit_exponent(|beta| cross_predictions(&fit_input, beta));
    let segments = profiled.iter().map(|p| p.segments.len()).sum();
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
        segments,
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

/// How `emit` sets the refresh period.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum PeriodChoice {
    /// One Δn for every frame: the fastest (node, Δn) under the budget on every session. The
    /// manifest's schedule is still written, for hosts that adapt.
    #[default]
    Fixed,
    /// Δn per frame from the manifest's schedule (`--adaptive`): the candidate whose schedule is
    /// predicted fastest over the frames of the target session, or of the profiled sessions
    /// ([`select_adaptive`]).
    Adaptive,
}

/// One profiled session for [`select_adaptive`].
#[derive(Debug, Clone, Copy)]
pub struct AdaptiveSession<'a> {
    /// Its mean motion, pixels per frame (`None`: the profile records none).
    pub motion: Option<f64>,
    pub nodes: &'a [NodeRecord],
    pub sets: &'a [SetRecord],
    pub hit_rate: &'a reproj_models::HitRateFit,
    /// The original shader's frame time there, ms.
    pub original_ms: f64,
}

/// What `emit --adaptive` predicted (`report.json`'s `adaptive`, report version 5).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct AdaptiveReport {
    /// Whose per-frame motion the candidates were predicted over: the target session's, or the
    /// profiled sessions' one after the other.
    pub trace: String,
    /// Frames of that trace.
    pub frames: usize,
    /// The shortest and longest Δn the chosen schedule gives its frames.
    pub delta_n_min: u32,
    pub delta_n_max: u32,
    /// The largest predicted error of one frame, and the mean over the frames.
    pub predicted_worst_error: f64,
    pub predicted_mean_error: f64,
    /// The fastest fixed choice under the same budget on the same sessions, for comparison:
    /// its name (`"root"`, a node id, a set's ids) and Δn, and its predicted speedup.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub fixed_node: Option<String>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub fixed_delta_n: Option<u32>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub fixed_predicted_speedup: Option<f64>,
    /// With `--verify`: the frames given the same Δn whose mean L2 error is the largest (each
    /// band of the schedule promises the budget).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub measured_worst_band: Option<BandError>,
}

/// The measured mean error of the frames one Δn was applied to.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct BandError {
    pub delta_n: u32,
    pub frames: u32,
    pub error: f64,
}

/// The candidate (node or set) whose run-time schedule is predicted fastest over `trace` (per-
/// frame motion, pixels per frame), each frame's error within the budget by construction of the
/// schedule ([`reproj_select::motion::predict_adaptive`]); ties keep the lower id. The original
/// when nothing is predicted faster than it. The choice's `delta_n` is the schedule's Δn at the
/// trace's median motion (the manifest's fixed default for hosts that do not adapt).
pub fn select_adaptive(
    sessions: &[AdaptiveSession<'_>],
    beta: f64,
    trace: &[f64],
    opts: &reproj_select::SelectOptions,
) -> (reproj_select::Selection, Option<AdaptiveReport>) {
    use reproj_select::motion::{ProfiledRecord, delta_n_in, predict_adaptive};
    use reproj_select::{Choice, OriginalReason, Selection};
    let Some(first) = sessions.first() else {
        return (
            Selection::Original {
                reason: OriginalReason::NoUsableNodes { skipped: 0 },
            },
            None,
        );
    };
    // Candidates: every node and set of the first profile, with its record in each session.
    let set_nodes: Vec<Vec<NodeRecord>> = sessions
        .iter()
        .map(|s| s.sets.iter().map(SetRecord::as_node).collect())
        .collect();
    let mut candidates: Vec<(Vec<u32>, Vec<ProfiledRecord<'_>>)> = Vec::new();
    for n in first.nodes {
        let found = |i: usize| {
            sessions[i]
                .nodes
                .iter()
                .find(|r| r.id == n.id && r.strategy == n.strategy)
        };
        candidates.push((Vec::new(), gather(sessions, &found)));
    }
    for set in first.sets {
        let found = |i: usize| {
            sessions[i]
                .sets
                .iter()
                .position(|r| r.members == set.members && r.strategy == set.strategy)
                .map(|p| &set_nodes[i][p])
        };
        candidates.push((set.members.clone(), gather(sessions, &found)));
    }
    let predictions: Vec<(usize, reproj_select::motion::AdaptivePrediction)> = candidates
        .iter()
        .enumerate()
        .filter(|(_, (_, r))| {
            !r.is_empty()
                && r.iter()
                    .all(|p| reproj_select::check_node(p.record).is_ok())
        })
        .filter_map(|(i, (_, r))| Some((i, predict_adaptive(r, beta, trace, opts)?)))
        .collect();
    let best = predictions.iter().min_by(|a, b| {
        a.1.predicted_ms.total_cmp(&b.1.predicted_ms).then(
            candidates[a.0].1[0]
                .record
                .id
                .cmp(&candidates[b.0].1[0].record.id),
        )
    });
    let Some((i, p)) = best else {
        return (
            Selection::Original {
                reason: OriginalReason::NoUsableNodes {
                    skipped: candidates.len(),
                },
            },
            None,
        );
    };
    let (members, records) = &candidates[*i];
    let record = records[0].record;
    let mut sorted: Vec<f64> = trace.iter().copied().filter(|m| m.is_finite()).collect();
    sorted.sort_by(f64::total_cmp);
    let median = sorted.get(sorted.len() / 2).copied().unwrap_or(0.0);
    let delta_n = delta_n_in(&p.schedule, median).unwrap_or(1);
    let report = AdaptiveReport {
        trace: String::new(),
        frames: trace.len(),
        delta_n_min: p.delta_n_per_frame.iter().copied().min().unwrap_or(1),
        delta_n_max: p.delta_n_per_frame.iter().copied().max().unwrap_or(1),
        predicted_worst_error: p.worst_error,
        predicted_mean_error: p.mean_error,
        fixed_node: None,
        fixed_delta_n: None,
        fixed_predicted_speedup: None,
        measured_worst_band: None,
    };
    if p.predicted_ms >= p.original_ms {
        return (
            Selection::Original {
                reason: OriginalReason::NotFaster {
                    best_ms: p.predicted_ms,
                    original_ms: p.original_ms,
                },
            },
            Some(report),
        );
    }
    let choice = Choice {
        node_id: record.id,
        node_text: record.text.clone(),
        strategy: record.strategy.clone(),
        delta_n,
        hit_rate: records[0].hit_rate.gamma(f64::from(delta_n)).unwrap_or(0.0),
        predicted_error: p.worst_error,
        predicted_ms: p.predicted_ms,
        original_ms: p.original_ms,
        predicted_speedup: p.predicted_speedup,
        predicted_speedup_ci95: None,
        members: members.clone(),
    };
    (Selection::Node(choice), Some(report))
}

/// A candidate's record in each session that has motion and the record (`find`).
fn gather<'b>(
    sessions: &'b [AdaptiveSession<'_>],
    find: &dyn Fn(usize) -> Option<&'b NodeRecord>,
) -> Vec<reproj_select::motion::ProfiledRecord<'b>> {
    sessions
        .iter()
        .enumerate()
        .filter_map(|(i, s)| {
            Some(reproj_select::motion::ProfiledRecord {
                motion: s.motion?,
                record: find(i)?,
                hit_rate: s.hit_rate,
                original_ms: s.original_ms,
            })
        })
        .collect()
}

/// The per-frame Δn a host applying `params`' schedule would use over `session` (its measured
/// motion, frame by frame); `None` without a schedule or when the motion cannot be measured.
pub fn adaptive_periods(params: &reproj_instance::Params, session: &Session) -> Option<Vec<u32>> {
    if params.schedule.is_empty() {
        return None;
    }
    let motion = measure(session, None)?;
    Some(
        motion
            .per_frame
            .iter()
            .map(|&m| params.delta_n_for(m))
            .collect(),
    )
}

/// One part of a profiled session's frames, as one more profile for the motion exponent: its mean
/// motion and each node's error model refitted on the part's own per-frame errors.
#[derive(Debug, Clone)]
pub struct Segment {
    pub motion: f64,
    pub nodes: Vec<NodeRecord>,
}

/// A node's record and its measurements' per-frame errors: (Δn, L2 error of each frame from 0).
pub type NodeFrames<'a> = (NodeRecord, Vec<(u32, &'a [f64])>);

/// Split one profile's replayed frames into a slower and a faster half by their motion
/// (`per_frame`, pixels per frame), leaving out the first `warmup` frames (the cache fills over
/// the first Δn frames), and refit each node on each half: per measured Δn, the mean of
/// `frame_errors` over the half's frames. `nodes`: each node's record with its measurements
/// (Δn, per-frame L2 errors from frame 0). Empty when the halves' motions differ by less than
/// [`reproj_models::motion::MIN_MOTION_RATIO`] (a session of even motion tells nothing) or
/// fewer than 4 frames remain.
pub fn segments(per_frame: &[f64], nodes: &[NodeFrames<'_>], warmup: usize) -> Vec<Segment> {
    let mut steady: Vec<usize> = (warmup.max(1)..per_frame.len())
        .filter(|&f| per_frame[f].is_finite())
        .collect();
    if steady.len() < 4 {
        return Vec::new();
    }
    steady.sort_by(|&a, &b| per_frame[a].total_cmp(&per_frame[b]));
    let (slow, fast) = steady.split_at(steady.len() / 2);
    let mean_motion =
        |fs: &[usize]| fs.iter().map(|&f| per_frame[f]).sum::<f64>() / fs.len() as f64;
    let (m_slow, m_fast) = (mean_motion(slow), mean_motion(fast));
    if !(m_slow >= STATIC_PIXELS && m_fast / m_slow >= reproj_models::motion::MIN_MOTION_RATIO) {
        return Vec::new();
    }
    [(m_slow, slow), (m_fast, fast)]
        .into_iter()
        .map(|(motion, frames)| Segment {
            motion,
            nodes: nodes
                .iter()
                .filter_map(|(record, measured)| {
                    let samples: Vec<(u32, f64)> = measured
                        .iter()
                        .filter_map(|&(dn, errors)| {
                            let v: Vec<f64> = frames
                                .iter()
                                .filter_map(|&f| errors.get(f).copied())
                                .filter(|e| e.is_finite())
                                .collect();
                            (v.len() * 2 >= frames.len())
                                .then(|| (dn, v.iter().sum::<f64>() / v.len() as f64))
                        })
                        .collect();
                    if samples.len() < 2 {
                        return None;
                    }
                    let fit_input: Vec<(f64, f64)> =
                        samples.iter().map(|&(d, e)| (f64::from(d), e)).collect();
                    Some(NodeRecord {
                        error: reproj_models::fit_error(
                            &fit_input,
                            &reproj_models::ErrorFitOptions::default(),
                        ),
                        measured_errors: samples,
                        ..record.clone()
                    })
                })
                .collect(),
        })
        .filter(|s| !s.nodes.is_empty())
        .collect()
}

/// [`segments`] of a profile for its records (the L2 error's: `frame_errors` are L2), with the
/// warm-up at the longest measured period (at most half the frames).
pub fn profile_segments(profile: &reproj_models::Profile, records: &[NodeRecord]) -> Vec<Segment> {
    let Some(motion) = &profile.motion else {
        return Vec::new();
    };
    let nodes: Vec<NodeFrames<'_>> = records
        .iter()
        .filter_map(|r| {
            let n = profile
                .nodes
                .iter()
                .find(|n| n.id == r.id && n.strategy == r.strategy)?;
            let measured: Vec<(u32, &[f64])> = n
                .measurements
                .iter()
                .filter(|m| !m.frame_errors.is_empty())
                .map(|m| (m.delta_n, &m.frame_errors[..]))
                .collect();
            (!measured.is_empty()).then(|| (r.clone(), measured))
        })
        .collect();
    let longest = nodes
        .iter()
        .flat_map(|(_, m)| m.iter().map(|p| p.0 as usize))
        .max()
        .unwrap_or(0);
    segments(
        &motion.per_frame,
        &nodes,
        longest.min(motion.per_frame.len() / 2),
    )
}

fn is_zero(n: &usize) -> bool {
    *n == 0
}

#[cfg(test)]
mod tests {
    use super::*;
    use reproj_models::{ErrorFitOptions, TimingFit, fit_error};

    /// A session whose second half moves three times as fast, its per-frame errors made with
    /// β = 1 (the cache ages with the distance moved): the two halves fit β near 1 from this one
    /// session; a session of even motion gives no segments.
    #[test]
    fn the_halves_of_one_session_of_uneven_motion_fit_the_exponent() {
        let error = |dn: u32, m: f64| 0.02 * (1.0 - (-0.05 * f64::from(dn - 1) * m).exp());
        let per_frame: Vec<f64> = (0..120).map(|f| if f < 60 { 1.0 } else { 3.0 }).collect();
        let periods = [2u32, 8, 16, 24, 32];
        let frame_errors: Vec<Vec<f64>> = periods
            .iter()
            .map(|&dn| per_frame.iter().map(|&m| error(dn, m)).collect())
            .collect();
        let whole: Vec<(f64, f64)> = periods
            .iter()
            .map(|&dn| (f64::from(dn), (error(dn, 1.0) + error(dn, 3.0)) / 2.0))
            .collect();
        let record = NodeRecord {
            id: 7,
            text: "n".into(),
            strategy: "3pass".into(),
            error: fit_error(&whole, &ErrorFitOptions::default()),
            timing: TimingFit::from_costs(1e-5, 2e-5, 0.5, 1000.0),
            mean_pixels: 1000.0,
            measured: None,
            measured_errors: whole.iter().map(|&(d, e)| (d as u32, e)).collect(),
        };
        let measured: Vec<(u32, &[f64])> = periods
            .iter()
            .zip(&frame_errors)
            .map(|(&dn, e)| (dn, &e[..]))
            .collect();
        let nodes = vec![(record.clone(), measured)];
        let segs = segments(&per_frame, &nodes, 1);
        assert_eq!(segs.len(), 2);
        assert!((segs[0].motion - 1.0).abs() < 1e-9 && (segs[1].motion - 3.0).abs() < 1e-9);
        let input: Vec<Profiled> = segs
            .iter()
            .map(|s| Profiled {
                motion: s.motion,
                nodes: &s.nodes,
            })
            .collect();
        let beta = fit_exponent(|b| cross_predictions(&input, b));
        assert_eq!(beta.source, ExponentSource::Fitted, "{beta:?}");
        assert!((beta.beta - 1.0).abs() <= 0.2, "{beta:?}");
        // Even motion: nothing to learn from halves.
        let even = vec![1.0; 120];
        assert!(segments(&even, &nodes, 32).is_empty());
        // Too few frames after the warm-up.
        assert!(segments(&per_frame, &nodes, 118).is_empty());
    }
}
