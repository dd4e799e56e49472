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
    /// What the interleaved race measured of it (version 7 on).
    #[serde(flatten)]
    pub timed: Timed,
    /// The probe replayed the session's first N frames only (`analyze --probe-frames`); `None`:
    /// the whole session (profiles before probes, or a session no longer than the probe).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub frames: Option<u32>,
    /// The original's mean frame time over the same frames, ms.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub original_ms: Option<f64>,
}

/// What an interleaved race (`reproj-bench`) measured of one of its entries: the speedup over the
/// original, its 95 % interval and the rounds it rests on; all `None` where the entry was not
/// raced. Flattened into each probe (the JSON fields `speedup`, `speedup_ci95`, `rounds`).
#[derive(Debug, Clone, Copy, Default, PartialEq, Serialize, Deserialize)]
pub struct Timed {
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub speedup: Option<f64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub speedup_ci95: Option<[f64; 2]>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub rounds: Option<u32>,
}

/// One value of a measured variant dimension raced for one node: a reconstruction filter
/// (`analyze --reconstruct auto`, [`FilterProbe`], version 9) or a refresh block size (`analyze
/// --block auto`, [`BlockProbe`], version 10). One record for both: the dimension's value is
/// `reconstruct` for a filter (absent for a block, whose value is `block`).
///
/// **Filters.** Per node, after its strategy was chosen and profiled with the base filter
/// (bilinear), the challenger (Catmull-Rom) is replayed at the longest training Δn; where its error
/// there is lower, the base is taken at the longest Δn whose predicted error is no higher (its
/// *equal-error period*: what the selector would pick for the base under that budget), and both
/// are timed interleaved with the original in one race. The challenger is kept only when it is
/// faster beyond doubt at equal error; otherwise the base is (ties and noise included).
///
/// **Blocks.** Per node, after its strategy was chosen, the base block (the strategy's default k)
/// and a larger one are replayed at one period — the longest training Δn at most half the frames
/// replayed, so every pixel is refreshed at least twice; the same period for both, so the same
/// share of pixels is refreshed per frame — and timed interleaved with the original in one race.
/// The larger block is kept only when its measured error is lower and it is not slower beyond
/// doubt; otherwise the base is (ties and noise included). Two probes per race, the base's first.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct RaceProbe {
    pub node: u32,
    /// The filter raced (`bilinear`, `catmull-rom`, ...); absent in a block's probe.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub reconstruct: Option<String>,
    /// The strategy of the node's variant (its strategy race's winner).
    pub strategy: String,
    /// The refresh block size k (the one raced, in a block's probe).
    pub block: u32,
    /// The period it was timed at. Filters: the longest training Δn for the challenger, the
    /// equal-error period for the base (1: the base reaches that error at no period, the original
    /// stands in). Blocks: the longest training Δn at most half the frames replayed, for both.
    pub delta_n: u32,
    /// Its error at `delta_n`: measured over the whole session (a filter's base: predicted by its
    /// fitted error model).
    pub error: f64,
    /// What the race measured of it (not raced: see `note`).
    #[serde(flatten)]
    pub timed: Timed,
    pub kept: bool,
    /// Why the node kept the value it kept, on the challenger's probe.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub note: Option<String>,
}

/// A reconstruction filter's probe (`reconstruct` set).
pub type FilterProbe = RaceProbe;

/// A refresh block size's probe (`reconstruct` absent).
pub type BlockProbe = RaceProbe;

#[cfg(test)]
mod tests {
    use super::*;

    /// The one record reads and writes each probe exactly as the three records it replaced did:
    /// the race's figures flat beside the other fields, a block's probe without `reconstruct`.
    #[test]
    fn probes_keep_their_json_fields_and_order() {
        let block = r#"{"node":3,"strategy":"2pass","block":4,"delta_n":26,"error":0.01,"speedup":1.5,"speedup_ci95":[1.4,1.6],"rounds":8,"kept":true}"#;
        let filter = r#"{"node":3,"reconstruct":"catmull-rom","strategy":"2pass","block":4,"delta_n":50,"error":0.02,"kept":false,"note":"not raced"}"#;
        let strategy = r#"{"node":3,"strategy":"fused","block":4,"delta_n":50,"frame_ms":2.0,"error":null,"pass_ms":[],"kept":false,"speedup":0.9,"speedup_ci95":[0.8,1.0],"rounds":16,"original_ms":1.8}"#;
        let b: BlockProbe = serde_json::from_str(block).unwrap();
        assert_eq!(b.reconstruct, None);
        assert_eq!(b.timed.rounds, Some(8));
        assert_eq!(serde_json::to_string(&b).unwrap(), block);
        let f: FilterProbe = serde_json::from_str(filter).unwrap();
        assert_eq!(f.reconstruct.as_deref(), Some("catmull-rom"));
        assert_eq!(f.timed, Timed::default());
        assert_eq!(serde_json::to_string(&f).unwrap(), filter);
        let s: StrategyProbe = serde_json::from_str(strategy).unwrap();
        assert_eq!(s.timed.speedup_ci95, Some([0.8, 1.0]));
        assert_eq!(serde_json::to_string(&s).unwrap(), strategy);
    }
}
