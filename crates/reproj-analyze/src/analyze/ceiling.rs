//! The most caching can give on this device, measured before any node is profiled: the root
//! cached and never refreshed, in each strategy, raced against the original. A variant costs its
//! own passes even where it recomputes nothing (two draws, the cache lookup, the depth test); on
//! ordinary lit shading those cost about what the shading does, and no node can pay. Saying so
//! in seconds, with the figures, beats a minute of node replays that all lose.

use reproj_instance::{InstanceOptions, NodeSelector, instance};
use reproj_models::profile::Ceiling;

use crate::AnalyzeError;
use crate::replayer::{RaceEntry, Replayer};

/// The period the floor is timed at: longer than any race, so nothing is refreshed in it.
pub const CEILING_DELTA_N: u32 = 100_000;

/// The speedup the floor's interval must reach for the nodes to be profiled: below it, what a
/// node could save at best is lost to timing noise and to the refreshes any budget needs.
pub const USEFUL_SPEEDUP: f64 = 1.1;

/// Race the root, cached and never refreshed, in each of the analysis's strategies against the
/// original ([`Replayer::race`]), and keep the fastest: the most any node can give here. `None`
/// where no strategy could be instanced or timed (the nodes are then profiled as before).
pub(super) fn measure_ceiling(rp: &mut Replayer<'_, '_>) -> Result<Option<Ceiling>, AnalyzeError> {
    let (input, opts) = (rp.input, rp.opts);
    let root = input.table.root();
    let mut built = Vec::new();
    for &strategy in &opts.strategies {
        let inst = InstanceOptions {
            strategy,
            block: opts.block.unwrap_or(strategy.default_block()),
            ..opts.instance
        };
        if let Ok(v) = instance(
            input.shader,
            input.norm,
            input.table,
            NodeSelector::Root,
            &inst,
        ) {
            let sources: Vec<String> = v.passes.iter().map(|p| p.wgsl.clone()).collect();
            built.push((strategy, sources, v));
        }
    }
    rp.progress.step("ceiling instanced");
    if built.is_empty() {
        return Ok(None);
    }
    let entries: Vec<RaceEntry> = built
        .iter()
        .map(|(s, sources, v)| RaceEntry {
            name: format!("ceiling {s}"),
            sources,
            variant: v,
            delta_n: CEILING_DELTA_N,
        })
        .collect();
    let race = rp.race("ceiling", root.id, &[], &entries)?;
    rp.progress.step("ceiling raced");
    let best = (0..built.len())
        .filter_map(|i| Some((i, race.estimate(i)?)))
        .filter(|(_, e)| e.speedup.is_finite() && e.ci95.iter().all(|b| b.is_finite()))
        .max_by(|a, b| a.1.speedup.total_cmp(&b.1.speedup));
    let Some((i, e)) = best else {
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
    Ok(Some(Ceiling {
        strategy: built[i].0.name().into(),
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
