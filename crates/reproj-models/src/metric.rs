//! Which error a budget bounds. (The per-replay summary of a metric the profile records is
//! `reproj_metrics::MetricSummary`, the type the replay reports.)
//!
//! `analyze` measures three metrics per replay (definitions in `docs/SCHEMAS.md`): the paper's
//! mean per-pixel L2 distance over all pixels, and ꟻLIP and SSIM over the pixels the object
//! covers. The error model is fitted to each error metric (L2, ꟻLIP, and 1 − SSIM), so the
//! selector can bound any of the ones a [`Metric`] names.

use serde::{Deserialize, Serialize};

/// An error metric a budget can bound (`emit --metric`).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Metric {
    /// Mean per-pixel L2 RGB distance over all pixels (the paper's error).
    #[default]
    L2,
    /// Mean ꟻLIP error over the covered pixels.
    Flip,
}

impl Metric {
    /// Every metric, in the order `--metric` lists them.
    pub const ALL: [Metric; 2] = [Metric::L2, Metric::Flip];

    /// The name `--metric` takes and reports print.
    pub fn name(self) -> &'static str {
        match self {
            Metric::L2 => "l2",
            Metric::Flip => "flip",
        }
    }
}

impl std::fmt::Display for Metric {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

impl std::str::FromStr for Metric {
    type Err = String;
    fn from_str(s: &str) -> Result<Metric, String> {
        Metric::ALL
            .into_iter()
            .find(|m| m.name() == s)
            .ok_or_else(|| format!("unknown metric `{s}` (expected l2 or flip)"))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_round_trip() {
        for m in Metric::ALL {
            assert_eq!(m.name().parse::<Metric>(), Ok(m));
            assert_eq!(serde_json::to_string(&m).unwrap(), format!("\"{m}\""));
        }
        assert!("ssim".parse::<Metric>().unwrap_err().contains("l2 or flip"));
        assert_eq!(Metric::default(), Metric::L2);
    }
}
