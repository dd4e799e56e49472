//! The races `analyze` ran per node and what each decided: the strategy race, and the filter and
//! refresh-block races (`--reconstruct auto`, `--block auto`). Part of the profile
//! ([`super::Profile`]), in their own file because each is a record of its own.

use serde::{Deserialize, Serialize};

/// One strategy tried for one node at one Δn (the longest training period): `analyze` keeps the
/// fastest strategy of each node and profiles only that one at every other Δn.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct StrategyProbe {
    pub node: u32,
    pub strategy: String,
    pub block: u32,
    pub delta_n: u32,
    /// Median ms per frame of the strategy's blocks in the race (before version 7: the mean of
    /// one replay).
    pub frame_ms: f64,
    /// The error over the probe's frames (profiles before version 7; a race measures no error).
    #[serde(default)]
    pub error: Option<f64>,
    /// Per-pass mean times, ms (frame 0 excluded; profiles before version 7).
    #[serde(default)]
    pub pass_ms: Vec<f64>,
    pub kept: bool,
    /// Speedup over the original, timed interleaved (`reproj-bench`), with its 95 % interval
    /// and the rounds it rests on (version 7 on).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub speedup: Option<f64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub speedup_ci95: Option<[f64; 2]>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub rounds: Option<u32>,
    /// The probe replayed the session's first N frames only (`analyze --probe-frames`); `None`:
    /// the whole session (profiles before probes, or a session no longer than the probe).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub frames: Option<u32>,
    /// The original's mean frame time over the same frames, ms.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub original_ms: Option<f64>,
}

/// One reconstruction filter raced for one node (`analyze --reconstruct auto`, version 9).
///
/// Per node, after its strategy was chosen and profiled with the base filter (bilinear), the
/// challenger (Catmull-Rom) is replayed at the longest training Δn; where its error there is
/// lower, the base is taken at the longest Δn whose predicted error is no higher (its
/// *equal-error period*: what the selector would pick for the base under that budget), and both
/// are timed interleaved with the original in one race. The challenger is kept only when it is
/// faster beyond doubt at equal error; otherwise the base is (ties and noise included).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct FilterProbe {
    pub node: u32,
    /// `bilinear`, `catmull-rom`, ...
    pub reconstruct: String,
    /// The strategy and block of the node's variant (the race's winner).
    pub strategy: String,
    pub block: u32,
    /// The period it was timed at: the longest training Δn for the challenger, the equal-error
    /// period for the base (1: the base reaches that error at no period, the original stands in).
    pub delta_n: u32,
    /// Its error at `delta_n`: the challenger's measured over the whole session, the base's
    /// predicted by its fitted error model.
    pub error: f64,
    /// Speedup over the original, timed interleaved (`reproj-bench`), with its 95 % interval and
    /// rounds (`None`: not raced, see `note`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub speedup: Option<f64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub speedup_ci95: Option<[f64; 2]>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub rounds: Option<u32>,
    pub kept: bool,
    /// Why the node kept the filter it kept, on the challenger's probe.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub note: Option<String>,
}

/// One refresh block size raced for one node (`analyze --block auto`, version 10).
///
/// Per node, after its strategy was chosen, the base block (the strategy's default k) and a
/// larger one are replayed at one period — the longest training Δn at most half the frames
/// replayed, so every pixel is refreshed at least twice; the same period for both, so the same
/// share of pixels is refreshed per frame — and timed interleaved with the original in one race. The larger
/// block is kept only when its measured error is lower and it is not slower beyond doubt;
/// otherwise the base is (ties and noise included). Two probes per race, the base's first.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct BlockProbe {
    pub node: u32,
    /// The strategy of the node's variant (its race's winner).
    pub strategy: String,
    /// The refresh block size k raced.
    pub block: u32,
    /// The period both were replayed and timed at (the longest training Δn at most half the
    /// frames replayed).
    pub delta_n: u32,
    /// The error measured over the whole session at `delta_n`.
    pub error: f64,
    /// Speedup over the original, timed interleaved (`reproj-bench`), with its 95 % interval and
    /// rounds (`None`: not raced, see `note`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub speedup: Option<f64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub speedup_ci95: Option<[f64; 2]>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub rounds: Option<u32>,
    pub kept: bool,
    /// Why the node kept the block it kept, on the larger block's probe.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub note: Option<String>,
}
