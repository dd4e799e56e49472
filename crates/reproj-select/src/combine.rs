//! The models of a variant that caches several nodes together (one payload), predicted from the
//! nodes' single-node fits — the paper leaves multi-node caching open (§6); these predictions rank
//! candidate sets, and `analyze` verifies the ones it keeps by replaying them.
//!
//! - Hit rate: shared. Every variant of a shader and session refreshes and reprojects the same
//!   pixels, so γ(Δn) is the one hit-rate model.
//! - Error: `ε̂(Δn) = Σ ε̂ᵢ(Δn)`. The per-pixel errors of stale nodes add up through the rest of the
//!   shader; for the mean per-pixel L2 distance the sum bounds the combined error (triangle
//!   inequality) when they superpose linearly.
//! - Time: a hit skips every cached node, so the savings add: with c₀ = t_original / M the
//!   original's cost per pixel, `E[hit] = max(0, Σ E[hit]ᵢ − (n − 1)·c₀)`. A miss computes the whole
//!   shader once and writes one payload: `E[miss] = max E[miss]ᵢ`, `E[overhead] = max E[overhead]ᵢ`.
//!   Savings of nested nodes (one inside the other's expression) do not add; such sets are
//!   over-predicted and the replay says so.

use reproj_models::{HitRateFit, TimingFit};
use serde::{Deserialize, Serialize};

use crate::{NodeRecord, check_node};

/// Predicted error and time of caching a set of nodes together at one Δn.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SetPrediction {
    /// The nodes, in payload order.
    pub node_ids: Vec<u32>,
    /// The refresh period.
    pub delta_n: u32,
    /// γ(Δn), shared.
    pub hit_rate: f64,
    /// Σ ε̂ᵢ(Δn).
    pub predicted_error: f64,
    /// t̂(Δn) of the combined timing model, ms per frame.
    pub predicted_ms: f64,
}

/// The combined timing model of `nodes` (see the module docs), when each has usable fits.
pub fn combined_timing(nodes: &[&NodeRecord], original_ms: f64) -> Option<TimingFit> {
    let first = nodes.first()?;
    let mean_pixels = first.mean_pixels;
    if !(original_ms.is_finite() && original_ms > 0.0) {
        return None;
    }
    let c0 = original_ms / mean_pixels;
    let (mut hit, mut miss, mut overhead) = (0.0, 0.0_f64, 0.0_f64);
    for n in nodes {
        check_node(n).ok()?;
        hit += n.timing.hit_ms?;
        miss = miss.max(n.timing.miss_ms?);
        overhead = overhead.max(n.timing.overhead_ms?);
    }
    let hit = (hit - (nodes.len() as f64 - 1.0) * c0).max(0.0);
    Some(TimingFit::from_costs(hit, miss, overhead, mean_pixels))
}

/// Prediction for caching `nodes` together at `delta_n`, when all have usable fits and the numbers
/// are finite.
pub fn predict_set(
    nodes: &[&NodeRecord],
    hit_rate: &HitRateFit,
    original_ms: f64,
    delta_n: u32,
) -> Option<SetPrediction> {
    let dn = f64::from(delta_n);
    let gamma = hit_rate.gamma(dn)?;
    let timing = combined_timing(nodes, original_ms)?;
    let ms = timing.frame_ms(gamma, nodes[0].mean_pixels)?;
    let mut error = 0.0;
    for n in nodes {
        error += n.error.predict(dn)?;
    }
    (error.is_finite() && ms.is_finite() && ms > 0.0).then(|| SetPrediction {
        node_ids: nodes.iter().map(|n| n.id).collect(),
        delta_n,
        hit_rate: gamma,
        predicted_error: error,
        predicted_ms: ms,
    })
}

/// The fastest Δn in `min_delta_n..=max_delta_n` at which caching `nodes` together is predicted
/// under `max_error` (ties: the lower Δn).
pub fn best_set(
    nodes: &[&NodeRecord],
    hit_rate: &HitRateFit,
    original_ms: f64,
    max_error: f64,
    (min_delta_n, max_delta_n): (u32, u32),
) -> Option<SetPrediction> {
    (min_delta_n.max(1)..=max_delta_n)
        .filter_map(|dn| predict_set(nodes, hit_rate, original_ms, dn))
        .filter(|p| p.predicted_error <= max_error)
        .min_by(|a, b| {
            a.predicted_ms
                .total_cmp(&b.predicted_ms)
                .then(a.delta_n.cmp(&b.delta_n))
        })
}
