//! The models of a variant that caches several nodes together (one payload), predicted from the
//! nodes' single-node fits — the paper leaves multi-node caching open (§6); these predictions rank
//! candidate sets, and `analyze` verifies the ones it keeps by replaying them.
//!
//! - Hit rate: shared. Every variant of a shader and session refreshes and reprojects the same
//!   pixels, so γ(Δn) is the one hit-rate model.
//! - Error: `ε̂(Δn) = Σ ε̂ᵢ(Δn)`. The per-pixel errors of stale nodes add up through the rest of the
//!   shader; for the mean per-pixel L2 distance the sum bounds the combined error (triangle
//!   inequality) when they superpose linearly.
//! - Time: what a single-node fit determines is its frame time as a function of the hit rate,
//!   `tᵢ(γ) = Aᵢ + γ·Bᵢ` with `Aᵢ = E[overhead]ᵢ + M·E[miss]ᵢ` (every pixel a miss) and
//!   `Bᵢ = M·(E[hit]ᵢ − E[miss]ᵢ)` (what turning misses into hits saves). How a fit splits `Aᵢ`
//!   between overhead and misses is not determined by the frames — a session's hits plus misses
//!   are about the same every frame — and on lavapipe the fits put nearly all of it in
//!   E[overhead] with E[hit] clamped to 0. So the set is combined in those determined terms: a
//!   miss computes the shader once and writes one payload, `A = max Aᵢ`; a hit skips every member,
//!   the savings add, `B = Σ Bᵢ`; as costs: `E[miss] = max E[miss]ᵢ` (moved into `[−B/M, A/M]`
//!   so that no cost is negative), `E[overhead] = A − M·E[miss]`,
//!   `E[hit] = E[miss] + Σ (E[hit]ᵢ − E[miss]ᵢ)`.
//!   (Adding per-pixel hit savings against the original's mean cost and taking the largest
//!   overhead, as this did first, predicted about the slower member where the fits had put the
//!   savings in the overhead: 4.2 ms for a pair measured at 1.1 ms,
//!   `docs/notebook/node-sets.md`.)
//!   Savings of nested nodes (one inside the other's expression) do not add; such sets are
//!   over-predicted, and the set search does not form them.

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

/// The combined timing model of `nodes` (see the module docs), when each has usable fits and
/// `original_ms` (the original's frame time, which a set is compared with) is a positive number.
pub fn combined_timing(nodes: &[&NodeRecord], original_ms: f64) -> Option<TimingFit> {
    let first = nodes.first()?;
    let mean_pixels = first.mean_pixels;
    if !(original_ms.is_finite() && original_ms > 0.0) {
        return None;
    }
    let (mut all_miss, mut miss, mut slope) = (0.0_f64, 0.0_f64, 0.0);
    for n in nodes {
        check_node(n).ok()?;
        let (h, m, o) = (n.timing.hit_ms?, n.timing.miss_ms?, n.timing.overhead_ms?);
        all_miss = all_miss.max(o + mean_pixels * m);
        miss = miss.max(m);
        slope += h - m;
    }
    // t(γ) = A + γ·B exactly, with costs that are not negative: E[miss] moved into
    // [−B/M, A/M] where the largest member miss lies outside it.
    let miss = miss.min(all_miss / mean_pixels).max(-slope);
    let overhead = (all_miss - mean_pixels * miss).max(0.0);
    let hit = (miss + slope).max(0.0);
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
