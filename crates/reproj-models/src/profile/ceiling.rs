//! The ceiling `analyze` measures before any node: the most caching can give on the device, and
//! whether the nodes were profiled at all. Part of the profile ([`super::Profile`]), in its own
//! file because it is a record of its own.

use serde::{Deserialize, Serialize};

/// The most any cached variant can give on one device: the root (the whole output) cached and
/// never refreshed, so only pixels that were not visible in the previous frame are shaded; what
/// is left is the variant's floor (its draws, the lookup, the depth test). Where a cacheable node
/// has a narrower cache texel, the narrowest saving the most is timed too (the cache's bandwidth
/// is much of the floor). Timed interleaved with the original, each strategy, the fastest kept.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Ceiling {
    /// The strategy of the fastest floor.
    pub strategy: String,
    /// The node it cached where that was the narrower node, not the root (absent: the root).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub node: Option<u32>,
    /// The floats per pixel of its payload (0 in profiles of version 13 and before).
    #[serde(default)]
    pub payload: u32,
    /// The period it was timed at (long enough that nothing is refreshed in the race).
    pub delta_n: u32,
    /// Its speedup over the original (median of interleaved rounds) and 95 % interval.
    pub speedup: f64,
    pub ci95: [f64; 2],
    /// Median ms per frame of the original and of the floor in that race.
    pub original_ms: f64,
    pub variant_ms: f64,
    /// The largest static saving of any cacheable node, as a share of the shader's static cost
    /// (the root's is 1): a node saves at most this share of the original's shading.
    pub best_share: f64,
    /// The speedup the floor must be able to reach (its interval's upper end) for the nodes to
    /// be profiled.
    pub threshold: f64,
    /// Whether it can reach it: `false`, `analyze` profiled no node.
    pub pays: bool,
}

impl std::fmt::Display for Ceiling {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let what = match self.node {
            Some(id) => format!(
                "{}, node {id}'s {}-float payload",
                self.strategy, self.payload
            ),
            None => self.strategy.clone(),
        };
        let at = format!(
            "{:.2}x [{:.2}, {:.2}] ({what}; original {:.3} ms/frame, variant {:.3} ms with nothing recomputed)",
            self.speedup, self.ci95[0], self.ci95[1], self.original_ms, self.variant_ms
        );
        if self.pays {
            write!(f, "caching can reach at most {at}")
        } else {
            write!(
                f,
                "caching cannot pay on this device: even with {} cached and never refreshed a variant reaches only {at}, under {:.2}x: its own passes (the draws, the cache lookup, the depth test) cost about what the shading they save does; the best node's share of the shader's static cost is {:.0} %",
                if self.node.is_some() {
                    "the whole output, or a node of a narrower payload,"
                } else {
                    "the whole output"
                },
                self.threshold,
                self.best_share * 100.0
            )
        }
    }
}
