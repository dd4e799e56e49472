//! `reproj analyze`'s arguments (the profile of a shader over a session: every node measured
//! over Δn) and `reproj merge`'s (profiles of one shader joined into one).

use std::path::PathBuf;

use clap::Args;
use reproj_emit::EXTENDED_MAX_DELTA_N;

use super::*;
use crate::values::{backend_help, delta_n_limit, output_path, parse_backend, unit_fraction};

/// Arguments of `reproj analyze`.
#[derive(Debug, Args)]
pub struct AnalyzeArgs {
    /// The shader: WGSL, GLSL (`.glsl`, `.frag`) or SPIR-V (`.spv`), by extension.
    pub shader: PathBuf,
    /// The shader's language, when its extension does not say.
    #[arg(hide = true, long, value_enum)]
    pub lang_in: Option<LangInArg>,
    #[command(flatten)]
    pub input: ShaderInputArgs,
    #[command(flatten)]
    pub unroll: UnrollArg,
    /// The session file. Repeat it to profile several sessions (other motion) one after the
    /// other: one profile each, the first at --out, the others beside it named after their
    /// session; `emit --profile A --profile B` then holds the budget on every one.
    #[arg(long, required = true)]
    pub session: Vec<PathBuf>,
    /// Profile file to write (default: SHADER_STEM.profile.json in the current directory).
    #[arg(long, value_parser = output_path)]
    pub out: Option<PathBuf>,
    /// Refresh periods the error model is fitted to (`--delta-n`, its former name, is still
    /// read).
    #[arg(long = "fit-delta-n", alias = "delta-n", value_delimiter = ',', default_value = "2,10,18,26,34,42,50", value_parser = delta_n_limit)]
    pub delta_n: Vec<u32>,
    /// Refresh periods used only to check the models.
    #[arg(hide = true, long, value_delimiter = ',', default_value = "6,30", value_parser = delta_n_limit)]
    pub holdout: Vec<u32>,
    /// Longest refresh period a node is replayed at: past the longest of --delta-n, a node's
    /// period is doubled while its error is under 0.1 and a longer period can still save 3 % of
    /// its frame time (at most the session's frames; 50: never past --delta-n).
    #[arg(hide = true, long, default_value_t = EXTENDED_MAX_DELTA_N, value_parser = delta_n_limit)]
    pub max_delta_n: u32,
    /// Profile the nodes even where the ceiling race (the root, and the narrowest-texel node
    /// saving the most, cached and never refreshed, raced against the original first) says
    /// caching cannot pay on this device; skips the race.
    #[arg(long, hide = true)]
    pub no_ceiling: bool,
    /// Profile these node ids only (the root is always added). Default: pruned by saving.
    #[arg(long, value_delimiter = ',')]
    pub nodes: Option<Vec<u32>>,
    /// Profile every cacheable node, as the paper did (hours on a CPU rasterizer for big shaders).
    #[arg(hide = true, long, conflicts_with_all = ["nodes", "max_nodes", "min_saving"])]
    pub all_nodes: bool,
    /// Most nodes to profile when pruning (the root included).
    #[arg(hide = true, long, default_value_t = 16, value_parser = clap::builder::TypedValueParser::map(clap::value_parser!(u32).range(1..), |n| n as usize))]
    pub max_nodes: usize,
    /// Smallest static saving worth profiling, as a fraction of the shader's cost.
    #[arg(hide = true, long, default_value_t = 0.05, value_parser = unit_fraction)]
    pub min_saving: f64,
    /// `adaptive`: replay a node at the longest, shortest and middle training Δn and the
    /// held-out ones, then, while the error model fitted so far misses a held-out measurement,
    /// at the other training Δn one at a time (nearest the worst miss first); `every`: at every
    /// training Δn (the paper's way).
    #[arg(hide = true, long, value_enum, default_value = "adaptive")]
    pub sampling: SamplingArg,
    /// Replay only the first N frames of the session.
    #[arg(long, value_parser = clap::value_parser!(u32).range(1..))]
    pub max_frames: Option<u32>,
    /// Race a node's strategies (timed interleaved against the original) on windows of the
    /// session's first N frames only (0: windows over the whole session).
    #[arg(hide = true, long, default_value_t = 0)]
    pub probe_frames: u32,
    /// Compute ꟻLIP and SSIM on every Nth frame of each replay (0, N, 2N, ...): each such frame
    /// is read back and compared on the CPU. Default: about 15 frames per replay (every 10th of
    /// a 150-frame session). Recorded in the profile.
    #[arg(hide = true, long, value_parser = clap::value_parser!(u32).range(1..))]
    pub metric_stride: Option<u32>,
    /// Do not search sets of nodes cached together (by default, after the single nodes, pairs
    /// among the best of them are ranked by their combined prediction, the best replayed, and the
    /// best measured grown by one node at a time).
    #[arg(hide = true, long, conflicts_with_all = ["set_top", "set_replays", "set_max_nodes"])]
    pub no_sets: bool,
    /// Form pairs among the K single nodes with the largest predicted saving.
    #[arg(hide = true, long, value_name = "K", default_value_t = 6, value_parser = clap::value_parser!(u32).range(2..))]
    pub set_top: u32,
    /// Replay the R pairs predicted fastest.
    #[arg(hide = true, long, value_name = "R", default_value_t = 3, value_parser = clap::value_parser!(u32).range(1..))]
    pub set_replays: u32,
    /// Grow the best measured set up to N nodes (2: pairs only; a payload holds 4 floats).
    #[arg(hide = true, long, value_name = "N", default_value_t = 3, value_parser = clap::value_parser!(u32).range(2..=4))]
    pub set_max_nodes: u32,
    #[command(flatten)]
    pub cache: CacheArgs,
    /// Fragment entry point.
    #[arg(long)]
    pub entry: Option<String>,
    #[arg(hide = true, long, help = backend_help(), value_parser = parse_backend)]
    pub backend: Option<String>,
    /// Profile only shard i of N (0-based) of the nodes, e.g. `--shard 0/3`; join the shards'
    /// profiles with `reproj merge`.
    #[arg(hide = true, long)]
    pub shard: Option<reproj_models::profile::Shard>,
    /// Start over: ignore the journal an interrupted run left beside the profile.
    #[arg(hide = true, long)]
    pub fresh: bool,
    /// Do not write the charts.
    #[arg(hide = true, long)]
    pub no_charts: bool,
    /// Print what was written as JSON (`reproj.analyze`, docs/SCHEMAS.md) instead of the summary.
    #[arg(long)]
    pub json: bool,
}

/// Arguments of `reproj merge`.
#[derive(Debug, Args)]
pub struct MergeArgs {
    /// The shard profiles (every index 0..N of one `--shard i/N` set, in any order).
    #[arg(required = true)]
    pub shards: Vec<PathBuf>,
    /// The merged profile.
    #[arg(long)]
    pub out: PathBuf,
    /// Print the summary as JSON (`reproj.merge`, docs/SCHEMAS.md).
    #[arg(long)]
    pub json: bool,
}
