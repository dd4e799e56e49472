//! The shape of a node's frame time over Δn, from races: its kept variant raced against the
//! original at a second period, the shortest of the plan, beside its strategy race at the
//! longest. The selector then draws its frame time along the line between the two races (in the
//! hit rate, which the occlusion queries count exactly), not along the replays' own times, which
//! a GPU's clock moves between readback pauses (not even monotone in Δn on the H200; on a shared
//! CPU machine neither).

use reproj_instance::Strategy;
use reproj_models::profile::StrategyProbe;

use crate::AnalyzeError;
use crate::replayer::{RaceEntry, Replayer, finite, timed_estimate};

/// The node's variant as it was kept (its strategy race's figures stand for it).
pub(super) struct Second<'a> {
    pub(super) id: u32,
    pub(super) strategy: Strategy,
    pub(super) block: u32,
    pub(super) sources: &'a [String],
    pub(super) variant: &'a reproj_instance::Variant,
}

/// Race `node`'s variant at the shortest period of `plan` (other than the longest, which its
/// strategy race timed): its probe, kept; none where the plan has no other period.
pub(super) fn race_second_period(
    rp: &mut Replayer<'_, '_>,
    node: &Second<'_>,
    plan: &[(u32, bool)],
) -> Result<Option<StrategyProbe>, AnalyzeError> {
    let longest = rp.longest;
    let Some(delta_n) = plan.iter().map(|p| p.0).filter(|&d| d < longest).min() else {
        return Ok(None);
    };
    let id = node.id;
    rp.progress.extend(1);
    let entry = RaceEntry {
        name: format!("{} Δn={delta_n}", node.strategy),
        sources: node.sources,
        variant: node.variant,
        delta_n,
    };
    let report = rp.race(&format!("node {id}"), id, &[], &[entry])?;
    rp.progress.step(&format!("node {id} race at Δn={delta_n}"));
    let e = report.estimate(0);
    let c = &report.candidates[0];
    Ok(Some(StrategyProbe {
        node: id,
        strategy: node.strategy.name().into(),
        block: node.block,
        delta_n,
        frame_ms: finite(e.map_or(c.median_ms.unwrap_or(0.0), |e| e.candidate_ms)),
        error: None,
        pass_ms: Vec::new(),
        kept: true,
        frames: None,
        original_ms: Some(finite(
            e.map_or(report.baseline.median_ms, |e| e.baseline_ms),
        )),
        timed: timed_estimate(e.as_ref()),
    }))
}
