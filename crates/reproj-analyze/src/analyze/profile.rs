//! The last phases of `analyze`: each node's models fitted to its replays ([`fit_nodes`]), and
//! everything measured gathered into the [`Profile`] ([`profile`]).

use rayon::prelude::*;
use reproj_instance::Strategy;
use reproj_models::profile::{
    AnalysisTime, Machine, NodeProfile, NodeStatus, OriginalRecord, SetProfile, Source,
};
use reproj_models::{HitRateFit, PROFILE_VERSION, Profile, content_hash};
use reproj_replay::Renderer;

use super::node::{Raw, Replays};
use crate::input::AnalyzeInput;
use crate::options::AnalyzeOptions;
use crate::replayer::{Fitted, Replayer, fit_replays, fit_session_hit_rate};

/// The session's hit-rate model, and each node's fits from its replays; a note for each node
/// its fits set aside.
pub(super) fn fit_nodes(
    rp: &Replayer<'_, '_>,
    raws: &[Raw],
    mean_pixels: f64,
) -> (HitRateFit, Vec<NodeProfile>) {
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
pub(super) struct Measured {
    pub(super) frames: u32,
    pub(super) stride: u32,
    pub(super) original: OriginalRecord,
    pub(super) hit_rate: HitRateFit,
    pub(super) nodes: Vec<NodeProfile>,
    pub(super) replays: Replays,
    pub(super) sets: Vec<SetProfile>,
    pub(super) time: AnalysisTime,
    pub(super) timing_warnings: Vec<String>,
    pub(super) clock: Option<reproj_bench::Settling>,
    pub(super) ceiling: Option<reproj_models::profile::Ceiling>,
}

/// The profile: the sources and their hashes, the machine, the settings, and what was measured.
pub(super) fn profile(
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
            ir_hash: Some(reproj_emit::ir_hash(input.shader)),
        },
        entry: input.norm.entry.clone(),
        unroll: input.norm.unroll.max_trip,
        // Recorded by the caller, who knows the paths relative to the profile's directory.
        shader_input: Default::default(),
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
            driver: Some(reproj_bench::driver_of(adapter)).filter(|d| !d.is_empty()),
            clock: m.clock,
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
        block_probes: m.replays.block_probes,
        period_probes: m.replays.period_probes,
        timing_warnings: m.timing_warnings,
        sets: m.sets,
        time: m.time,
        shard: opts.shard,
        motion: reproj_emit::motion::measure(input.session, Some(m.frames)),
        ceiling: m.ceiling,
    }
}
