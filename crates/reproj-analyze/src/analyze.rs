//! `analyze`: replay the session for the original shader and for the variants of the chosen nodes
//! at every training and held-out Δn, fit the models, and gather everything into a [`Profile`].

use std::time::Instant;

use rayon::prelude::*;
use reproj_instance::{InstanceOptions, NodeSelector, Reconstruct, Strategy, instance};
use reproj_models::profile::{
    AnalysisTime, FilterProbe, Machine, Measurement, NodeProfile, NodeStatus, OriginalRecord,
    Shard, Source, StrategyProbe,
};
use reproj_models::{PROFILE_VERSION, Profile, content_hash};
use reproj_replay::{RenderOptions, Renderer};

use crate::AnalyzeError;
pub use crate::input::{AnalyzeInput, Progress, Silent};
use crate::journal::Journal;
pub use crate::options::{
    AnalyzeOptions, DEFAULT_HOLDOUT, DEFAULT_PERCEPTUAL_FRAMES, DEFAULT_PERCEPTUAL_STRIDE,
    DEFAULT_RACE, DEFAULT_TRAIN, Sampling,
};
use crate::options::{check_periods, period_plan};
use crate::prune::profile_candidates;
use crate::replayer::{
    Fitted, RaceEntry, Replayer, Subject, finite, fit_replays, fit_session_hit_rate, mean, too_slow,
};
use crate::strategies::{StrategyPruner, Verdict};
use reproj_models::speedup::{SpeedupEstimate, separates};

/// Profile the shader over the session. Phases: the nodes and the journal, the reference,
/// the replays node by node ([`replay_nodes`]), the fits ([`fit_nodes`]), the sets, then the
/// profile ([`profile`]).
pub fn analyze(
    input: &AnalyzeInput,
    renderer: &Renderer,
    opts: &AnalyzeOptions,
    progress: &dyn Progress,
) -> Result<Profile, AnalyzeError> {
    let started = Instant::now();
    let period_warnings = check_periods(
        opts,
        opts.max_frames
            .map_or(input.session.frames, |m| m.min(input.session.frames)),
    )?;
    for w in &period_warnings {
        progress.note(&format!("warning: {w}"));
    }
    let ids = node_ids(input, opts)?;
    // The longest training period first: it is the fastest a variant gets, so a node whose variant is
    // slower than the original even there can never be chosen and is set aside at once.
    let longest = *opts.delta_n_train.iter().max().expect("checked above");
    let plan = period_plan(opts, longest);
    if opts.strategies.is_empty() {
        return Err(AnalyzeError::Options("no strategy to profile".into()));
    }
    let extra = opts.strategies.len() - 1;
    let session_frames = opts
        .max_frames
        .map_or(input.session.frames, |m| m.min(input.session.frames))
        .max(1);
    let stride = opts
        .perceptual_stride
        .unwrap_or(session_frames.div_ceil(DEFAULT_PERCEPTUAL_FRAMES));
    let journal = open_journal(input, renderer, opts, &ids, stride, progress)?;
    // Per node: each strategy instanced (or pruned), the race, the longest period and the plan.
    progress.start(1 + (ids.len() * (3 + plan.len() + extra)) as u64);
    let (reference, render_opts, time) = render_reference(input, renderer, opts, stride)?;
    progress.step("original");
    let (mut original, mean_pixels) = original_record(&reference, progress);
    let mut journal = journal;
    if let Some(j) = &mut journal {
        // A resumed run keeps the first run's original times: they decide what is set aside.
        original = j.original(original)?;
    }
    let mut rp = Replayer {
        renderer,
        input,
        reference: &reference,
        render_opts,
        opts,
        progress,
        journal,
        time,
        original_ms: original.frame_ms,
        longest,
        timing_warnings: Vec::new(),
    };
    let replays = replay_nodes(&mut rp, &ids, &plan)?;
    let t = Instant::now();
    let (hit_rate, nodes) = fit_nodes(&rp, &replays.raws, mean_pixels);
    rp.time.fitting_s += t.elapsed().as_secs_f64();
    let sets = match &opts.sets {
        // A shard sees only its part of the nodes: sets are searched over whole analyses.
        Some(set_opts) if ids.len() > 1 && opts.shard.is_none() => {
            crate::sets::analyze_sets(&mut rp, &nodes, &hit_rate, mean_pixels, set_opts)?
        }
        _ => Vec::new(),
    };
    progress.finish();
    if let Some(j) = &rp.journal {
        progress.note(&format!(
            "replayed {}, reused {} recorded by an earlier run; raced {}, reused {}",
            j.recorded, j.reused, j.races_recorded, j.races_reused
        ));
    }
    let mut time = rp.time;
    time.total_s = started.elapsed().as_secs_f64();
    Ok(profile(
        input,
        renderer,
        opts,
        Measured {
            frames: reference.frames.len() as u32,
            stride,
            original,
            hit_rate,
            nodes,
            replays,
            sets,
            time,
            timing_warnings: rp.timing_warnings,
        },
    ))
}

/// The nodes to profile: `--nodes` checked against the table (the root added), or the pruned
/// candidates; a shard's share of them.
fn node_ids(input: &AnalyzeInput, opts: &AnalyzeOptions) -> Result<Vec<u32>, AnalyzeError> {
    let ids = match &opts.nodes {
        Some(ids) => {
            let mut ids = ids.clone();
            for id in &ids {
                match input.table.get(*id) {
                    None => {
                        return Err(AnalyzeError::Options(format!(
                            "no node {id} in {}",
                            input.table.shader
                        )));
                    }
                    Some(n) if !n.cacheable => {
                        return Err(AnalyzeError::Options(format!(
                            "node {id} (`{}`) is culled as {}",
                            n.text,
                            n.reason.map_or("?", |r| r.as_str())
                        )));
                    }
                    _ => {}
                }
            }
            ids.push(input.table.root().id);
            ids.sort_unstable();
            ids.dedup();
            ids
        }
        None => profile_candidates(input.table, &opts.prune),
    };
    let ids: Vec<u32> = match opts.shard {
        None => ids,
        Some(Shard { index, count }) => ids
            .into_iter()
            .enumerate()
            .filter(|(p, _)| *p as u32 % count == index)
            .map(|(_, id)| id)
            .collect(),
    };
    Ok(ids)
}

/// The journal of this analysis (`--journal`), keyed by everything a replay's result depends
/// on, with a note when it resumes.
fn open_journal(
    input: &AnalyzeInput,
    renderer: &Renderer,
    opts: &AnalyzeOptions,
    ids: &[u32],
    stride: u32,
    progress: &dyn Progress,
) -> Result<Option<Journal>, AnalyzeError> {
    let Some(j) = &opts.journal else {
        return Ok(None);
    };
    let key = content_hash(
        format!(
            "{} {} {:?} {:?} {ids:?} {:?} {:?} {:?} {:?} {} {:?} {} {:?} {}",
            content_hash(input.shader.source.as_bytes()),
            content_hash(input.session_bytes),
            opts.delta_n_train,
            opts.delta_n_holdout,
            opts.strategies,
            opts.block,
            opts.instance,
            opts.max_frames,
            renderer.adapter().name,
            renderer.timing_method(),
            stride,
            opts.probe_frames,
            input.norm.unroll.max_trip,
        )
        .as_bytes(),
    );
    let (journal, note) = Journal::open(j, &key)?;
    if let Some(note) = note {
        progress.note(&note);
    }
    if journal.len() > 0 {
        progress.note(&format!(
            "resuming: {} replays already done in {} (--fresh starts over)",
            journal.len(),
            j.path.display()
        ));
    }
    Ok(Some(journal))
}

/// The original's reference replay over the session (the options every whole-session replay
/// shares), and the time it took.
fn render_reference(
    input: &AnalyzeInput,
    renderer: &Renderer,
    opts: &AnalyzeOptions,
    stride: u32,
) -> Result<(reproj_replay::Reference, RenderOptions, AnalysisTime), AnalyzeError> {
    let render_opts = RenderOptions {
        png_dir: None,
        max_frames: opts.max_frames,
        first_frame: 0,
        timing_only: false,
        classify: false,
        raw_frames: false,
        perceptual_stride: Some(stride),
    };
    let mut time = AnalysisTime::default();
    let t = Instant::now();
    let entry = input.shader.fragment_entry(Some(&input.norm.entry))?;
    let reference = renderer.render_original(input.shader, entry, input.session, &render_opts)?;
    time.reference_s = t.elapsed().as_secs_f64();
    Ok((reference, render_opts, time))
}

/// The original's record from its reference replay (frame 0, which compiles shaders, left out)
/// and its mean shaded pixels; a warning when it renders non-finite pixels.
fn original_record(
    reference: &reproj_replay::Reference,
    progress: &dyn Progress,
) -> (OriginalRecord, f64) {
    let original_frames: Vec<_> = reference.report.frames.iter().skip(1).collect();
    let mean_pixels = mean(original_frames.iter().map(|f| f.shaded as f64));
    let original = OriginalRecord {
        frame_ms: finite(reference.report.frame_ms),
        mean_pixels,
        frame_times_ms: original_frames.iter().map(|f| finite(f.frame_ms)).collect(),
        nonfinite_pixels: reference.report.nonfinite_pixels,
    };
    if let Some(first) = reference.report.frames.iter().find(|f| f.nonfinite > 0) {
        progress.note(&format!(
            "warning: the original shader renders {} pixels that are NaN or infinite over the session (first in frame {}); they are left out of every error measured, and the profile records them",
            reference.report.nonfinite_pixels, first.frame
        ));
    }
    (original, mean_pixels)
}

/// One node's replays: the strategy and filter it was profiled with, its measurements, and why
/// it failed (when it did).
struct Raw {
    id: u32,
    strategy: Strategy,
    block: u32,
    reconstruct: Reconstruct,
    measurements: Vec<Measurement>,
    failure: Option<String>,
}

/// What the replay phase gathers: each node's replays and the probes of the strategy and filter
/// races.
#[derive(Default)]
struct Replays {
    raws: Vec<Raw>,
    probes: Vec<StrategyProbe>,
    filter_probes: Vec<FilterProbe>,
}

/// Replay the nodes one by one ([`replay_node`]), pruning the strategies that keep losing.
fn replay_nodes(
    rp: &mut Replayer<'_, '_>,
    ids: &[u32],
    plan: &[(u32, bool)],
) -> Result<Replays, AnalyzeError> {
    let mut replays = Replays::default();
    let mut pruner = StrategyPruner::new(rp.opts.strategies.len());
    for &id in ids {
        let raw = replay_node(rp, id, plan, &mut pruner, &mut replays)?;
        replays.raws.push(raw);
    }
    Ok(replays)
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
    let race = if built.is_empty() {
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
        Some(rp.race(&format!("node {id}"), id, &[], &entries)?)
    };
    progress.step(&format!("node {id} race at Δn={longest}"));
    let estimates: Vec<Option<SpeedupEstimate>> = race
        .as_ref()
        .map(|r| (0..r.candidates.len()).map(|i| r.estimate(i)).collect())
        .unwrap_or_default();
    let strategies: Vec<Strategy> = built.iter().map(|b| b.strategy).collect();
    let winner = race_winner(&strategies, &estimates);
    if let Some(w) = winner
        && let Some(best) = estimates[w]
    {
        for (b, e) in built.iter().zip(&estimates) {
            // A loss counts only where the intervals separate.
            let ratio = match e {
                Some(e) if separates(&best, e) => best.speedup / e.speedup,
                Some(_) => 1.0,
                None => f64::INFINITY,
            };
            pruner.record(b.si, ratio, best.surely_faster());
        }
    }
    if let Some(r) = &race {
        replays
            .probes
            .extend(strategy_probes(id, longest, &built, r, winner));
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
    profile_winner(rp, id, winner, estimate, plan, &mut replays.filter_probes)
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
                    "{strategy}: at least {:.2}× slower than the fastest strategy at Δn = {longest} for {} nodes; not tried for the remaining nodes",
                    StrategyPruner::MARGIN,
                    StrategyPruner::LOSSES
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

/// The probes of node `id`'s strategy race at the longest period, the winner's kept.
fn strategy_probes(
    id: u32,
    longest: u32,
    built: &[Built],
    r: &reproj_bench::BenchReport,
    winner: Option<usize>,
) -> Vec<StrategyProbe> {
    built
        .iter()
        .zip(&r.candidates)
        .enumerate()
        .map(|(i, (b, c))| StrategyProbe {
            node: id,
            strategy: b.strategy.name().into(),
            block: b.block,
            delta_n: longest,
            frame_ms: finite(c.median_ms.unwrap_or(0.0)),
            error: None,
            pass_ms: Vec::new(),
            kept: Some(i) == winner,
            frames: None,
            original_ms: Some(finite(r.baseline.median_ms)),
            speedup: c.speedup.map(finite),
            speedup_ci95: c.speedup_ci95.map(|[lo, hi]| [finite(lo), finite(hi)]),
            rounds: Some(c.rounds),
        })
        .collect()
}

/// The winning strategy replayed over the longest period and the plan, and, with
/// `race_filters`, the challenger filter raced at equal error and, when kept, replayed instead.
fn profile_winner(
    rp: &mut Replayer<'_, '_>,
    id: u32,
    winner: Built,
    estimate: SpeedupEstimate,
    plan: &[(u32, bool)],
    filter_probes: &mut Vec<FilterProbe>,
) -> Result<Raw, AnalyzeError> {
    let (input, opts, progress, longest) = (rp.input, rp.opts, rp.progress, rp.longest);
    let node = input.table.get(id).expect("ids come from the table");
    let sel = selector(rp, id);
    let Built {
        strategy,
        block,
        sources,
        variant,
        ..
    } = winner;
    let verdict = too_slow(&estimate, node.root, longest, strategy);
    let mut failure = None;
    let mut measurements = Vec::new();
    let node_plan: Vec<(u32, bool)> = std::iter::once((longest, false))
        .chain(plan.iter().copied())
        .collect();
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
    rp.replay_plan(
        &subject,
        &sources,
        &variant,
        &node_plan,
        &mut measurements,
        &mut failure,
    )?;
    let mut reconstruct = opts.instance.reconstruct;
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
            progress.extend(plan.len() as u64);
            let subject = Subject {
                reconstruct: Some(reconstruct),
                verdict: None,
                ..subject
            };
            rp.replay_plan(
                &subject,
                &kept.sources,
                &kept.variant,
                plan,
                &mut measurements,
                &mut failure,
            )?;
        }
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

/// The session's hit-rate model, and each node's fits from its replays; a note for each node
/// its fits set aside.
fn fit_nodes(
    rp: &Replayer<'_, '_>,
    raws: &[Raw],
    mean_pixels: f64,
) -> (reproj_models::HitRateFit, Vec<NodeProfile>) {
    let (input, opts, progress) = (rp.input, rp.opts, rp.progress);
    let hit_rate = fit_session_hit_rate(
        raws.iter().flat_map(|r| &r.measurements),
        &opts.delta_n_train,
    );
    let nodes: Vec<NodeProfile> = raws
        .par_iter()
        .map(|raw| {
            let node = input.table.get(raw.id).expect("ids come from the table");
            let Fitted {
                error_fit,
                flip_fit,
                dssim_fit,
                timing_fit,
                holdout,
                status,
            } = fit_replays(
                &raw.measurements,
                raw.failure.as_deref(),
                opts,
                &hit_rate,
                mean_pixels,
            );
            NodeProfile {
                id: raw.id,
                root: node.root,
                text: node.text.clone(),
                line: node.line,
                col: node.col,
                ty: node.ty.clone(),
                cost: node.cost,
                overlap: node.overlap,
                strategy: raw.strategy.name().into(),
                block: Some(raw.block),
                reconstruct: Some(raw.reconstruct.name().into()),
                measurements: raw.measurements.clone(),
                error_fit,
                flip_fit,
                dssim_fit,
                timing_fit,
                holdout,
                status,
            }
        })
        .collect();
    for n in &nodes {
        if let NodeStatus::SetAside { reason } = &n.status
            && raws.iter().any(|r| r.id == n.id && r.failure.is_none())
        {
            progress.note(&format!("node {} `{}`: set aside: {reason}", n.id, n.text));
        }
    }
    (hit_rate, nodes)
}

/// What the analysis measured and fitted, for the profile.
struct Measured {
    frames: u32,
    stride: u32,
    original: OriginalRecord,
    hit_rate: reproj_models::HitRateFit,
    nodes: Vec<NodeProfile>,
    replays: Replays,
    sets: Vec<reproj_models::profile::SetProfile>,
    time: AnalysisTime,
    timing_warnings: Vec<String>,
}

/// The profile: the sources and their hashes, the machine, the settings, and what was measured.
fn profile(
    input: &AnalyzeInput,
    renderer: &Renderer,
    opts: &AnalyzeOptions,
    m: Measured,
) -> Profile {
    let adapter = renderer.adapter();
    Profile {
        schema: "reproj.profile".into(),
        version: PROFILE_VERSION,
        shader: Source {
            path: input.shader.path.display().to_string(),
            hash: content_hash(input.shader.source.as_bytes()),
            ir_hash: Some(crate::emit::ir_hash(input.shader)),
        },
        entry: input.norm.entry.clone(),
        unroll: input.norm.unroll.max_trip,
        session: Source {
            path: input.session_path.display().to_string(),
            hash: content_hash(input.session_bytes),
            ir_hash: None,
        },
        machine: Machine {
            adapter: adapter.name.clone(),
            backend: adapter.backend.clone(),
            timing_method: match renderer.timing_method() {
                reproj_metrics::TimingMethod::GpuTimestamps => "timestamp-queries".into(),
                reproj_metrics::TimingMethod::CpuSubmitWait => "cpu-wall-clock".into(),
            },
            cpu_cores: std::thread::available_parallelism().map_or(1, |n| n.get() as u32),
            lp_num_threads: std::env::var("LP_NUM_THREADS").ok(),
            cpu_rasterizer: reproj_bench::Machine::of(renderer).cpu_rasterizer,
        },
        resolution: input.session.resolution,
        frames: m.frames,
        delta_n_train: opts.delta_n_train.clone(),
        delta_n_holdout: opts.delta_n_holdout.clone(),
        perceptual_stride: Some(m.stride),
        block: opts.block.unwrap_or(Strategy::ThreePass.default_block()),
        depth_epsilon: opts.instance.depth_epsilon,
        reconstruct: opts.instance.reconstruct.name().into(),
        cache_format: opts.instance.cache_format.name(),
        original: m.original,
        hit_rate: m.hit_rate,
        nodes: m.nodes,
        strategy_probes: m.replays.probes,
        filter_probes: m.replays.filter_probes,
        timing_warnings: m.timing_warnings,
        sets: m.sets,
        time: m.time,
        shard: opts.shard,
        motion: crate::motion::measure(input.session, Some(m.frames)),
    }
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
/// would let a strategy that does not separate hide one that does.) `None` when no strategy has
/// an estimate.
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
    }
}
