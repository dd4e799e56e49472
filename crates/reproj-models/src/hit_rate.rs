//! Hit-rate model (paper §4.3, eq. 4): `γ(Δn) = µ (1 − 1/Δn)`, one µ per shader and session.
//!
//! The hit rate does not depend on which node is cached, so µ is fitted once, in closed form:
//! with `x = 1 − 1/Δn`, least squares gives `µ = Σ x·γ / Σ x²`, clamped to [0, 1].

use serde::{Deserialize, Serialize};

use crate::stats::{r_squared, rms_residual};

/// Why a hit-rate fit failed.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, thiserror::Error)]
#[serde(tag = "kind", rename_all = "snake_case")]
pub enum HitRateFitFailure {
    /// No samples.
    #[error("no hit-rate samples")]
    Empty,
    /// Some Δn or hit rate is NaN or infinite.
    #[error("{count} sample(s) with a NaN or infinite Δn or hit rate")]
    NonFiniteInput {
        /// How many samples were not finite.
        count: usize,
    },
    /// A Δn below 1.
    #[error("refresh period Δn = {value} is below 1")]
    InvalidDeltaN {
        /// The offending Δn.
        value: f64,
    },
    /// A hit rate outside [0, 1].
    #[error("hit rate {value} is outside [0, 1]")]
    OutOfRange {
        /// The offending hit rate.
        value: f64,
    },
    /// Every sample is at Δn = 1, where the model is 0 whatever µ.
    #[error("no sample at Δn > 1: µ is undetermined")]
    NoSampleAboveOne,
}

/// Status of a [`HitRateFit`].
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(tag = "status", rename_all = "snake_case")]
pub enum HitRateStatus {
    /// µ is the least-squares estimate.
    Ok,
    /// The least-squares µ was outside [0, 1] and was clamped (usable; a warning).
    Clamped {
        /// The estimate before clamping.
        raw_mu: f64,
    },
    /// Not usable.
    Failed {
        /// Why.
        reason: HitRateFitFailure,
    },
}

/// Fitted hit-rate model of one shader and session.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct HitRateFit {
    /// µ in [0, 1].
    pub mu: Option<f64>,
    /// R² over the samples.
    pub r2: Option<f64>,
    /// RMS residual (hit-rate units).
    pub rms_residual: Option<f64>,
    /// Samples given.
    pub n_samples: usize,
    /// Ok, clamped, or why not.
    pub status: HitRateStatus,
}

impl HitRateFit {
    /// A fit with a given µ (clamped to [0, 1]), e.g. for tests or a µ known from elsewhere.
    pub fn from_mu(mu: f64) -> Self {
        let clamped = if mu.is_finite() {
            mu.clamp(0.0, 1.0)
        } else {
            0.0
        };
        Self {
            mu: Some(clamped),
            r2: None,
            rms_residual: None,
            n_samples: 0,
            status: if clamped == mu {
                HitRateStatus::Ok
            } else {
                HitRateStatus::Clamped {
                    raw_mu: if mu.is_finite() { mu } else { 0.0 },
                }
            },
        }
    }

    /// Whether µ can be used (Ok or Clamped).
    pub fn is_usable(&self) -> bool {
        self.mu.is_some() && !matches!(self.status, HitRateStatus::Failed { .. })
    }

    /// γ(Δn); `None` if the fit is not usable or Δn < 1 or not finite.
    pub fn gamma(&self, delta_n: f64) -> Option<f64> {
        if !self.is_usable() || !delta_n.is_finite() || delta_n < 1.0 {
            return None;
        }
        let g = self.mu? * (1.0 - 1.0 / delta_n);
        g.is_finite().then_some(g)
    }

    fn failed(n_samples: usize, reason: HitRateFitFailure) -> Self {
        Self {
            mu: None,
            r2: None,
            rms_residual: None,
            n_samples,
            status: HitRateStatus::Failed { reason },
        }
    }
}

/// Fit µ to `(Δn, measured hit rate)` samples (hit rate = hits / shaded pixels, in [0, 1]).
pub fn fit_hit_rate(samples: &[(f64, f64)]) -> HitRateFit {
    let n = samples.len();
    if n == 0 {
        return HitRateFit::failed(0, HitRateFitFailure::Empty);
    }
    let non_finite = samples
        .iter()
        .filter(|(dn, g)| !dn.is_finite() || !g.is_finite())
        .count();
    if non_finite > 0 {
        return HitRateFit::failed(n, HitRateFitFailure::NonFiniteInput { count: non_finite });
    }
    if let Some(&(dn, _)) = samples.iter().find(|s| s.0 < 1.0) {
        return HitRateFit::failed(n, HitRateFitFailure::InvalidDeltaN { value: dn });
    }
    if let Some(&(_, g)) = samples.iter().find(|s| !(0.0..=1.0).contains(&s.1)) {
        return HitRateFit::failed(n, HitRateFitFailure::OutOfRange { value: g });
    }
    let xs: Vec<f64> = samples.iter().map(|s| 1.0 - 1.0 / s.0).collect();
    let sxx: f64 = xs.iter().map(|x| x * x).sum();
    if sxx <= 0.0 {
        return HitRateFit::failed(n, HitRateFitFailure::NoSampleAboveOne);
    }
    let sxy: f64 = xs.iter().zip(samples).map(|(x, s)| x * s.1).sum();
    let raw = sxy / sxx;
    let mu = raw.clamp(0.0, 1.0);
    let observed: Vec<f64> = samples.iter().map(|s| s.1).collect();
    let fitted: Vec<f64> = xs.iter().map(|x| mu * x).collect();
    HitRateFit {
        mu: Some(mu),
        r2: Some(r_squared(&observed, &fitted)),
        rms_residual: Some(rms_residual(&observed, &fitted)),
        n_samples: n,
        status: if raw == mu {
            HitRateStatus::Ok
        } else {
            HitRateStatus::Clamped { raw_mu: raw }
        },
    }
}
