//! The choice of `emit`: the fastest (node or set, Δn) whose predicted error holds on every
//! profiled session — and on a target session whose motion is carried from them — at a fixed Δn or
//! on an adaptive schedule.

use reproj_models::{Metric, Profile};
use reproj_select::{
    NodeRecord, Scene, ScenePrediction, SelectOptions, Selection, SetRecord, select_with_sets,
    select_worst_case,
};

use crate::EmitOptions;
use crate::motion::{AdaptiveReport, MotionReport, PeriodChoice, ProfiledSession, Segment};

/// A profile with its nodes and sets as the selector's records.
pub(super) type Records<'p> = (&'p Profile, Vec<NodeRecord>, Vec<SetRecord>);

/// What [`choose`] decided, and what the report says of it.
pub(super) struct Chosen {
    pub(super) selection: Selection,
    /// Each session's prediction for the choice (empty with one session).
    pub(super) sessions: Vec<ScenePrediction>,
    pub(super) motion: Option<MotionReport>,
    pub(super) adaptive: Option<AdaptiveReport>,
}

/// Choose across `all` (the profile `emit` was given first, then `--also`'s), named `names`.
pub(super) fn choose(
    all: &[Records<'_>],
    names: &[String],
    opts: &EmitOptions,
    select_opts: &SelectOptions,
) -> Chosen {
    // Each session's slower and faster halves (per-frame L2 errors, profile version 9).
    let segments: Vec<Vec<Segment>> = all
        .iter()
        .map(|(p, nodes, _)| match opts.metric {
            Metric::L2 => crate::motion::profile_segments(p, nodes),
            Metric::Flip => Vec::new(),
        })
        .collect();
    let profiled: Vec<ProfiledSession> = all
        .iter()
        .zip(names)
        .zip(&segments)
        .map(|(((p, nodes, sets), name), segments)| ProfiledSession {
            name,
            hash: &p.session.hash,
            motion: p.motion.as_ref(),
            nodes,
            sets,
            segments,
        })
        .collect();
    let (mut motion, carried) = crate::motion::carry(&profiled, opts.target.as_ref());
    let target_name = opts
        .target
        .as_ref()
        .map(|t| format!("{} (carried)", t.name));
    let mut scenes: Vec<Scene> = all
        .iter()
        .zip(names)
        .map(|((p, nodes, sets), name)| Scene {
            name,
            nodes,
            sets,
            hit_rate: &p.hit_rate,
            original_ms: p.original.frame_ms,
        })
        .collect();
    if let (Some(c), Some(name)) = (&carried, &target_name) {
        let from = scenes[c.from];
        scenes.push(Scene {
            name,
            nodes: &c.nodes,
            sets: &c.sets,
            ..from
        });
    }
    let (selection, sessions) = if scenes.len() == 1 {
        let (p, nodes, sets) = &all[0];
        let selection =
            select_with_sets(nodes, sets, &p.hit_rate, p.original.frame_ms, select_opts);
        (selection, Vec::new())
    } else {
        select_worst_case(&scenes, select_opts)
    };
    let (selection, adaptive) = match opts.period {
        PeriodChoice::Fixed => (selection, None),
        PeriodChoice::Adaptive => {
            let profiles: Vec<(&Profile, &[NodeRecord], &[SetRecord])> =
                all.iter().map(|(p, n, s)| (*p, &n[..], &s[..])).collect();
            crate::motion::choose_adaptive(
                &profiles,
                names,
                opts.target.as_ref(),
                motion.exponent.beta,
                select_opts,
                &selection,
            )
        }
    };
    if let Some(name) = &target_name {
        motion.target_predicted_error = sessions
            .iter()
            .find(|s| s.session == *name)
            .map(|s| s.predicted_error);
        if let Some(a) = &adaptive {
            // The target's whole-session error, as --verify measures it: the frames' mean.
            motion.target_predicted_error = Some(a.predicted_mean_error);
        }
    }
    let motion = (!motion.profiled.is_empty() || motion.target.is_some()).then_some(motion);
    Chosen {
        selection,
        sessions,
        motion,
        adaptive,
    }
}
