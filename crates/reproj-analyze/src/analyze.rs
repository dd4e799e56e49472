//! `analyze`: replay the session for the original shader and for the variants of the chosen nodes
//! at every training and held-out Δn, fit the models, and gather everything into a [`Profile`].

use std::path::Path;
use std::time::Instant;

use rayon::prelude::*;
use reproj_front::{NodeTable, Normalized, Shader};
use reproj_instance::{InstanceOptions, NodeSelector, Strategy, instance};
use reproj_models::profile::{
    AnalysisTime, Machine, Measurement, NodeProfile, NodeStatus, OriginalRecord, Shard, Source,
    StrategyProbe,
};
use reproj_models::{PROFILE_VERSION, Profile, content_hash, fit_hit_rate};
use reproj_replay::{RenderOptions, Renderer, Session};

use crate::AnalyzeError;
use crate::journal::{Journal, ReplayKey};
pub use crate::options::{
    AnalyzeOptions, DEFAULT_HOLDOUT, DEFAULT_PERCEPTUAL_FRAMES, DEFAULT_PERCEPTUAL_STRIDE,
    DEFAULT_PROBE_FRAMES, DEFAULT_TRAIN, Sampling,
};
use crate::options::{check_periods, period_plan};
use crate::prune::profile_candidates;
use crate::replayer::{Fitted, Replayer, Subject, finite, fit_replays, mean, too_slow};
use crate::strategies::{StrategyPruner, Verdict};

/// Progress of a long analysis, reported by [`analyze`] (the CLI draws a bar).
pub trait Progress {
    /// `total` replays will follow (the reference included).
    fn start(&self, total: u64);
    /// One replay is done; `what` says which.
    fn step(&self, what: &str);
    /// A line worth showing (a node set aside, ...).
    fn note(&self, line: &str);
    /// `more` replays will follow beyond those announced by `start` (the set search decides
    /// how many it replays as it goes).
    fn extend(&self, more: u64) {
        let _ = more;
    }
    fn finish(&self);
}

/// A [`Progress`] that shows nothing.
#[derive(Debug, Default)]
pub struct Silent;

impl Progress for Silent {
    fn start(&self, _: u64) {}
    fn step(&self, _: &str) {}
    fn note(&self, _: &str) {}
    fn finish(&self) {}
}

/// What [`analyze`] works on.
#[derive(Debug)]
pub struct AnalyzeInput<'a> {
    pub shader: &'a Shader,
    pub norm: &'a Normalized,
    pub table: &'a NodeTable,
    /// Session file path (recorded in the profile) and its bytes (hashed).
    pub session_path: &'a Path,
    pub session_bytes: &'a [u8],
    pub session: &'a Session,
}

/// Profile the shader over the session.
pub fn analyze(
    input: &AnalyzeInput,
    renderer: &Renderer,
    opts: &AnalyzeOptions,
    progress: &dyn Progress,
) -> Result<Profile, AnalyzeError> {
    let started = Instant::now();
    check_periods(opts)?;
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
    let mut journal = match &opts.journal {
        None => None,
        Some(j) => {
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
            Some(journal)
        }
    };
    // Whether strategies may be compared on a prefix: then the kept one costs one more replay.
    let probing = extra > 0 && opts.probe_frames.is_some_and(|p| p < session_frames);
    progress.start(1 + (ids.len() * (1 + plan.len() + extra + usize::from(probing))) as u64);

    let render_opts = RenderOptions {
        png_dir: None,
        max_frames: opts.max_frames,
        first_frame: 0,
        classify: false,
        raw_frames: false,
        perceptual_stride: Some(stride),
    };
    let mut time = AnalysisTime::default();
    let t = Instant::now();
    let entry = input.shader.fragment_entry(Some(&input.norm.entry))?;
    let reference = renderer.render_original(input.shader, entry, input.session, &render_opts)?;
    time.reference_s = t.elapsed().as_secs_f64();
    progress.step("original");
    let original_frames: Vec<_> = reference.report.frames.iter().skip(1).collect();
    let mean_pixels = mean(original_frames.iter().map(|f| f.shaded as f64));
    let mut original = OriginalRecord {
        frame_ms: finite(reference.report.frame_ms),
        mean_pixels,
        frame_times_ms: original_frames.iter().map(|f| finite(f.frame_ms)).collect(),
    };
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
    };

    // Replays, node by node.
    struct Raw {
        id: u32,
        strategy: Strategy,
        block: u32,
        measurements: Vec<Measurement>,
        failure: Option<String>,
    }
    let mut raws = Vec::new();
    let mut probes: Vec<StrategyProbe> = Vec::new();
    let mut pruner = StrategyPruner::new(opts.strategies.len());
    for &id in &ids {
        let node = input.table.get(id).expect("ids come from the table");
        let sel = if node.root {
            NodeSelector::Root
        } else {
            NodeSelector::Id(id)
        };
        // The strategies still in the running for this node.
        let mut to_try: Vec<(usize, Strategy)> = Vec::new();
        for (si, &strategy) in opts.strategies.iter().enumerate() {
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
        // Several strategies are compared on the session's first `probe` frames at the longest
        // period; only the fastest is then replayed over the whole session.
        let probe = opts
            .probe_frames
            .filter(|&p| to_try.len() > 1 && p < session_frames);
        if probing && probe.is_none() {
            progress.step(&format!("node {id}: one strategy left, no probe"));
        }
        // A probe decides on time alone: no frame is read back for the perceptual metrics.
        let probe_opts = match probe {
            Some(p) => RenderOptions {
                max_frames: Some(p),
                perceptual_stride: None,
                ..rp.render_opts.clone()
            },
            None => rp.render_opts.clone(),
        };
        let mut tried: Vec<Tried> = Vec::new();
        for &(si, strategy) in &to_try {
            let block = opts.block.unwrap_or(strategy.default_block());
            let inst = InstanceOptions {
                strategy,
                block,
                ..opts.instance
            };
            let t = Instant::now();
            let variant = instance(input.shader, input.norm, input.table, sel, &inst);
            rp.time.instancing_s += t.elapsed().as_secs_f64();
            let variant = match variant {
                Ok(v) => v,
                Err(e) => {
                    progress.note(&format!("node {id} ({strategy}): cannot instance: {e}"));
                    tried.push(Tried {
                        si,
                        strategy,
                        block,
                        built: None,
                        res: Err(format!("cannot instance: {e}")),
                    });
                    continue;
                }
            };
            let sources: Vec<String> = variant.passes.iter().map(|p| p.wgsl.clone()).collect();
            let res = rp.replay(
                ReplayKey {
                    node: id,
                    strategy: strategy.name().into(),
                    block,
                    delta_n: longest,
                    frames: probe,
                    set: Vec::new(),
                },
                &sources,
                &variant,
                longest,
                Some(&probe_opts),
            )?;
            let on = match probe {
                Some(p) => format!(" on {p} frames"),
                None => String::new(),
            };
            progress.step(&format!("node {id} {strategy} Δn={longest}{on}"));
            if let Err(e) = &res {
                progress.note(&format!(
                    "node {id} ({strategy}): replay failed at Δn={longest}{on}: {e}"
                ));
            }
            tried.push(Tried {
                si,
                strategy,
                block,
                built: Some((sources, variant)),
                res,
            });
        }
        let best = tried
            .iter()
            .enumerate()
            .filter_map(|(i, t)| t.res.as_ref().ok().map(|(m, _)| (i, m.frame_ms)))
            .min_by(|a, b| a.1.total_cmp(&b.1));
        // The original's time over the same frames (frame 0 excluded, as in every mean).
        let original_ms = match probe {
            Some(p) => {
                let prefix =
                    &original.frame_times_ms[..(p as usize - 1).min(original.frame_times_ms.len())];
                if prefix.is_empty() {
                    original.frame_ms
                } else {
                    mean(prefix.iter().copied())
                }
            }
            None => original.frame_ms,
        };
        if let Some((_, best_ms)) = best {
            for t in &tried {
                if let Ok((m, _)) = &t.res {
                    pruner.record(t.si, m.frame_ms / best_ms, best_ms < original_ms);
                }
            }
        }
        let best = best.map(|(i, _)| i);
        if opts.strategies.len() > 1 {
            for (i, t) in tried.iter().enumerate() {
                if let Ok((m, pass_ms)) = &t.res {
                    probes.push(StrategyProbe {
                        node: id,
                        strategy: t.strategy.name().into(),
                        block: t.block,
                        delta_n: longest,
                        frame_ms: m.frame_ms,
                        error: m.error,
                        pass_ms: pass_ms.clone(),
                        kept: Some(i) == best,
                        frames: probe,
                        original_ms: Some(original_ms),
                    });
                }
            }
        }
        let Some(best) = best else {
            let why = tried
                .iter()
                .filter_map(|t| t.res.as_ref().err().cloned())
                .next()
                .unwrap_or_else(|| "no strategy could be replayed".into());
            for _ in 0..plan.len() + usize::from(probe.is_some()) {
                progress.step(&format!("node {id}"));
            }
            raws.push(Raw {
                id,
                strategy: opts.strategies[0],
                block: opts.block.unwrap_or(opts.strategies[0].default_block()),
                measurements: Vec::new(),
                failure: Some(why),
            });
            continue;
        };
        let Tried {
            strategy,
            block,
            built,
            res,
            ..
        } = tried.swap_remove(best);
        let (sources, variant) = built.expect("a replayed strategy was instanced");
        let (probed, _) = res.expect("the best strategy replayed");
        // Without a probe the kept strategy's replay at the longest period is the node's first
        // measurement; after one, that replay over the whole session leads the node's plan.
        // (A probe that lost to the original over its frames is not worth that whole replay.)
        let mut failure = too_slow(&probed, node.root, original_ms, longest, strategy, probe);
        let (mut measurements, node_plan) = match probe {
            None => (vec![probed], plan.clone()),
            Some(_) => (
                Vec::new(),
                std::iter::once((longest, false))
                    .chain(plan.iter().copied())
                    .collect(),
            ),
        };
        if let Some(why) = &failure {
            progress.note(&format!("node {id} `{}`: set aside: {why}", node.text));
        }
        let subject = Subject {
            node: id,
            set: Vec::new(),
            who: format!("node {id}"),
            text: node.text.clone(),
            root: node.root,
            strategy,
            block,
        };
        rp.replay_plan(
            &subject,
            &sources,
            &variant,
            &node_plan,
            &mut measurements,
            &mut failure,
        )?;
        raws.push(Raw {
            id,
            strategy,
            block,
            measurements,
            failure,
        });
    }

    // Fits.
    let t = Instant::now();
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
            "replayed {}, reused {} recorded by an earlier run",
            j.recorded, j.reused
        ));
    }
    let mut time = rp.time;
    time.total_s = started.elapsed().as_secs_f64();

    let adapter = renderer.adapter();
    Ok(Profile {
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
                reproj_replay::TimingMethod::GpuTimestamps => "timestamp-queries".into(),
                reproj_replay::TimingMethod::CpuSubmitWait => "cpu-wall-clock".into(),
            },
            cpu_cores: std::thread::available_parallelism().map_or(1, |n| n.get() as u32),
            lp_num_threads: std::env::var("LP_NUM_THREADS").ok(),
        },
        resolution: input.session.resolution,
        frames: reference.frames.len() as u32,
        delta_n_train: opts.delta_n_train.clone(),
        delta_n_holdout: opts.delta_n_holdout.clone(),
        perceptual_stride: Some(stride),
        block: opts.block.unwrap_or(Strategy::ThreePass.default_block()),
        depth_epsilon: opts.instance.depth_epsilon,
        original,
        hit_rate,
        nodes,
        strategy_probes: probes,
        sets,
        time,
        shard: opts.shard,
    })
}

/// The hit-rate model of a shader and session: one fit over every node's measurements at the
/// training periods (`analyze`, and `merge` over the joined shards).
pub(crate) fn fit_session_hit_rate<'a>(
    measurements: impl Iterator<Item = &'a Measurement>,
    train: &[u32],
) -> reproj_models::HitRateFit {
    let samples: Vec<(f64, f64)> = measurements
        .filter(|m| train.contains(&m.delta_n))
        .map(|m| (m.delta_n as f64, m.hit_rate))
        .collect();
    fit_hit_rate(&samples)
}

/// One strategy tried on one node in `analyze`: its index in the options' strategies, the variant
/// built (when it could be: pass sources and the variant), and the replay at the longest period
/// with per-pass times.
struct Tried {
    si: usize,
    strategy: Strategy,
    block: u32,
    built: Option<(Vec<String>, reproj_instance::Variant)>,
    res: Result<(Measurement, Vec<f64>), String>,
}
