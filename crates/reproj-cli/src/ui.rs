//! How the CLI speaks to a person on stderr: one `error:` / `warning:` prefix for every message,
//! colour only where it is wanted (`--color auto|always|never`, `NO_COLOR`), and how much is said
//! (`-q` errors and warnings only; `-v` adds what each step did). Stdout is the command's result
//! (a table or `--json`) and is never coloured.

use std::fmt::Display;
use std::io::IsTerminal;
use std::sync::OnceLock;

/// `--color`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, clap::ValueEnum)]
pub enum ColorChoice {
    /// Colour when stderr is a terminal and `NO_COLOR` is unset (or empty).
    #[default]
    Auto,
    Always,
    Never,
}

impl ColorChoice {
    /// Whether messages on stderr are coloured.
    pub fn enabled(self) -> bool {
        match self {
            ColorChoice::Always => true,
            ColorChoice::Never => false,
            ColorChoice::Auto => {
                std::io::stderr().is_terminal()
                    && std::env::var_os("NO_COLOR").is_none_or(|v| v.is_empty())
                    && std::env::var_os("TERM").is_none_or(|t| t != "dumb")
            }
        }
    }

    /// The same choice for clap's own help and parse errors.
    pub fn clap(self) -> clap::ColorChoice {
        match self {
            ColorChoice::Auto => clap::ColorChoice::Auto,
            ColorChoice::Always => clap::ColorChoice::Always,
            ColorChoice::Never => clap::ColorChoice::Never,
        }
    }

    /// `--color` read from the raw arguments, before clap parses them (clap's own help and
    /// errors are coloured by it too). The last one wins, as clap would have it.
    pub fn from_args(args: &[std::ffi::OsString]) -> ColorChoice {
        let mut choice = ColorChoice::Auto;
        let mut it = args.iter().skip(1).map(|a| a.to_string_lossy());
        while let Some(a) = it.next() {
            if a == "--" {
                break;
            }
            let value = match a.strip_prefix("--color") {
                Some("") => it.next().map(|v| v.into_owned()),
                Some(rest) => rest.strip_prefix('=').map(str::to_owned),
                None => None,
            };
            match value.as_deref() {
                Some("always") => choice = ColorChoice::Always,
                Some("never") => choice = ColorChoice::Never,
                Some("auto") => choice = ColorChoice::Auto,
                _ => {}
            }
        }
        choice
    }
}

/// How much is said on stderr.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Ui {
    pub color: bool,
    /// `-q`: errors and warnings only (no progress, no notes).
    pub quiet: bool,
    /// `-v` (repeatable): what each step did.
    pub verbose: u8,
}

static UI: OnceLock<Ui> = OnceLock::new();

/// Set once, by `main`, from the global flags.
pub fn init(ui: Ui) {
    let _ = UI.set(ui);
}

fn get() -> Ui {
    UI.get().copied().unwrap_or(Ui {
        color: false,
        quiet: false,
        verbose: 0,
    })
}

/// `-q` was given: no progress, no notes.
pub fn quiet() -> bool {
    get().quiet
}

/// `-v` was given (at least `level` times).
pub fn verbose(level: u8) -> bool {
    get().verbose >= level
}

fn label(text: &str, ansi: &str) -> String {
    if get().color {
        format!("\x1b[{ansi}m{text}\x1b[0m")
    } else {
        text.to_owned()
    }
}

/// `LABEL: MESSAGE` on stderr, naga_oil's decorated names read as `module::item`.
fn say(what: &str, ansi: &str, message: impl Display) {
    let message = message.to_string();
    let message = reproj_front::names::undecorate(&message);
    eprintln!("{}: {message}", label(what, ansi));
}

/// `error: MESSAGE` (the one prefix of every error reproj prints).
pub fn error(message: impl Display) {
    say("error", "1;31", message);
}

/// `warning: MESSAGE`, said even with `-q`.
pub fn warn(message: impl Display) {
    say("warning", "1;33", message);
}

/// A line about what is going on (which profile, how far): left out with `-q`.
pub fn note(message: impl Display) {
    if !quiet() {
        eprintln!("{message}");
    }
}

/// A line only `-v` shows: what a step did.
pub fn detail(message: impl Display) {
    if verbose(1) {
        eprintln!("{}: {message}", label("info", "1;36"));
    }
}

/// A diagnostic already rendered with its source line and caret (it begins `error`): coloured
/// at its label only.
pub fn diagnostic(rendered: &str) {
    match rendered.strip_prefix("error") {
        Some(rest) if get().color => eprint!("{}{rest}", label("error", "1;31")),
        _ => eprint!("{rendered}"),
    }
}

/// The exit codes, as `--help` lists them (the same as docs/CI.md; checked by `tests/cli.rs`).
pub const EXIT_CODES: &str = "\
Exit codes:
  0    done
  1    internal error (a bug: please report it)
  2    bad input (a message says which file and field); an output path holding a file reproj did
       not write, or another reproj writing it; a command this build does not have
  3    `emit --min-speedup` not met
  4    `emit --verify` measured an error over the budget, or non-finite (NaN/∞) pixels
  5    the output could not be written to stdout (a full disk, a closed stdout)
  130  interrupted (SIGINT/SIGTERM): what was being written is removed, previous outputs kept";

#[cfg(test)]
mod tests {
    use super::ColorChoice;

    fn args(a: &[&str]) -> Vec<std::ffi::OsString> {
        a.iter().map(|s| s.into()).collect()
    }

    #[test]
    fn color_is_read_before_parsing() {
        assert_eq!(
            ColorChoice::from_args(&args(&["reproj", "nodes", "--color", "never"])),
            ColorChoice::Never
        );
        assert_eq!(
            ColorChoice::from_args(&args(&["reproj", "--color=always", "nodes"])),
            ColorChoice::Always
        );
        assert_eq!(
            ColorChoice::from_args(&args(&["reproj", "nodes", "--", "--color=always"])),
            ColorChoice::Auto
        );
        assert!(!ColorChoice::Never.enabled());
        assert!(ColorChoice::Always.enabled());
    }
}
