//! The most caching can give on this device, measured before any node is profiled: the root
//! cached and never refreshed, in each strategy, raced against the original. A variant costs its
//! own passes even where it recomputes nothing (two draws, the cache lookup, the depth test); on
//! ordinary lit shading those cost about what the shading does, and no node can pay. Saying so
//! in seconds, with the figures, beats a minute of node replays that all lose.
//!
//! The root's payload is the widest (four floats a pixel), and on a GPU at high resolution the
//! cache's bandwidth is much of what a variant costs: on the H200 at 1080p marble's root cached
//! reached 1.66× while its one-float node 680 reached 2.22×. So where a cacheable node's cache
//! texel is narrower than the root's, the narrowest saving the most is raced beside it, and the
//! ceiling is the faster of the two.

use reproj_front::{Node, NodeTable};
use reproj_instance::{CacheFormat, InstanceOptions, NodeSelector, instance};
use reproj_models::profile::Ceiling;
use reproj_models::speedup::SpeedupEstimate;

use crate::AnalyzeError;
use crate::replayer::{Again, RaceEntry, Replayer};

/// The period the floor is timed at: longer than any race, so nothing is refreshed in it.
pub const CEILING_DELTA_N: u32 = 100_000;

/// The speedup the floor's interval must reach for the nodes to be profiled: below it, what a
/// node could save at best is lost to timing noise and to the refreshes any budget needs.
pub const USEFUL_SPEEDUP: f64 = 1.1;

/// Race the root, and the narrower node of [`narrow_node`] where there is one, cached and never
/// refreshed, in each of the analysis's strategies against the original ([`Replayer::race`]), and
/// keep the fastest: the most any node can give here. `None` where nothing could be instanced or
/// timed (the nodes are then profiled as before).
pub(super) fn measure_ceiling(rp: &mut Replayer<'_, '_>) -> Result<Option<Ceiling>, AnalyzeError> {
    let (input, opts) = (rp.input, rp.opts);
    let root = input.table.root();
    let subjects: Vec<&Node> = std::iter::once(root)
        .chain(narrow_node(input.table))
        .collect();
    let mut built = Vec::new();
    for node in &subjects {
        for &strategy in &opts.strategies {
            let inst = InstanceOptions {
                strategy,
                block: opts.block.unwrap_or(strategy.default_block()),
                ..opts.instance
            };
            let selector = if node.root {
                NodeSelector::Root
            } else {
                NodeSelector::Id(node.id)
            };
            if let Ok(v) = instance(input.shader, input.norm, input.table, selector, &inst) {
                let sources: Vec<String> = v.passes.iter().map(|p| p.wgsl.clone()).collect();
                built.push((strategy, *node, sources, v));
            }
        }
    }
    rp.progress.step("ceiling instanced");
    if built.is_empty() {
        return Ok(None);
    }
    let entries: Vec<RaceEntry> = built
        .iter()
        .map(|(s, node, sources, v)| RaceEntry {
            name: if node.root {
                format!("ceiling {s}")
            } else {
                format!("ceiling {s} node {}", node.id)
            },
            sources,
            variant: v,
            delta_n: CEILING_DELTA_N,
        })
        .collect();
    let contest = rp.contest((root.id, "ceiling", "ceiling raced"), &entries, |e| {
        let (_, best) = fastest(e)?;
        undecided(&best).then(|| Again::Longer {
            why: format!(
                "ceiling: {} leaves open whether caching can reach {USEFUL_SPEEDUP:.2}× here; raced again, longer",
                best.display()
            ),
        })
    })?;
    let Some((i, e)) = fastest(&contest.estimates) else {
        return Ok(None);
    };
    let total = input.table.total_cost.max(1e-9);
    let best_share = input
        .table
        .cacheable()
        .filter(|n| !n.root)
        .map(|n| n.saving() / total)
        .fold(0.0_f64, f64::max)
        .min(1.0);
    let (strategy, node, ..) = &built[i];
    Ok(Some(Ceiling {
        strategy: strategy.name().into(),
        node: (!node.root).then_some(node.id),
        payload: node.components,
        delta_n: CEILING_DELTA_N,
        speedup: e.speedup,
        ci95: e.ci95,
        original_ms: e.baseline_ms,
        variant_ms: e.candidate_ms,
        best_share,
        threshold: USEFUL_SPEEDUP,
        pays: e.ci95[1] >= USEFUL_SPEEDUP,
    }))
}

/// The cacheable node of the narrowest cache texel narrower than the root's (one float before
/// two; there is no three-channel format, so a `vec3` is as wide as the root) that saves the
/// most: the variant of a narrow payload most likely to beat the root cached (marble: node 680,
/// one float, 95 % of the root's saving). `None` where every cacheable node is as wide as the
/// root.
fn narrow_node(table: &NodeTable) -> Option<&Node> {
    let channels = |n: &Node| CacheFormat::narrowest(n.components, false).channels();
    let width = channels(table.root());
    table
        .cacheable()
        .filter(|n| !n.root && n.components > 0 && channels(n) < width)
        .max_by(|a, b| {
            channels(b)
                .cmp(&channels(a))
                .then(a.saving().total_cmp(&b.saving()))
        })
}

/// The fastest entry with a finite estimate and interval, and its estimate.
fn fastest(estimates: &[Option<SpeedupEstimate>]) -> Option<(usize, SpeedupEstimate)> {
    estimates
        .iter()
        .enumerate()
        .filter_map(|(i, e)| Some((i, (*e)?)))
        .filter(|(_, e)| e.speedup.is_finite() && e.ci95.iter().all(|b| b.is_finite()))
        .max_by(|a, b| a.1.speedup.total_cmp(&b.1.speedup))
}

/// Whether a short race leaves the question open: the floor's median is under
/// [`USEFUL_SPEEDUP`] but its interval reaches it. On a loaded machine (a CI run's parallel
/// tests), eight rounds left a floor at 0.49x [0.20, 1.17]: the nodes were profiled for nothing.
/// A longer race decides; where it too reaches the threshold, the nodes are profiled.
fn undecided(e: &SpeedupEstimate) -> bool {
    e.speedup < USEFUL_SPEEDUP && e.ci95[1] >= USEFUL_SPEEDUP
}

#[cfg(test)]
mod tests {
    use super::*;

    use crate::replayer::test_estimate as est;

    #[test]
    fn only_a_floor_whose_interval_straddles_the_threshold_is_raced_again() {
        assert!(undecided(&est(0.49, 0.20, 1.17)));
        assert!(!undecided(&est(0.49, 0.40, 0.60)));
        assert!(!undecided(&est(1.30, 1.00, 1.60)));
    }

    #[test]
    fn the_fastest_finite_estimate_is_kept() {
        let e = [
            Some(est(0.8, 0.7, 0.9)),
            None,
            Some(est(f64::NAN, 0.0, 1.0)),
            Some(est(0.9, 0.8, f64::INFINITY)),
            Some(est(0.85, 0.8, 0.9)),
        ];
        assert_eq!(fastest(&e).map(|(i, _)| i), Some(4));
        assert_eq!(fastest(&[None]).map(|(i, _)| i), None);
    }
}
