//! Selection (paper §4.5): under an error budget ε_max, pick the cached node and refresh period Δn
//! with the lowest predicted frame time, or keep the original shader and say why.
//!
//! Pure arithmetic on the fitted models of `reproj-models` (no GPU, milliseconds), so a designer can
//! sweep budgets interactively. For every node whose fits are usable and every integer Δn in
//! `min_delta_n..=max_delta_n` we predict the error `ε̂(Δn)` (eq. 2) and the frame time
//! `t̂(Δn) = E[overhead] + M·(γ·E[hit] + (1 − γ)·E[miss])` (eq. 4-5); the choice is the lowest
//! `t̂` with `ε̂ ≤ ε_max` that beats the original, ties broken by lower Δn then lower node id.
//! [`pareto`] gives the error-vs-time frontier of the same predictions, for charts.

mod budget;
pub mod combine;
mod measured;
pub mod motion;
mod records;
mod worst;

pub use budget::{Budget, DELTA_N_RANGE, InvalidBudget};
pub use combine::{SetPrediction, best_set, combined_timing, predict_set};
pub use measured::{
    Calibration, MeasuredBound, RaceLine, RacePoint, calibration, measured_errors, predicted_error,
    respect_measurements,
};
pub use records::{ProfileRecords, profile_records};
pub use worst::{Scene, ScenePrediction, select_worst_case};

use reproj_models::{ErrorFitFailure, ErrorFitStatus, HitRateFit, TimingFit, predicted_frame_ms};
use serde::{Deserialize, Serialize};

/// Default largest refresh period considered (the paper's clip): [`DELTA_N_RANGE`]'s end.
pub const DEFAULT_MAX_DELTA_N: u32 = *DELTA_N_RANGE.end();
/// Default largest refresh period `emit` considers: `analyze` replays a node past
/// [`DEFAULT_MAX_DELTA_N`] only where that can still pay (its `Extension`), and no period past a
/// node's longest measured one is ever predicted ([`respect_measurements`]), so a profile
/// measured up to Δn 50 is chosen from as before.
pub const EXTENDED_MAX_DELTA_N: u32 = 400;
/// Default smallest refresh period considered (Δn = 1 recomputes every frame: never faster):
/// [`DELTA_N_RANGE`]'s start.
pub const DEFAULT_MIN_DELTA_N: u32 = *DELTA_N_RANGE.start();

/// What the selector knows of one candidate node.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct NodeRecord {
    /// The node's stable id (from the front end).
    pub id: u32,
    /// The node's source text, for reports.
    pub text: String,
    /// The variant strategy its models were measured with (`3pass`, `2pass`, `fused`).
    #[serde(default = "three_pass")]
    pub strategy: String,
    /// Its error model, fitted to the metric the budget bounds.
    pub error: reproj_models::ErrorFit,
    /// Its timing model (E[hit], E[miss], E[overhead]).
    pub timing: TimingFit,
    /// M: mean shaded pixels per frame at which to predict the frame time.
    pub mean_pixels: f64,
    /// The node's speedup measured interleaved with the original (`analyze`'s race), which sets
    /// the level of its predicted frame times; `None`: the timing model alone.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub measured: Option<Calibration>,
    /// The errors the profile measured, `(Δn, error)` in the budget's metric: the prediction never
    /// goes below them, nor below the line between two neighbouring ones, and no Δn past the
    /// longest measured one is predicted ([`respect_measurements`]). Empty: the model alone.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub measured_errors: Vec<(u32, f64)>,
}

fn three_pass() -> String {
    "3pass".into()
}

/// Options of [`select`].
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SelectOptions {
    /// ε_max: largest acceptable predicted error, in the unit of the nodes' error models (the
    /// mean per-pixel L2 RGB distance, or the mean ꟻLIP when `emit --metric flip` hands over the
    /// models fitted to it).
    pub max_error: Budget,
    /// Smallest Δn considered (≥ 1).
    pub min_delta_n: u32,
    /// Largest Δn considered.
    pub max_delta_n: u32,
}

impl SelectOptions {
    /// Options with budget `max_error` and the default Δn range, [`DELTA_N_RANGE`].
    pub fn new(max_error: Budget) -> Self {
        Self {
            max_error,
            min_delta_n: DEFAULT_MIN_DELTA_N,
            max_delta_n: DEFAULT_MAX_DELTA_N,
        }
    }
}

/// Why a node is not considered.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, thiserror::Error)]
#[serde(tag = "kind", rename_all = "snake_case")]
pub enum SkipReason {
    /// Its error fit failed.
    #[error("error fit failed: {reason}")]
    ErrorFitFailed {
        /// The fit's failure.
        reason: ErrorFitFailure,
    },
    /// Its timing fit failed or left a cost undetermined.
    #[error("timing fit not usable")]
    TimingNotUsable,
    /// Its M is not a positive finite number.
    #[error("mean shaded pixels {value} is not positive")]
    InvalidMeanPixels {
        /// The offending M.
        value: f64,
    },
}

/// Whether `node` can be considered (its fits are usable), or why not.
pub fn check_node(node: &NodeRecord) -> Result<(), SkipReason> {
    if let ErrorFitStatus::Failed { reason } = &node.error.status {
        return Err(SkipReason::ErrorFitFailed {
            reason: reason.clone(),
        });
    }
    if !node.timing.is_usable() {
        return Err(SkipReason::TimingNotUsable);
    }
    if !(node.mean_pixels.is_finite() && node.mean_pixels > 0.0) {
        return Err(SkipReason::InvalidMeanPixels {
            value: if node.mean_pixels.is_finite() {
                node.mean_pixels
            } else {
                0.0
            },
        });
    }
    Ok(())
}

/// Predicted error and time of caching one node at one Δn.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Prediction {
    /// The node.
    pub node_id: u32,
    /// Its variant strategy.
    #[serde(default = "three_pass")]
    pub strategy: String,
    /// The refresh period.
    pub delta_n: u32,
    /// γ(Δn).
    pub hit_rate: f64,
    /// ε̂(Δn).
    pub predicted_error: f64,
    /// t̂(Δn), ms per frame (calibrated by the node's measured speedup where it has one).
    pub predicted_ms: f64,
    /// With a calibration: the predicted speedup's 95 % interval relative to it.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub rel_ci95: Option<[f64; 2]>,
}

/// A point of the error-vs-time frontier.
pub type ParetoPoint = Prediction;

/// Prediction for `node` at `delta_n`, when its fits are usable and the numbers are finite, with a
/// positive frame time.
pub fn predict(node: &NodeRecord, hit_rate: &HitRateFit, delta_n: u32) -> Option<Prediction> {
    check_node(node).ok()?;
    let dn = f64::from(delta_n);
    let gamma = hit_rate.gamma(dn)?;
    let error = predicted_error(node, delta_n)?;
    // Two races: the frame time along them; one: the timing model at the race's level.
    let (ms, rel_ci95) = match node.measured {
        Some(Calibration {
            line: Some(line), ..
        }) => (line.ms_at(gamma), Some(line.rel_ci95_at(gamma))),
        measured => {
            let ms = predicted_frame_ms(&node.timing, hit_rate, dn, node.mean_pixels)?;
            (
                ms * measured.map_or(1.0, |c| c.ms_scale),
                measured.map(|c| c.rel_ci95),
            )
        }
    };
    (error.is_finite() && ms.is_finite() && ms > 0.0).then(|| Prediction {
        node_id: node.id,
        strategy: node.strategy.clone(),
        delta_n,
        hit_rate: gamma,
        predicted_error: error,
        predicted_ms: ms,
        rel_ci95,
    })
}

/// Every prediction over the usable nodes and `min_delta_n..=max_delta_n`, in input order of the
/// nodes then increasing Δn (for scatter charts such as the paper's Fig. 7).
pub fn candidates(
    nodes: &[NodeRecord],
    hit_rate: &HitRateFit,
    min_delta_n: u32,
    max_delta_n: u32,
) -> Vec<Prediction> {
    nodes
        .iter()
        .flat_map(|node| {
            (min_delta_n.max(1)..=max_delta_n).filter_map(move |dn| predict(node, hit_rate, dn))
        })
        .collect()
}

/// Total order: lower time, then lower Δn, then lower node id (then lower error).
fn by_time(a: &Prediction, b: &Prediction) -> std::cmp::Ordering {
    a.predicted_ms
        .total_cmp(&b.predicted_ms)
        .then(a.delta_n.cmp(&b.delta_n))
        .then(a.node_id.cmp(&b.node_id))
        .then(a.strategy.cmp(&b.strategy))
        .then(a.predicted_error.total_cmp(&b.predicted_error))
}

/// The error-vs-time Pareto frontier over all (node, Δn) in the range: the points that no other
/// point beats in both time and error (ties keep the first in the [`select`] order). Sorted by
/// increasing time, hence decreasing error. The original shader is not a point of it.
pub fn pareto(
    nodes: &[NodeRecord],
    hit_rate: &HitRateFit,
    min_delta_n: u32,
    max_delta_n: u32,
) -> Vec<ParetoPoint> {
    let mut all = candidates(nodes, hit_rate, min_delta_n, max_delta_n);
    all.sort_by(by_time);
    let mut front: Vec<ParetoPoint> = Vec::new();
    for p in all {
        let dominated = front
            .last()
            .is_some_and(|last| p.predicted_error >= last.predicted_error);
        if !dominated {
            // Same time as the last kept point but lower error: it dominates that one.
            if front
                .last()
                .is_some_and(|last| last.predicted_ms == p.predicted_ms)
            {
                front.pop();
            }
            front.push(p);
        }
    }
    front
}

/// The selected variant.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Choice {
    /// The cached node.
    pub node_id: u32,
    /// Its source text.
    pub node_text: String,
    /// The variant strategy.
    pub strategy: String,
    /// The refresh period.
    pub delta_n: u32,
    /// Predicted hit rate γ(Δn).
    pub hit_rate: f64,
    /// Predicted error ε̂(Δn).
    pub predicted_error: f64,
    /// Predicted frame time, ms.
    pub predicted_ms: f64,
    /// The original shader's mean frame time, ms.
    pub original_ms: f64,
    /// `original_ms / predicted_ms` (> 1).
    pub predicted_speedup: f64,
    /// Its 95 % interval, where the node's speedup was measured interleaved ([`Calibration`]).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub predicted_speedup_ci95: Option<[f64; 2]>,
    /// For a set of nodes cached together ([`select_with_sets`]): every member id in payload
    /// order (`node_id` is the first, `node_text` the texts joined by ` + `). Empty for a single
    /// node.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub members: Vec<u32>,
}

/// Why the original shader is kept.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, thiserror::Error)]
#[serde(tag = "kind", rename_all = "snake_case")]
pub enum OriginalReason {
    /// The Δn range is empty or starts below 1.
    #[error("invalid refresh-period range {min}..={max}")]
    InvalidDeltaNRange {
        /// `min_delta_n`.
        min: u32,
        /// `max_delta_n`.
        max: u32,
    },
    /// The original's time is not a positive finite number.
    #[error("invalid original frame time")]
    InvalidOriginalTime,
    /// The shared hit-rate fit failed.
    #[error("the hit-rate fit is not usable")]
    HitRateUnavailable,
    /// No node has usable fits.
    #[error("no node has usable fits ({skipped} set aside)")]
    NoUsableNodes {
        /// Nodes set aside.
        skipped: usize,
    },
    /// Every candidate's predicted error exceeds the budget.
    #[error("no node fits the error budget {max_error} (lowest predicted error {lowest_error:.6})")]
    OverBudget {
        /// ε_max.
        max_error: f64,
        /// The lowest predicted error of any candidate.
        lowest_error: f64,
    },
    /// Candidates fit the budget but none is predicted faster than the original.
    #[error(
        "no node under the budget is predicted faster than the original ({best_ms:.3} ms vs {original_ms:.3} ms)"
    )]
    NotFaster {
        /// The fastest prediction under the budget, ms.
        best_ms: f64,
        /// The original's time, ms.
        original_ms: f64,
    },
}

/// Outcome of [`select`].
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(tag = "kind", rename_all = "snake_case")]
pub enum Selection {
    /// Cache this node at this Δn.
    Node(Choice),
    /// Keep the original shader.
    Original {
        /// Why.
        reason: OriginalReason,
    },
}

/// Pick the (node, Δn) with the lowest predicted frame time among those with `ε̂ ≤ max_error` and
/// faster than `original_ms`; ties: lower Δn, then lower node id. Nodes whose fits are not usable
/// are skipped (see [`check_node`]). Independent of the order of `nodes`.
pub fn select(
    nodes: &[NodeRecord],
    hit_rate: &HitRateFit,
    original_ms: f64,
    opts: &SelectOptions,
) -> Selection {
    let original = |reason| Selection::Original { reason };
    if opts.min_delta_n < 1 || opts.min_delta_n > opts.max_delta_n {
        return original(OriginalReason::InvalidDeltaNRange {
            min: opts.min_delta_n,
            max: opts.max_delta_n,
        });
    }
    if !(original_ms.is_finite() && original_ms > 0.0) {
        return original(OriginalReason::InvalidOriginalTime);
    }
    if !hit_rate.is_usable() {
        return original(OriginalReason::HitRateUnavailable);
    }
    let usable: Vec<&NodeRecord> = nodes.iter().filter(|n| check_node(n).is_ok()).collect();
    let all: Vec<Prediction> = usable
        .iter()
        .flat_map(|node| {
            (opts.min_delta_n..=opts.max_delta_n).filter_map(move |dn| predict(node, hit_rate, dn))
        })
        .collect();
    if all.is_empty() {
        return original(OriginalReason::NoUsableNodes {
            skipped: nodes.len() - usable.len(),
        });
    }
    let under: Vec<&Prediction> = all
        .iter()
        .filter(|p| opts.max_error.admits(p.predicted_error))
        .collect();
    let Some(best) = under.iter().copied().min_by(|a, b| by_time(a, b)) else {
        let lowest_error = all
            .iter()
            .map(|p| p.predicted_error)
            .fold(f64::INFINITY, f64::min);
        return original(OriginalReason::OverBudget {
            max_error: opts.max_error.get(),
            lowest_error,
        });
    };
    if best.predicted_ms >= original_ms {
        return original(OriginalReason::NotFaster {
            best_ms: best.predicted_ms,
            original_ms,
        });
    }
    let text = nodes
        .iter()
        .find(|n| n.id == best.node_id)
        .map(|n| n.text.clone())
        .unwrap_or_default();
    Selection::Node(Choice {
        node_id: best.node_id,
        node_text: text,
        strategy: best.strategy.clone(),
        delta_n: best.delta_n,
        hit_rate: best.hit_rate,
        predicted_error: best.predicted_error,
        predicted_ms: best.predicted_ms,
        original_ms,
        predicted_speedup: original_ms / best.predicted_ms,
        predicted_speedup_ci95: best.rel_ci95.map(|[lo, hi]| {
            [
                lo * original_ms / best.predicted_ms,
                hi * original_ms / best.predicted_ms,
            ]
        }),
        members: Vec::new(),
    })
}

/// What the selector knows of a set of nodes cached together in one payload, replayed and fitted
/// like a node (`analyze`'s set search).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SetRecord {
    /// The member ids, in payload order.
    pub members: Vec<u32>,
    /// The members' source texts, in the same order.
    pub texts: Vec<String>,
    /// The variant strategy its models were measured with.
    pub strategy: String,
    /// Its own fitted models (not the members' combined predictions).
    pub error: reproj_models::ErrorFit,
    pub timing: TimingFit,
    /// M: mean shaded pixels per frame.
    pub mean_pixels: f64,
    /// Its measured errors in the budget's metric (see [`NodeRecord::measured_errors`]).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub measured_errors: Vec<(u32, f64)>,
}

impl SetRecord {
    /// The set as the selector's node: its fits under the first member's id.
    pub fn as_node(&self) -> NodeRecord {
        NodeRecord {
            id: self.members.first().copied().unwrap_or(0),
            text: self.texts.join(" + "),
            strategy: self.strategy.clone(),
            error: self.error.clone(),
            timing: self.timing.clone(),
            mean_pixels: self.mean_pixels,
            measured: None,
            measured_errors: self.measured_errors.clone(),
        }
    }
}

/// [`select`] over the single nodes and the measured sets together: the fastest predicted
/// variant under the budget, a set only when it is predicted faster than every single node under
/// the budget (ties keep the single node) and than the original. Sets whose fits are not usable
/// are skipped; without usable sets this is `select`.
pub fn select_with_sets(
    nodes: &[NodeRecord],
    sets: &[SetRecord],
    hit_rate: &HitRateFit,
    original_ms: f64,
    opts: &SelectOptions,
) -> Selection {
    let single = select(nodes, hit_rate, original_ms, opts);
    let fine = match &single {
        Selection::Node(_) => true,
        Selection::Original { reason } => matches!(
            reason,
            OriginalReason::NoUsableNodes { .. }
                | OriginalReason::OverBudget { .. }
                | OriginalReason::NotFaster { .. }
        ),
    };
    if !fine {
        return single;
    }
    let best = sets
        .iter()
        .filter(|s| s.members.len() > 1)
        .flat_map(|s| {
            let node = s.as_node();
            (opts.min_delta_n..=opts.max_delta_n)
                .filter_map(move |dn| predict(&node, hit_rate, dn).map(|p| (s, p)))
        })
        .filter(|(_, p)| opts.max_error.admits(p.predicted_error))
        .min_by(|(sa, a), (sb, b)| by_time(a, b).then(sa.members.cmp(&sb.members)));
    let Some((set, p)) = best else {
        return single;
    };
    let beats = match &single {
        Selection::Node(c) => p.predicted_ms < c.predicted_ms,
        Selection::Original { .. } => p.predicted_ms < original_ms,
    };
    if !beats {
        return single;
    }
    Selection::Node(Choice {
        node_id: p.node_id,
        node_text: set.texts.join(" + "),
        strategy: p.strategy,
        delta_n: p.delta_n,
        hit_rate: p.hit_rate,
        predicted_error: p.predicted_error,
        predicted_ms: p.predicted_ms,
        original_ms,
        predicted_speedup: original_ms / p.predicted_ms,
        predicted_speedup_ci95: p.rel_ci95.map(|[lo, hi]| {
            [
                lo * original_ms / p.predicted_ms,
                hi * original_ms / p.predicted_ms,
            ]
        }),
        members: set.members.clone(),
    })
}
