//! `reproj`: the command-line front of the reproj shader optimizer. This file only parses
//! arguments and dispatches; each command lives in `cmd/`.

use std::path::PathBuf;
use std::process::ExitCode;

use clap::{Args, Parser, Subcommand};

mod cmd;

/// Automatic reprojection-cache optimizer for WGSL fragment shaders.
#[derive(Debug, Parser)]
#[command(name = "reproj", version, about, long_about = None)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Debug, Subcommand)]
enum Command {
    /// List the candidate nodes of a shader: cacheable ones, or all with the reason others are culled.
    Nodes(NodesArgs),
    /// Write the three passes and the manifest of the variant that caches one node.
    Instance(InstanceArgs),
}

/// Arguments of `reproj nodes`.
#[derive(Debug, Args)]
pub struct NodesArgs {
    /// The WGSL shader.
    pub shader: PathBuf,
    /// Fragment entry point (needed when the module has several).
    #[arg(long)]
    pub entry: Option<String>,
    /// Print JSON (schema: docs/SCHEMAS.md#nodes) instead of a table.
    #[arg(long)]
    pub json: bool,
    /// Include culled nodes, with their reasons.
    #[arg(long)]
    pub all: bool,
}

/// Cache texel format.
#[derive(Debug, Clone, Copy, clap::ValueEnum)]
pub enum CacheFormatArg {
    /// 32-bit float channels: exact.
    Rgba32float,
    /// 16-bit float channels (the paper's cache).
    Rgba16float,
}

/// Arguments of `reproj instance`.
#[derive(Debug, Args)]
pub struct InstanceArgs {
    /// The WGSL shader.
    pub shader: PathBuf,
    /// Node id from `reproj nodes`, or `root` for the final color.
    #[arg(long)]
    pub node: String,
    /// Output directory (created if needed).
    #[arg(long)]
    pub out: PathBuf,
    /// Fragment entry point (needed when the module has several).
    #[arg(long)]
    pub entry: Option<String>,
    /// Cache texel format.
    #[arg(long, value_enum, default_value = "rgba32float")]
    pub cache_format: CacheFormatArg,
    /// Default refresh period Δn written to the manifest (the passes take it at run time).
    #[arg(long, default_value_t = 8)]
    pub delta_n: u32,
    /// Refresh block size k (1 or even).
    #[arg(long, default_value_t = 4)]
    pub block: u32,
    /// Relative depth tolerance of the cache hit test.
    #[arg(long, default_value_t = 0.01)]
    pub depth_epsilon: f32,
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    let result = match cli.command {
        Command::Nodes(args) => cmd::nodes::run(&args),
        Command::Instance(args) => cmd::instance::run(&args),
    };
    cmd::finish(result)
}
