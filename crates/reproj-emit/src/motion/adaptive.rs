//! `emit --adaptive`: the node (or set) whose run-time schedule is predicted fastest over the
//! frames' motion ([`select_adaptive`]), and the per-frame Δn a host applies ([`adaptive_periods`]).

use reproj_scene::Session;
use reproj_select::{NodeRecord, SetRecord};
use serde::{Deserialize, Serialize};

use reproj_models::Profile;
use reproj_select::{SelectOptions, Selection};

use super::{TargetSession, measure};

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

/// `emit --adaptive`'s choice ([`select_adaptive`]) over the profiled sessions (`profiles`, each
/// with its records; `names` theirs), for the target session's per-frame motion when one is
/// given, else the profiled sessions' one after the other; the report names the fixed selection
/// it replaces (`fixed`) for comparison.
pub fn choose_adaptive(
    profiles: &[(&Profile, &[NodeRecord], &[SetRecord])],
    names: &[String],
    target: Option<&TargetSession>,
    beta: f64,
    opts: &SelectOptions,
    fixed: &Selection,
) -> (Selection, Option<AdaptiveReport>) {
    let sessions: Vec<AdaptiveSession<'_>> = profiles
        .iter()
        .map(|&(p, nodes, sets)| AdaptiveSession {
            motion: p.motion.as_ref().map(|m| m.pixels_per_frame),
            nodes,
            sets,
            hit_rate: &p.hit_rate,
            original_ms: p.original.frame_ms,
        })
        .collect();
    let frames_of = |m: &reproj_models::motion::Motion| {
        if m.per_frame.is_empty() {
            vec![m.pixels_per_frame]
        } else {
            m.per_frame.clone()
        }
    };
    let (trace, trace_name) = match target {
        Some(t) => (frames_of(&t.motion), t.name.clone()),
        None => (
            profiles
                .iter()
                .filter_map(|(p, _, _)| p.motion.as_ref())
                .flat_map(frames_of)
                .collect(),
            names.join(" + "),
        ),
    };
    let (chosen, mut report) = select_adaptive(&sessions, beta, &trace, opts);
    if let Some(r) = report.as_mut() {
        r.trace = trace_name;
        if let Selection::Node(f) = fixed {
            let root = profiles
                .first()
                .is_some_and(|(p, _, _)| p.nodes.iter().any(|n| n.id == f.node_id && n.root));
            r.fixed_node = Some(if !f.members.is_empty() {
                f.members
                    .iter()
                    .map(u32::to_string)
                    .collect::<Vec<_>>()
                    .join("+")
            } else if root {
                "root".into()
            } else {
                f.node_id.to_string()
            });
            r.fixed_delta_n = Some(f.delta_n);
            r.fixed_predicted_speedup = Some(f.predicted_speedup);
        }
    }
    (chosen, report)
}
