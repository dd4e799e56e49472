//! `reproj compare`'s arguments: the target (a speedup or an error budget), the methods
//! compared at it, and their searches' and final timing's tuning.

use std::path::PathBuf;

use clap::Args;
use reproj_emit::{Budget, EXTENDED_MAX_DELTA_N};

use super::*;
use crate::values::{
    at_least_one, backend_help, budget, delta_n_limit, output_path, parse_backend,
    supersample_count,
};

/// Arguments of `reproj compare`.
#[derive(Debug, Args)]
pub struct CompareArgs {
    /// The shader: WGSL, GLSL (`.glsl`, `.frag`) or SPIR-V (`.spv`), by extension.
    pub shader: PathBuf,
    /// The shader's language, when its extension does not say.
    #[arg(hide = true, long, value_enum)]
    pub lang_in: Option<LangInArg>,
    /// How the shader is read (with --profile: the profile's, unless given here).
    #[command(flatten)]
    pub input: ShaderInputArgs,
    /// Fragment entry point (default: the only one).
    #[arg(long)]
    pub entry: Option<String>,
    /// The session file.
    #[arg(long)]
    pub session: PathBuf,
    /// The speedup over the original every method aims at (> 1).
    #[arg(
        long,
        required_unless_present = "max_error",
        conflicts_with = "max_error"
    )]
    pub speedup: Option<f64>,
    /// Aim instead at the speedup reproj's own selection is predicted to reach under this error
    /// budget (as `emit --max-error`; needs --profile).
    #[arg(long, requires = "profile", value_parser = budget)]
    pub max_error: Option<Budget>,
    /// Profile from `reproj analyze` of this shader, for reproj's own choice (without one, only
    /// resizing and simplification are compared).
    #[arg(long)]
    pub profile: Option<PathBuf>,
    /// Output directory (default `out/compare-SHADER`): compare.json, compare.svg/png, crops.png,
    /// simplified.wgsl.
    #[arg(long, value_parser = output_path)]
    pub out: Option<PathBuf>,
    /// Replay only the first N frames of the session.
    #[arg(long, value_parser = clap::value_parser!(u32).range(1..))]
    pub max_frames: Option<u32>,
    /// Simplification: nodes with the largest static saving tried per step (and half as many
    /// more nearest the saving still needed for the target).
    #[arg(hide = true, long, default_value_t = 6, value_parser = at_least_one)]
    pub candidates: usize,
    /// Simplification: most nodes replaced.
    #[arg(hide = true, long, default_value_t = 8, value_parser = at_least_one)]
    pub max_steps: usize,
    /// Resizing: most scales rendered in the search.
    #[arg(hide = true, long, default_value_t = 4, value_parser = at_least_one)]
    pub resize_tries: usize,
    /// reproj at a target speedup (`--speedup`): most points raced while steering to it; the
    /// profile's models choose the first, the measured speedups the next.
    #[arg(hide = true, long, default_value_t = 4, value_parser = at_least_one)]
    pub reproj_tries: usize,
    /// Longest refresh period reproj may choose.
    #[arg(hide = true, long, default_value_t = EXTENDED_MAX_DELTA_N, value_parser = delta_n_limit)]
    pub max_delta_n: u32,
    /// Jittered samples per pixel of the supersampled reference every method is also scored
    /// against (0: none). Costs that many renders of the original.
    #[arg(hide = true, long, default_value_t = 16, value_parser = supersample_count)]
    pub supersample: u32,
    /// Leave temporal upsampling out of the comparison.
    #[arg(hide = true, long)]
    pub no_temporal: bool,
    /// Print compare.json instead of the table.
    #[arg(long)]
    pub json: bool,
    #[arg(hide = true, long, help = backend_help(), value_parser = parse_backend)]
    pub backend: Option<String>,
}
