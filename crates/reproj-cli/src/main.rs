//! `reproj`: the command-line front of the reproj shader optimizer. This file only parses
//! arguments and dispatches; each command lives in `cmd/`.

use std::ffi::OsString;
use std::process::ExitCode;

use clap::{Args, CommandFactory, FromArgMatches, Parser, Subcommand};

mod args;
mod cmd;
mod ui;
mod values;
pub use args::*;

/// Automatic reprojection-cache optimizer for WGSL, GLSL and SPIR-V fragment shaders.
#[derive(Debug, Parser)]
#[command(name = "reproj", version, about, long_about = None)]
struct Cli {
    #[command(subcommand)]
    command: Command,
    /// Let sessions (and their glTF files) name files outside their own folder: absolute paths,
    /// `..` above it, links out of it. Off by default, so a session from elsewhere cannot read
    /// other files of this machine.
    #[arg(long, global = true, hide = true)]
    allow_outside_paths: bool,
    /// Say less on stderr: errors and warnings only (no progress, no notes).
    #[arg(short, long, global = true, conflicts_with = "verbose")]
    quiet: bool,
    /// Say more on stderr: what each step did.
    #[arg(short, long, global = true, action = clap::ArgAction::Count)]
    verbose: u8,
    /// Colour the labels of messages on stderr: `auto` (on a terminal, unless NO_COLOR is set),
    /// `always` or `never`. Stdout (tables, --json) is never coloured.
    #[arg(
        long,
        global = true,
        value_enum,
        default_value = "auto",
        value_name = "WHEN"
    )]
    color: ui::ColorChoice,
}

#[derive(Debug, Subcommand)]
enum Command {
    /// List the candidate nodes of a shader: cacheable ones, or all with the reason others are culled.
    Nodes(NodesArgs),
    /// Write the passes (one to three, by strategy) and the manifest of the variant that caches
    /// one node, or several packed together.
    Instance(InstanceArgs),
    /// Replay a session for the original shader or one cached variant; print error, hit rate, time.
    Render(RenderArgs),
    /// Profile the shader's nodes over a session, fit the models, and save a profile (and charts).
    Analyze(AnalyzeArgs),
    /// Join the profiles of `analyze --shard i/N` runs into one profile.
    Merge(MergeArgs),
    /// Select the fastest node and Δn under an error budget from a profile and write the passes.
    Emit(EmitArgs),
    /// Write one self-contained HTML page of a profile: trade-off chart with a budget slider,
    /// frames of every selection, model charts, the table of fits.
    Report(ReportArgs),
    /// Compare reprojection with reduced resolution (bilinear, edge-adaptive), temporal
    /// upsampling (also with reproj inside it) and code simplification at equal frame time: error
    /// (L2, PSNR, ꟻLIP) per method against the original and a supersampled reference, a chart and
    /// side-by-side crops.
    Compare(CompareArgs),
    /// Time variants or other shaders against the original, interleaved in one run: median
    /// ms/frame and the speedup with its 95 % interval ("hyperfine for shaders").
    Bench(BenchArgs),
    /// Start a session file for a shader (`reproj session init SHADER --out s.json`).
    Session(SessionArgs),
    /// Print a shell completion script (`reproj completions bash > /etc/bash_completion.d/reproj`).
    Completions(CompletionsArgs),
}

/// Arguments of `reproj completions`.
#[derive(Debug, Args)]
pub struct CompletionsArgs {
    /// The shell to complete for.
    #[arg(value_enum)]
    pub shell: clap_complete::Shell,
}

/// The whole command line, as clap builds it: every subcommand's help ends with the exit codes,
/// and clap's own help and errors are coloured as `--color` says.
pub(crate) fn command(color: ui::ColorChoice) -> clap::Command {
    negative_numbers(
        Cli::command()
            .color(color.clap())
            .after_help(ui::EXIT_CODES)
            .mut_subcommands(|s| s.after_help(ui::EXIT_CODES)),
    )
}

/// `--delta-n -1` is a value for the flag, refused by its parser with the valid range, not
/// clap's "unexpected argument '-1'" with a tip to write `-- -1` (no flag of reproj is a number).
fn negative_numbers(c: clap::Command) -> clap::Command {
    c.allow_negative_numbers(true)
        .mut_subcommands(negative_numbers)
}

/// Headless machines have no display: Mesa's Vulkan device-select layer would try to reach one and
/// print `XDG_RUNTIME_DIR is invalid` on every run. Turn the layer off unless the user chose.
#[allow(unsafe_code)]
fn quiet_headless_vulkan() {
    if std::env::var_os("XDG_RUNTIME_DIR").is_none()
        && std::env::var_os("NODEVICE_SELECT").is_none()
    {
        // SAFETY: called first thing in `main`, before any other thread exists.
        unsafe { std::env::set_var("NODEVICE_SELECT", "1") };
    }
}

fn main() -> ExitCode {
    quiet_headless_vulkan();
    let raw: Vec<OsString> = std::env::args_os().collect();
    let color = ui::ColorChoice::from_args(&raw);
    let matches = command(color).get_matches_from(raw);
    let cli = Cli::from_arg_matches(&matches).unwrap_or_else(|e| e.exit());
    ui::init(ui::Ui {
        color: cli.color.enabled(),
        quiet: cli.quiet,
        verbose: cli.verbose,
    });
    cmd::clean_up_on_signals();
    if cli.allow_outside_paths {
        reproj_scene::session::allow_outside_paths();
    }
    let result = match cli.command {
        Command::Nodes(args) => cmd::nodes::run(&args),
        Command::Instance(args) => cmd::instance::run(&args),
        Command::Emit(args) => cmd::emit::run(&args),
        Command::Completions(args) => cmd::completions::run(&args),
        Command::Session(args) => cmd::session::run(&args),
        #[cfg(feature = "gpu")]
        Command::Render(args) => cmd::render::run(&args),
        #[cfg(feature = "gpu")]
        Command::Analyze(args) => cmd::analyze::run(&args),
        #[cfg(feature = "gpu")]
        Command::Merge(args) => cmd::merge::run(&args),
        #[cfg(feature = "gpu")]
        Command::Report(args) => cmd::report::run(&args),
        #[cfg(feature = "gpu")]
        Command::Compare(args) => cmd::compare::run(&args),
        #[cfg(feature = "gpu")]
        Command::Bench(args) => cmd::bench::run(&args),
        #[cfg(not(feature = "gpu"))]
        _ => Err(cmd::needs_gpu(
            matches.subcommand_name().unwrap_or("this command"),
        )),
    };
    cmd::finish(result)
}
