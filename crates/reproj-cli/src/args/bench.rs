//! `reproj bench`'s arguments: the candidates raced against the original, and the race's
//! blocks, warm-up and stopping rule.

use std::path::PathBuf;

use clap::Args;

use super::*;
use crate::values::{backend_help, parse_backend, positive_fraction, positive_seconds};

/// `bench --block`'s default: the timing engine's (the same number in a build without it).
#[cfg(feature = "gpu")]
const DEFAULT_BLOCK_FRAMES: u32 = reproj_bench::DEFAULT_BLOCK_FRAMES;
#[cfg(not(feature = "gpu"))]
const DEFAULT_BLOCK_FRAMES: u32 = 12;

/// Arguments of `reproj bench`.
#[derive(Debug, Args)]
pub struct BenchArgs {
    /// The original shader (the baseline): WGSL, GLSL (`.glsl`, `.frag`) or SPIR-V (`.spv`).
    pub shader: PathBuf,
    /// The candidates: variant directories (written by `instance` or `emit`) or other shader
    /// files over the same session (the shader itself: the A/A check).
    pub candidates: Vec<PathBuf>,
    /// The shader's language, when its extension does not say (the baseline and shader
    /// candidates).
    #[arg(hide = true, long, value_enum)]
    pub lang_in: Option<LangInArg>,
    #[command(flatten)]
    pub input: ShaderInputArgs,
    /// The session file.
    #[arg(long)]
    pub session: PathBuf,
    /// Refresh period of every variant candidate (default: the Δn `emit` chose, from the
    /// directory's report.json, else the manifest's).
    #[arg(long, value_parser = clap::value_parser!(u32).range(1..=100_000))]
    pub delta_n: Option<u32>,
    /// Variant directories whose manifest has a run-time schedule: each frame's Δn from it at
    /// that frame's on-screen motion (see `render --adaptive`); the others keep a fixed Δn, so an
    /// adaptive variant can be timed against fixed periods in one interleaved run.
    #[arg(long, conflicts_with = "delta_n")]
    pub adaptive: bool,
    /// Stop after this many rounds at most (each round renders one block per subject).
    #[arg(hide = true, long, default_value_t = 48, value_parser = clap::value_parser!(u32).range(1..=10_000))]
    pub rounds: u32,
    /// Run at least this many rounds (the rounds cycle through 4 windows of the session: 8 gives
    /// each window two).
    #[arg(hide = true, long, default_value_t = 8, value_parser = clap::value_parser!(u32).range(1..=10_000))]
    pub min_rounds: u32,
    /// Stop measuring after this many seconds (checked between rounds).
    #[arg(hide = true, long, default_value_t = 30.0, value_parser = positive_seconds)]
    pub max_time: f64,
    /// Stop once every interval is within ± this fraction of its estimate.
    #[arg(hide = true, long, default_value_t = 0.03, value_parser = positive_fraction)]
    pub target: f64,
    /// Timed frames per block (each block renders one more, discarded).
    #[arg(hide = true, long = "block-frames", default_value_t = DEFAULT_BLOCK_FRAMES, value_parser = clap::value_parser!(u32).range(1..=10_000))]
    pub block: u32,
    /// Draw the windows from the session's first N frames only.
    #[arg(long, value_parser = clap::value_parser!(u32).range(1..))]
    pub max_frames: Option<u32>,
    /// Fragment entry point.
    #[arg(long)]
    pub entry: Option<String>,
    #[arg(hide = true, long, help = backend_help(), value_parser = parse_backend)]
    pub backend: Option<String>,
    /// Print the result as JSON (`reproj.bench` v1, docs/SCHEMAS.md).
    #[arg(long)]
    pub json: bool,
}
