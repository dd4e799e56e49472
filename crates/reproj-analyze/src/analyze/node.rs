//! One node's replays: each strategy still in the running instanced and raced against the
//! original at the longest period ([`replay_node`]), the winner chosen only beyond doubt
//! ([`race_winner`]) and replayed over the node's periods, with the filter race where asked
//! ([`profile_winner`]).

use std::time::Instant;

use reproj_instance::{InstanceOptions, NodeSelector, Reconstruct, Strategy, instance};
use reproj_models::profile::{BlockProbe, FilterProbe, Measurement, StrategyProbe};
use reproj_models::speedup::{SpeedupEstimate, separates};

use super::shape;
use crate::AnalyzeError;
use crate::replayer::{Again, RaceEntry, Replayer, Subject, finite, timed_estimate, too_slow};
use crate::strategies::{Outcome, StrategyPruner, Verdict};

/// One node's replays: the strategy and filter it was profiled with, its measurements, and why
/// it failed (when it did).
pub(super) struct Raw {
    pub(super) id: u32,
    pub(super) strategy: Strategy,
    pub(super) block: u32,
    pub(super) reconstruct: Reconstruct,
    pub(super) measurements: Vec<Measurement>,
    pub(super) failure: Option<String>,
}

/// What the replay phase gathers: each node's replays and the probes of the strategy and filter
/// races.
#[derive(Default)]
pub(super) struct Replays {
    pub(super) raws: Vec<Raw>,
    pub(super) probes: Vec<StrategyProbe>,
    pub(super) filter_probes: Vec<FilterProbe>,
    pub(super) block_probes: Vec<BlockProbe>,
    pub(super) period_probes: Vec<StrategyProbe>,
}

/// Replay the nodes one by one ([`replay_node`]), pruning the strategies that keep losing: the
/// largest static saving first, where a strategy that cannot win on this adapter loses clearly
/// (fused on a CPU rasterizer: twice as slow as 2pass on marble's best nodes, level with it on
/// nodes that save little), so it is pruned before the nodes where it would only be raced.
/// Everything gathered comes back in id order.
pub(super) fn replay_nodes(
    rp: &mut Replayer<'_, '_>,
    ids: &[u32],
    plan: &[(u32, bool)],
) -> Result<Replays, AnalyzeError> {
    let mut replays = Replays::default();
    let mut pruner = StrategyPruner::new(rp.opts.strategies.len());
    for id in by_saving(rp, ids) {
        let raw = replay_node(rp, id, plan, &mut pruner, &mut replays)?;
        replays.raws.push(raw);
    }
    replays.raws.sort_by_key(|r| r.id);
    replays.probes.sort_by_key(|p| p.node);
    replays.filter_probes.sort_by_key(|p| p.node);
    replays.block_probes.sort_by_key(|p| p.node);
    replays.period_probes.sort_by_key(|p| p.node);
    Ok(replays)
}

/// `ids` by static saving ([`reproj_front::Node::saving`]), the largest first (ties by id).
fn by_saving(rp: &Replayer<'_, '_>, ids: &[u32]) -> Vec<u32> {
    let saving = |id: u32| {
        rp.input
            .table
            .get(id)
            .map_or(0.0, reproj_front::Node::saving)
    };
    let mut order = ids.to_vec();
    order.sort_by(|&a, &b| saving(b).total_cmp(&saving(a)).then(a.cmp(&b)));
    order
}

/// One node: each strategy still in the running instanced, then all raced against the original
/// at the longest period, interleaved (`reproj-bench`): the fastest wins only where its interval
/// separates from the simplest's, and a node is set aside only when its winner's interval lies
/// wholly below 1×. The winner is then replayed over the plan ([`profile_winner`]).
fn replay_node(
    rp: &mut Replayer<'_, '_>,
    id: u32,
    plan: &[(u32, bool)],
    pruner: &mut StrategyPruner,
    replays: &mut Replays,
) -> Result<Raw, AnalyzeError> {
    let (opts, progress, longest) = (rp.opts, rp.progress, rp.longest);
    let to_try = strategies_to_try(rp, id, pruner);
    let (mut built, instance_failure) = instance_strategies(rp, id, &to_try);
    let strategies: Vec<Strategy> = built.iter().map(|b| b.strategy).collect();
    let contest = if built.is_empty() {
        progress.step(&format!("node {id} race at Δn={longest}"));
        None
    } else {
        let entries: Vec<RaceEntry> = built
            .iter()
            .map(|b| RaceEntry {
                name: b.strategy.name().to_string(),
                sources: &b.sources,
                variant: &b.variant,
                delta_n: longest,
            })
            .collect();
        let root = rp.input.table.get(id).is_some_and(|n| n.root);
        let done = format!("node {id} race at Δn={longest}");
        Some(
            rp.contest((id, &format!("node {id}"), &done), &entries, |e| {
                doubt(root, &strategies, e).map(|which| Again::Pooled {
                    which,
                    why: format!("node {id}: in doubt against the original"),
                })
            })?,
        )
    };
    let (race, estimates) = contest.map(|c| (c.report, c.estimates)).unzip();
    let estimates = estimates.unwrap_or_default();
    let winner = race_winner(&strategies, &estimates);
    if let Some(w) = winner
        && let Some(best) = estimates[w]
    {
        for (i, (b, e)) in built.iter().zip(&estimates).enumerate() {
            // A loss counts only where the intervals separate, a win only for the winner.
            let outcome = match e {
                _ if i == w => Outcome::Won {
                    beat_original: best.surely_faster(),
                },
                Some(e) if separates(&best, e) => Outcome::Slower(best.speedup / e.speedup),
                Some(_) => Outcome::Level,
                None => Outcome::Slower(f64::INFINITY),
            };
            pruner.record(b.si, outcome);
        }
    }
    if let Some(r) = &race {
        replays
            .probes
            .extend(strategy_probes(id, longest, &built, r, &estimates, winner));
    }
    let Some(w) = winner else {
        let why = instance_failure
            .unwrap_or_else(|| "no strategy could be timed (no finite frame time)".into());
        for _ in 0..1 + plan.len() {
            progress.step(&format!("node {id}"));
        }
        return Ok(Raw {
            id,
            strategy: opts.strategies[0],
            block: opts.block.unwrap_or(opts.strategies[0].default_block()),
            reconstruct: opts.instance.reconstruct,
            measurements: Vec::new(),
            failure: Some(why),
        });
    };
    let estimate = estimates[w].expect("the winner has an estimate");
    let winner = built.swap_remove(w);
    profile_winner(rp, id, winner, estimate, plan, replays)
}

/// Whether a race leaves it in doubt that a variant is slower than the original: slower by its
/// estimate, its interval reaching 1× or beyond ([`doubt`]; where one more race does not
/// settle it either, the node is profiled).
fn in_doubt(e: &SpeedupEstimate) -> bool {
    e.speedup < 1.0 && !e.surely_slower()
}

/// The strategies still in the running for node `id` (the others pruned, said once).
fn strategies_to_try(
    rp: &Replayer<'_, '_>,
    id: u32,
    pruner: &mut StrategyPruner,
) -> Vec<(usize, Strategy)> {
    let (progress, longest) = (rp.progress, rp.longest);
    let mut to_try: Vec<(usize, Strategy)> = Vec::new();
    for (si, &strategy) in rp.opts.strategies.iter().enumerate() {
        match pruner.verdict(si) {
            Verdict::Try => to_try.push((si, strategy)),
            Verdict::PruneNow => {
                progress.note(&format!(
                    "{strategy}: slower than the winner at Δn = {longest} beyond doubt, by {:.2}× or more on {} nodes or {:.0}× on one; not tried for the remaining nodes",
                    StrategyPruner::MARGIN,
                    StrategyPruner::LOSSES,
                    StrategyPruner::DECISIVE
                ));
                progress.step(&format!("node {id} {strategy} pruned"));
            }
            Verdict::Pruned => progress.step(&format!("node {id} {strategy} pruned")),
        }
    }
    to_try
}

/// The node's selector: the root, or its id.
fn selector(rp: &Replayer<'_, '_>, id: u32) -> NodeSelector {
    let node = rp.input.table.get(id).expect("ids come from the table");
    if node.root {
        NodeSelector::Root
    } else {
        NodeSelector::Id(id)
    }
}

/// Each strategy to try instanced for node `id`, and the first instancing failure.
fn instance_strategies(
    rp: &mut Replayer<'_, '_>,
    id: u32,
    to_try: &[(usize, Strategy)],
) -> (Vec<Built>, Option<String>) {
    let (input, opts, progress) = (rp.input, rp.opts, rp.progress);
    let sel = selector(rp, id);
    let mut built: Vec<Built> = Vec::new();
    let mut instance_failure = None;
    for &(si, strategy) in to_try {
        let block = opts.block.unwrap_or(strategy.default_block());
        let inst = InstanceOptions {
            strategy,
            block,
            ..opts.instance
        };
        let t = Instant::now();
        let variant = instance(input.shader, input.norm, input.table, sel, &inst);
        rp.time.instancing_s += t.elapsed().as_secs_f64();
        progress.step(&format!("node {id} {strategy} instanced"));
        match variant {
            Ok(variant) => built.push(Built {
                si,
                strategy,
                block,
                sources: variant.passes.iter().map(|p| p.wgsl.clone()).collect(),
                variant,
            }),
            Err(e) => {
                progress.note(&format!("node {id} ({strategy}): cannot instance: {e}"));
                instance_failure.get_or_insert(format!("cannot instance: {e}"));
            }
        }
    }
    (built, instance_failure)
}

/// The probes of node `id`'s strategy race at the longest period, the winner's kept: each
/// strategy's figures as decided on (`estimates`: the race's, or where a doubt was settled the
/// rounds of both races, [`doubt`]).
fn strategy_probes(
    id: u32,
    longest: u32,
    built: &[Built],
    r: &reproj_bench::BenchReport,
    estimates: &[Option<SpeedupEstimate>],
    winner: Option<usize>,
) -> Vec<StrategyProbe> {
    built
        .iter()
        .zip(&r.candidates)
        .enumerate()
        .map(|(i, (b, c))| {
            let e = estimates.get(i).copied().flatten();
            StrategyProbe {
                node: id,
                strategy: b.strategy.name().into(),
                block: b.block,
                delta_n: longest,
                frame_ms: finite(e.map_or(c.median_ms.unwrap_or(0.0), |e| e.candidate_ms)),
                error: None,
                pass_ms: Vec::new(),
                kept: Some(i) == winner,
                frames: None,
                original_ms: Some(finite(e.map_or(r.baseline.median_ms, |e| e.baseline_ms))),
                timed: timed_estimate(e.as_ref()),
            }
        })
        .collect()
}

/// Whether a race left its winner in doubt against the original ([`in_doubt`]; never the
/// root's), and if so the strategies to race again: the winner and every one ahead of it by
/// estimate. Raced again, each one's estimate becomes that of the rounds of both races, the
/// winner is chosen again on them and the node is set aside only if it is then slower beyond
/// doubt: a node that would otherwise be replayed over its periods (several replays of the
/// whole session) though most likely it cannot pay off costs one short race instead.
fn doubt(
    root: bool,
    strategies: &[Strategy],
    estimates: &[Option<SpeedupEstimate>],
) -> Option<Vec<usize>> {
    let winner = race_winner(strategies, estimates)?;
    let floor = estimates[winner].filter(|e| !root && in_doubt(e))?.speedup;
    Some(
        (0..estimates.len())
            .filter(|&i| i == winner || estimates[i].is_some_and(|e| e.speedup > floor))
            .collect(),
    )
}

/// The winning strategy replayed over the longest period and the plan; with `race_blocks`, a
/// larger refresh block raced at its period ([`crate::blocks::race_period`]) and, when kept,
/// replayed over the plan instead; with `race_filters`, the challenger filter raced at equal error and, when kept,
/// replayed instead.
fn profile_winner(
    rp: &mut Replayer<'_, '_>,
    id: u32,
    winner: Built,
    estimate: SpeedupEstimate,
    plan: &[(u32, bool)],
    replays: &mut Replays,
) -> Result<Raw, AnalyzeError> {
    let (input, opts, progress, longest) = (rp.input, rp.opts, rp.progress, rp.longest);
    let node = input.table.get(id).expect("ids come from the table");
    let sel = selector(rp, id);
    let Built {
        strategy,
        mut block,
        mut sources,
        mut variant,
        ..
    } = winner;
    let verdict = too_slow(&estimate, node.root, longest, strategy);
    let mut failure = None;
    let mut measurements = Vec::new();
    let subject = Subject {
        node: id,
        set: Vec::new(),
        who: format!("node {id}"),
        text: node.text.clone(),
        root: node.root,
        strategy,
        block,
        reconstruct: None,
        raced: true,
        verdict,
    };
    // The longest period first, and the block race's period with it: the race starts from them.
    let (race_dn, first, mut rest) = rp.period_order(plan);
    rp.replay_plan(
        &subject,
        &sources,
        &variant,
        &first,
        &mut measurements,
        &mut failure,
    )?;
    if let Some(dn) = race_dn
        && failure.is_none()
        && let Some(base) = measurements.iter().find(|m| m.delta_n == dn).cloned()
    {
        let race = crate::blocks::BlockRace {
            id,
            sel,
            strategy,
            block,
            base_sources: &sources,
            base_variant: &variant,
            delta_n: dn,
            base: &base,
        };
        if let Some(kept) = crate::blocks::race_block(rp, &race, &mut replays.block_probes)? {
            block = kept.block;
            sources = kept.sources;
            variant = kept.variant;
            measurements = vec![kept.measurement];
            if dn != longest {
                // The kept block's own measurement at the longest period, before the rest.
                progress.extend(1);
                rest.insert(0, (longest, false));
            }
        }
    }
    let mut subject = Subject {
        block,
        verdict: None,
        ..subject
    };
    rp.replay_plan(
        &subject,
        &sources,
        &variant,
        &rest,
        &mut measurements,
        &mut failure,
    )?;
    let filter_probes = &mut replays.filter_probes;
    let mut reconstruct = opts.instance.reconstruct;
    // The speed the periods past the training ones are judged from: the strategy race's, or,
    // where a filter was kept after another race, the replays' own.
    let mut raced = Some(estimate.speedup);
    if opts.race_filters && failure.is_none() {
        let race = crate::filters::FilterRace {
            id,
            sel,
            strategy,
            block,
            base_sources: &sources,
            base_variant: &variant,
            base_measurements: &measurements,
            base_speedup: Some(estimate.speedup),
        };
        if let Some(kept) = crate::filters::race_filter(rp, &race, filter_probes)? {
            // The node is profiled with the kept filter alone: its measurement at the longest
            // period, then the rest of the plan.
            reconstruct = crate::filters::CHALLENGER;
            measurements = vec![kept.measurement];
            (sources, variant, raced) = (kept.sources, kept.variant, None);
            progress.extend(plan.len() as u64);
            subject = Subject {
                reconstruct: Some(reconstruct),
                verdict: None,
                ..subject
            };
            rp.replay_plan(
                &subject,
                &sources,
                &variant,
                plan,
                &mut measurements,
                &mut failure,
            )?;
        }
    }
    rp.extend_periods(
        raced,
        &subject,
        &sources,
        &variant,
        &mut measurements,
        &mut failure,
    )?;
    if failure.is_none() && raced.is_some() {
        let kept = (sources.as_slice(), &variant);
        let probe = shape::race_second_period(rp, &subject, kept, &measurements, plan)?;
        replays.period_probes.extend(probe);
    }
    Ok(Raw {
        id,
        strategy,
        block,
        reconstruct,
        measurements,
        failure,
    })
}

/// One strategy of one node in `analyze`, instanced: its index in the options' strategies and
/// the variant (pass sources and the variant).
struct Built {
    si: usize,
    strategy: Strategy,
    block: u32,
    sources: Vec<String>,
    variant: reproj_instance::Variant,
}

/// The strategy that wins a node's race: among those faster than the simplest strategy (the
/// fewest passes) beyond doubt — their intervals separate above its — the fastest by its
/// estimate; otherwise the simplest: timing noise never decides. (The fastest estimate alone
/// would let a strategy that does not separate hide one that does.) A winner slower than the
/// original beyond doubt gives way to the fastest strategy whose interval still reaches 1×: a
/// node is never set aside while one of its strategies may pay. `None` when no strategy has an
/// estimate.
fn race_winner(strategies: &[Strategy], estimates: &[Option<SpeedupEstimate>]) -> Option<usize> {
    let timed: Vec<(usize, SpeedupEstimate)> = estimates
        .iter()
        .enumerate()
        .filter_map(|(i, e)| Some((i, (*e)?)))
        .collect();
    let simplest = *timed
        .iter()
        .min_by_key(|(i, _)| (passes(strategies[*i]), *i))?;
    let winner = timed
        .iter()
        .filter(|(_, e)| e.speedup > simplest.1.speedup && separates(e, &simplest.1))
        .max_by(|a, b| a.1.speedup.total_cmp(&b.1.speedup))
        .map_or(simplest.0, |w| w.0);
    let surely_slower = |i: usize| timed.iter().any(|(j, e)| *j == i && e.surely_slower());
    if surely_slower(winner)
        && let Some(may_pay) = timed
            .iter()
            .filter(|(_, e)| !e.surely_slower())
            .max_by(|a, b| a.1.speedup.total_cmp(&b.1.speedup))
    {
        return Some(may_pay.0);
    }
    Some(winner)
}

/// How many passes a strategy draws per frame: the measure of simplicity a tie falls back on.
fn passes(s: Strategy) -> u32 {
    match s {
        Strategy::Fused => 1,
        Strategy::TwoPass => 2,
        Strategy::ThreePass => 3,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn e(speedup: f64, lo: f64, hi: f64) -> Option<SpeedupEstimate> {
        Some(SpeedupEstimate {
            speedup,
            ci95: [lo, hi],
            rounds: 8,
            outliers: 0,
            baseline_ms: 10.0,
            candidate_ms: 10.0 / speedup,
        })
    }

    #[test]
    fn a_race_is_won_only_beyond_doubt_and_a_wide_fastest_does_not_hide_a_sure_one() {
        let s = [Strategy::ThreePass, Strategy::TwoPass, Strategy::Fused];
        // Nothing separates from fused (the simplest): fused wins.
        assert_eq!(
            race_winner(&s, &[e(2.0, 1.0, 3.0), e(1.9, 1.2, 2.6), e(1.5, 1.3, 1.7)]),
            Some(2)
        );
        // 3pass has the best estimate but a wide interval; 2pass is surely faster than fused.
        assert_eq!(
            race_winner(&s, &[e(2.0, 1.5, 2.5), e(1.9, 1.8, 2.0), e(1.4, 1.2, 1.6)]),
            Some(1)
        );
        // Both separate: the faster estimate.
        assert_eq!(
            race_winner(&s, &[e(2.2, 2.1, 2.3), e(1.9, 1.8, 2.0), e(1.4, 1.2, 1.6)]),
            Some(0)
        );
        // Separated below the simplest: no win.
        assert_eq!(
            race_winner(&s[1..], &[e(1.0, 0.9, 1.1), e(1.5, 1.4, 1.6)]),
            Some(1)
        );
        assert_eq!(race_winner(&s, &[None, None, None]), None);
        // The simplest is slower than the original beyond doubt, another may still pay: that
        // one (a normal-mapped Blinn-Phong: fused 0.73× [0.55, 0.97], 2pass 0.93× [0.75, 1.16]).
        assert_eq!(
            race_winner(
                &s,
                &[e(0.6, 0.5, 0.7), e(0.93, 0.75, 1.16), e(0.73, 0.55, 0.97)]
            ),
            Some(1)
        );
        // All slower beyond doubt: the simplest, as before (the node is then set aside).
        assert_eq!(
            race_winner(
                &s,
                &[e(0.6, 0.5, 0.7), e(0.9, 0.85, 0.95), e(0.73, 0.55, 0.97)]
            ),
            Some(2)
        );
    }

    #[test]
    fn only_a_slower_estimate_whose_interval_reaches_one_is_in_doubt() {
        let d = |speedup, lo, hi| in_doubt(&e(speedup, lo, hi).unwrap());
        // Marble's node 152 in one run: fused 0.86× [0.67, 1.09].
        assert!(d(0.86, 0.67, 1.09));
        // Slower beyond doubt: set aside without another race.
        assert!(!d(0.84, 0.75, 0.95));
        // Faster by its estimate: profiled, whatever its interval.
        assert!(!d(1.05, 0.9, 1.2));
        assert!(!d(2.0, 1.9, 2.1));
    }

    #[test]
    fn a_winner_in_doubt_races_again_with_every_strategy_ahead_of_it() {
        let s = [Strategy::ThreePass, Strategy::TwoPass, Strategy::Fused];
        // Fused wins (nothing separates from it) at 0.86× [0.67, 1.09]: it and 3pass, ahead by
        // its estimate, race again; 2pass, behind, does not.
        let est = [e(0.9, 0.6, 1.2), e(0.8, 0.6, 1.0), e(0.86, 0.67, 1.09)];
        assert_eq!(doubt(false, &s, &est), Some(vec![0, 2]));
        // Never the root's; never a winner faster by its estimate or slower beyond doubt.
        assert_eq!(doubt(true, &s, &est), None);
        assert_eq!(doubt(false, &s, &[None, None, e(1.05, 0.9, 1.2)]), None);
        assert_eq!(doubt(false, &s, &[None, None, e(0.8, 0.7, 0.9)]), None);
        assert_eq!(doubt(false, &s, &[None, None, None]), None);
    }
}
