//! The value parsers of the flags: each checks a number or a path at the door, so a bad value is
//! exit 2 naming the flag and the range (clap prints it) before any work.

use std::path::PathBuf;

use reproj_emit::Budget;

/// A time limit in seconds: finite and positive.
pub(crate) fn positive_seconds(s: &str) -> Result<f64, String> {
    match s.parse::<f64>() {
        Ok(v) if v.is_finite() && v > 0.0 => Ok(v),
        _ => Err(format!("`{s}` is not a positive number of seconds")),
    }
}

/// The longest refresh period any flag accepts: far past any session worth profiling (a
/// period longer than the session is refused where the session is known).
pub(crate) const MAX_DELTA_N: u32 = 10_000;

/// A refresh period a profile can measure or a selection can choose: 2..=[`MAX_DELTA_N`] (Δn 1
/// is the original shader).
pub(crate) fn delta_n_limit(s: &str) -> Result<u32, String> {
    match s.trim().parse::<u32>() {
        Ok(v) if (2..=MAX_DELTA_N).contains(&v) => Ok(v),
        _ => Err(format!(
            "`{s}` is not a refresh period in 2..={MAX_DELTA_N} (Δn 1 is the original shader)"
        )),
    }
}

/// A refresh period a variant runs at: 1..=[`MAX_DELTA_N`] (1 renders the original shader).
pub(crate) fn refresh_period(s: &str) -> Result<u32, String> {
    match s.trim().parse::<u32>() {
        Ok(v) if (1..=MAX_DELTA_N).contains(&v) => Ok(v),
        _ => Err(format!(
            "`{s}` is not a refresh period in 1..={MAX_DELTA_N} (1: the original shader)"
        )),
    }
}

/// A refresh block size: 1, or even (blocks align with 2×2 quads) up to 256.
pub(crate) fn block_size(s: &str) -> Result<u32, String> {
    match s.parse::<u32>() {
        Ok(v) if v == 1 || (v.is_multiple_of(2) && (2..=256).contains(&v)) => Ok(v),
        _ => Err(format!(
            "`{s}` is not a block size: 1, or an even number in 2..=256 (blocks align with 2×2 quads)"
        )),
    }
}

/// `--block`: a refresh block size, or `auto` (analyze races a larger block per node).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum BlockArg {
    /// This block size k for every variant.
    Size(u32),
    /// `analyze` only: per node, race a larger block against the strategy's default.
    Auto,
}

/// A `--block` value: `auto` or a [`block_size`].
pub(crate) fn block_choice(s: &str) -> Result<BlockArg, String> {
    if s == "auto" {
        return Ok(BlockArg::Auto);
    }
    block_size(s)
        .map(BlockArg::Size)
        .map_err(|e| format!("{e}, or `auto` (analyze)"))
}

/// The relative depth tolerance of the hit test: a number in (0, 1].
pub(crate) fn depth_epsilon(s: &str) -> Result<f32, String> {
    match s.parse::<f32>() {
        Ok(v) if v.is_finite() && v > 0.0 && v <= 1.0 => Ok(v),
        _ => Err(format!(
            "`{s}` is not a relative depth tolerance in (0, 1] (default 0.01)"
        )),
    }
}

/// An error budget (`--max-error`): a finite number ≥ 0, checked here once as a [`Budget`].
pub(crate) fn budget(s: &str) -> Result<Budget, String> {
    s.parse()
}

/// A count of at least 1 (`compare --candidates`, `--max-steps`, `--resize-tries`).
pub(crate) fn at_least_one(s: &str) -> Result<usize, String> {
    match s.parse::<usize>() {
        Ok(v) if v >= 1 => Ok(v),
        _ => Err(format!("`{s}` is not a whole number ≥ 1")),
    }
}

/// Samples per pixel of a supersampled reference: 0 (none) or 2 to 256.
pub(crate) fn supersample_count(s: &str) -> Result<u32, String> {
    match s.parse::<u32>() {
        Ok(v) if v == 0 || (2..=256).contains(&v) => Ok(v),
        _ => Err(format!(
            "`{s}` is not 0 (no supersampled reference) or a whole number from 2 to 256"
        )),
    }
}

/// A finite number > 0.
pub(crate) fn positive(s: &str) -> Result<f64, String> {
    match s.parse::<f64>() {
        Ok(v) if v.is_finite() && v > 0.0 => Ok(v),
        _ => Err(format!("`{s}` is not a finite number > 0")),
    }
}

/// `NAME=VALUE` of `--override`: an `override` constant's name (or `@id` number) and a finite
/// number (`true`/`false` for a bool).
pub(crate) fn override_value(s: &str) -> Result<(String, f64), String> {
    let (name, value) = s
        .split_once('=')
        .ok_or_else(|| format!("`{s}` is not NAME=VALUE"))?;
    let name = name.trim();
    if name.is_empty() {
        return Err(format!("`{s}` names no override"));
    }
    let value = match value.trim() {
        "true" => 1.0,
        "false" => 0.0,
        v => match v.parse::<f64>() {
            Ok(v) if v.is_finite() => v,
            _ => return Err(format!("`{v}` is not a finite number (nor true/false)")),
        },
    };
    Ok((name.to_owned(), value))
}

/// A fraction in [0, 1].
pub(crate) fn unit_fraction(s: &str) -> Result<f64, String> {
    match s.parse::<f64>() {
        Ok(v) if (0.0..=1.0).contains(&v) => Ok(v),
        _ => Err(format!("`{s}` is not a fraction in [0, 1]")),
    }
}

/// A fraction in (0, 1].
pub(crate) fn positive_fraction(s: &str) -> Result<f64, String> {
    match s.parse::<f64>() {
        Ok(v) if v.is_finite() && v > 0.0 && v <= 1.0 => Ok(v),
        _ => Err(format!("`{s}` is not a fraction in (0, 1]")),
    }
}

/// A path reproj writes to. `-` is refused rather than taken as a file or directory named `-`:
/// these commands write files (several, or a profile), never to stdout (clap reports it, exit 2).
pub(crate) fn output_path(s: &str) -> Result<PathBuf, String> {
    match s {
        "-" => Err(
            "`-` (stdout) is not supported: this writes files, give a path (`./-` for one named `-`)"
                .into(),
        ),
        "" => Err("the path is empty".into()),
        _ => Ok(PathBuf::from(s)),
    }
}

/// `--backend`'s help: the backends this build has (wgpu's answer, not a fixed list).
#[cfg(feature = "gpu")]
pub(crate) fn backend_help() -> String {
    format!(
        "wgpu backend, as WGPU_BACKEND (default: WGPU_BACKEND, else vulkan); this build has: {}",
        reproj_replay::compiled_backends().join(", ")
    )
}

/// `--backend`'s help in a build without the `gpu` feature.
#[cfg(not(feature = "gpu"))]
pub(crate) fn backend_help() -> String {
    "wgpu backend, as WGPU_BACKEND (this build has none: it was built without the `gpu` feature)"
        .into()
}

/// A `--backend` list must name backends this build has (clap reports the error, exit code 2).
#[cfg(feature = "gpu")]
pub(crate) fn parse_backend(s: &str) -> Result<String, String> {
    match reproj_replay::parse_backends(s, "--backend") {
        Ok(_) => Ok(s.to_string()),
        Err(reproj_replay::ReplayError::Backend {
            name,
            reason,
            compiled,
            accepted,
            ..
        }) => Err(format!(
            "`{name}` {reason} (this build has: {compiled}; accepted names: {accepted})"
        )),
        Err(e) => Err(e.to_string()),
    }
}

/// A build without the `gpu` feature has no backend: the commands that would use one say so.
#[cfg(not(feature = "gpu"))]
pub(crate) fn parse_backend(s: &str) -> Result<String, String> {
    Ok(s.to_string())
}

/// `--def NAME[=VALUE]`: a shader def (`reproj_front::parse_def`).
pub(crate) fn shader_def(s: &str) -> Result<(String, reproj_front::DefValue), String> {
    reproj_front::parse_def(s)
}

/// `--defs-preset ENGINE`.
pub(crate) fn defs_preset(s: &str) -> Result<reproj_front::DefsPreset, String> {
    s.parse()
}
