//! Selection over several sessions: a budget is a promise on every motion the user profiled.
//!
//! Each session's profile predicts every candidate — a node or a set, in a strategy, at a Δn — on
//! its own. A candidate counts only where every session predicts it; its error is the largest
//! of the sessions' and its speed the smallest speedup. The choice is the candidate with the
//! largest worst-case speedup whose worst-case error is within the budget, and the report gives
//! every session's prediction for it.

use std::collections::BTreeMap;

use reproj_models::HitRateFit;
use serde::{Deserialize, Serialize};

use crate::{
    Choice, NodeRecord, OriginalReason, Prediction, SelectOptions, Selection, SetRecord,
    check_node, predict, select_with_sets,
};

/// One profiled session: its records, hit-rate fit and original frame time.
#[derive(Debug, Clone, Copy)]
pub struct Scene<'a> {
    /// How reports name it (the session's file).
    pub name: &'a str,
    pub nodes: &'a [NodeRecord],
    pub sets: &'a [SetRecord],
    pub hit_rate: &'a HitRateFit,
    pub original_ms: f64,
}

/// What one session predicts for the chosen candidate.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ScenePrediction {
    pub session: String,
    pub predicted_error: f64,
    pub predicted_ms: f64,
    pub original_ms: f64,
    pub predicted_speedup: f64,
}

/// A candidate's identity across sessions: its members (one id for a node), strategy and Δn.
type Key = (Vec<u32>, String, u32);

/// Every prediction of one session, by candidate.
fn predictions(scene: &Scene, opts: &SelectOptions) -> BTreeMap<Key, (Prediction, String)> {
    let mut out = BTreeMap::new();
    let dns = opts.min_delta_n..=opts.max_delta_n;
    for node in scene.nodes.iter().filter(|n| check_node(n).is_ok()) {
        for dn in dns.clone() {
            if let Some(p) = predict(node, scene.hit_rate, dn) {
                out.insert(
                    (vec![node.id], node.strategy.clone(), dn),
                    (p, node.text.clone()),
                );
            }
        }
    }
    for set in scene.sets.iter().filter(|s| s.members.len() > 1) {
        let node = set.as_node();
        for dn in dns.clone() {
            if let Some(p) = predict(&node, scene.hit_rate, dn) {
                out.insert(
                    (set.members.clone(), set.strategy.clone(), dn),
                    (p, set.texts.join(" + ")),
                );
            }
        }
    }
    out
}

/// The candidates every scene predicts, each with its worst error, its worst speedup and the
/// index of the scene where it is slowest.
fn worst_cases<'k>(
    all: &'k [BTreeMap<Key, (Prediction, String)>],
    scenes: &[Scene],
) -> Vec<(&'k Key, f64, f64, usize)> {
    let mut common = Vec::new();
    for key in all[0].keys() {
        let per: Option<Vec<&(Prediction, String)>> = all.iter().map(|m| m.get(key)).collect();
        let Some(per) = per else { continue };
        let error = per
            .iter()
            .map(|(p, _)| p.predicted_error)
            .fold(f64::NEG_INFINITY, f64::max);
        let (slowest, speedup) = per
            .iter()
            .zip(scenes)
            .map(|((p, _), s)| s.original_ms / p.predicted_ms)
            .enumerate()
            .fold(
                (0, f64::INFINITY),
                |(bi, b), (i, x)| {
                    if x < b { (i, x) } else { (bi, b) }
                },
            );
        common.push((key, error, speedup, slowest));
    }
    common
}

/// The fastest candidate in the worst case whose error holds the budget on every scene, and every
/// scene's prediction for it (empty when the original is kept). With one scene this is
/// [`select_with_sets`].
pub fn select_worst_case(
    scenes: &[Scene],
    opts: &SelectOptions,
) -> (Selection, Vec<ScenePrediction>) {
    let [first, rest @ ..] = scenes else {
        return keep(OriginalReason::NoUsableNodes { skipped: 0 });
    };
    // The checks of the budget, the range and the fits are the single-session selector's.
    let single = select_with_sets(
        first.nodes,
        first.sets,
        first.hit_rate,
        first.original_ms,
        opts,
    );
    if rest.is_empty() {
        let per = match &single {
            Selection::Node(c) => vec![ScenePrediction {
                original_ms: c.original_ms,
                ..prediction(
                    first,
                    c.predicted_error,
                    c.predicted_ms,
                    c.predicted_speedup,
                )
            }],
            Selection::Original { .. } => Vec::new(),
        };
        return (single, per);
    }
    if let Selection::Original { reason } = &single
        && !matches!(
            reason,
            OriginalReason::OverBudget { .. }
                | OriginalReason::NotFaster { .. }
                | OriginalReason::NoUsableNodes { .. }
        )
    {
        return (single, Vec::new());
    }
    if scenes
        .iter()
        .any(|s| !(s.original_ms.is_finite() && s.original_ms > 0.0 && s.hit_rate.is_usable()))
    {
        return keep(OriginalReason::HitRateUnavailable);
    }
    let all: Vec<_> = scenes.iter().map(|s| predictions(s, opts)).collect();
    let common = worst_cases(&all, scenes);
    if common.is_empty() {
        return keep(OriginalReason::NoUsableNodes { skipped: 0 });
    }
    let best = common
        .iter()
        .filter(|(_, e, _, _)| opts.max_error.admits(*e))
        .max_by(|a, b| {
            a.2.total_cmp(&b.2)
                // Ties: fewer members, shorter Δn, lower ids (reversed: max_by keeps the last).
                .then(b.0.0.len().cmp(&a.0.0.len()))
                .then(b.0.2.cmp(&a.0.2))
                .then(b.0.0.cmp(&a.0.0))
        });
    let Some((key, error, speedup, slowest)) = best else {
        let lowest_error = common.iter().map(|c| c.1).fold(f64::INFINITY, f64::min);
        return keep(OriginalReason::OverBudget {
            max_error: opts.max_error.get(),
            lowest_error,
        });
    };
    let (worst, text) = &all[*slowest][*key];
    let worst_scene = &scenes[*slowest];
    if *speedup <= 1.0 {
        return keep(OriginalReason::NotFaster {
            best_ms: worst.predicted_ms,
            original_ms: worst_scene.original_ms,
        });
    }
    let per = all
        .iter()
        .zip(scenes)
        .map(|(m, s)| {
            let p = &m[*key].0;
            prediction(
                s,
                p.predicted_error,
                p.predicted_ms,
                s.original_ms / p.predicted_ms,
            )
        })
        .collect();
    let original_ms = worst_scene.original_ms;
    let choice = Choice {
        node_id: key.0[0],
        node_text: text.clone(),
        strategy: key.1.clone(),
        delta_n: key.2,
        hit_rate: worst.hit_rate,
        predicted_error: *error,
        predicted_ms: worst.predicted_ms,
        original_ms,
        predicted_speedup: *speedup,
        predicted_speedup_ci95: worst.rel_ci95.map(|[lo, hi]| [lo * speedup, hi * speedup]),
        members: if key.0.len() > 1 {
            key.0.clone()
        } else {
            Vec::new()
        },
    };
    (Selection::Node(choice), per)
}

/// The original kept, for `reason`, with no scene's prediction.
fn keep(reason: OriginalReason) -> (Selection, Vec<ScenePrediction>) {
    (Selection::Original { reason }, Vec::new())
}

/// A scene's prediction for the choice.
fn prediction(s: &Scene, error: f64, ms: f64, speedup: f64) -> ScenePrediction {
    ScenePrediction {
        session: s.name.to_string(),
        predicted_error: error,
        predicted_ms: ms,
        original_ms: s.original_ms,
        predicted_speedup: speedup,
    }
}
