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

fn main() -> ExitCode {
    let cli = Cli::parse();
    let result = match cli.command {
        Command::Nodes(args) => cmd::nodes::run(&args),
    };
    cmd::finish(result)
}
