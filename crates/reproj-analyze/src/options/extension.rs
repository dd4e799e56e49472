//! Periods past the longest training one ([`Extension`]): when a node's error there is still far
//! under any budget and refreshing still a large part of its cost, the next, longer period to
//! replay ([`next_extension`]), or why there is none ([`ExtensionStop`]).

use reproj_models::profile::Measurement;

/// Periods past the longest training one, replayed where they can still matter: the training
/// periods stop at a fixed Δn, but where the error there is still far under any budget a user
/// asks for and refreshing is still a large part of the variant's cost, a longer period is
/// faster at an error users accept (at 1920×1080 marble's error at Δn 50 was 0.003, so budgets
/// 0.01 to 0.1 all chose Δn 50). A node's period is doubled while [`next_extension`] says so.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Extension {
    /// The longest period replayed (at most the replayed frames; at or below the longest
    /// training period: no extension).
    pub max_delta_n: u32,
    /// Stop once the measured error reaches this: the loosest budget a user is expected to ask
    /// `emit` for (no budget would choose a longer period).
    pub max_error: f64,
    /// Stop once doubling the period can save less than this share of the variant's frame
    /// time, at most (the refreshes it drops, each costing at most an original pixel).
    pub min_gain: f64,
}

impl Extension {
    /// No period past the training ones.
    pub const OFF: Extension = Extension {
        max_delta_n: 0,
        max_error: 0.0,
        min_gain: f64::INFINITY,
    };
    /// The default longest period (emit's default `--max-delta-n` is the same).
    pub const DEFAULT_MAX_DELTA_N: u32 = reproj_select::EXTENDED_MAX_DELTA_N;
    /// The default loosest budget.
    pub const DEFAULT_MAX_ERROR: f64 = 0.1;
    /// The default smallest gain worth a replay: 5 % (a variant's draws and lookup dominate its
    /// time where it runs 2-3× faster than the original: doubling marble's Δn 50 gains at most
    /// 2.9 % on lavapipe at 256×256 and 2.2 % on an H200 at 1080p; a node whose variant runs 10×
    /// faster gains up to 10 %).
    pub const DEFAULT_MIN_GAIN: f64 = 0.05;
}

impl Default for Extension {
    fn default() -> Self {
        Extension {
            max_delta_n: Extension::DEFAULT_MAX_DELTA_N,
            max_error: Extension::DEFAULT_MAX_ERROR,
            min_gain: Extension::DEFAULT_MIN_GAIN,
        }
    }
}

/// Why a node's periods stop where they do ([`next_extension`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum ExtensionStop {
    /// The error reached the loosest budget.
    Error { error: f64 },
    /// Doubling the period would save at most `gain` of the frame time.
    Gain { gain: f64 },
    /// The next period would pass the longest allowed (or the replayed frames).
    Limit { limit: u32 },
}

impl std::fmt::Display for ExtensionStop {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            ExtensionStop::Error { error } => {
                write!(f, "its error {error:.5} reaches the loosest budget")
            }
            ExtensionStop::Gain { gain } => write!(
                f,
                "doubling Δn would save at most {:.1} % of its frame time",
                gain * 100.0
            ),
            ExtensionStop::Limit { limit } => write!(f, "the next period would pass Δn {limit}"),
        }
    }
}

/// The next period past the training ones for a node whose longest replay so far is `last`, or
/// why there is none. Doubling Δn drops half of the refreshes: under the hit-rate model
/// `γ = µ (1 − 1/Δn)` the refreshed share of the shaded pixels at Δn is `µ/Δn = γ/(Δn − 1)`, and
/// each refreshed pixel costs at most what the original shader costs per shaded pixel, so the
/// share of the variant's frame time saved is at most `γ/(2 (Δn − 1)) · speedup`, `speedup` being
/// the variant's at `last` (original / variant frame time, from the node's interleaved race).
/// `frames`: the replayed frames (a longer period is measured only in part).
pub fn next_extension(
    last: &Measurement,
    speedup: f64,
    frames: u32,
    ext: &Extension,
) -> Result<u32, ExtensionStop> {
    let limit = ext.max_delta_n.min(frames);
    let next = last.delta_n.saturating_mul(2);
    if next > limit {
        return Err(ExtensionStop::Limit { limit });
    }
    // A NaN error stops it too.
    if last.error.partial_cmp(&ext.max_error) != Some(std::cmp::Ordering::Less) {
        return Err(ExtensionStop::Error { error: last.error });
    }
    let refreshed = last.hit_rate / f64::from(last.delta_n.saturating_sub(1).max(1));
    let gain = 0.5 * refreshed * speedup;
    if !(gain >= ext.min_gain && gain.is_finite()) {
        return Err(ExtensionStop::Gain {
            gain: if gain.is_finite() { gain } else { 0.0 },
        });
    }
    Ok(next)
}
