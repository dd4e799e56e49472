//! Motion as a model variable: how fast a session moves on screen, and how a node's error model
//! carries over to a session that moves faster or slower than the profiled one.
//!
//! A cached value ages with the motion it has to follow: at Δn frames between refreshes, a
//! session that moves twice as fast has had about twice as much reprojection, resampling and
//! disocclusion by the time it refreshes. So the error model transfers by *time warp*: the error
//! at Δn on a session of motion `m` is the profiled error at the period `1 + (Δn − 1)·r`, with
//! `r = (m / m_profiled)^β` ([`period_scale`]). For the exponential model
//! `ε̂(Δn) = α (1 − e^(−λ (Δn − 1)))` this scales λ by `r`.
//!
//! β says how much the error follows the motion: 0 not at all, 1 proportionally. With two or more
//! profiles of one shader whose motions differ, [`fit_exponent`] chooses it by how well each
//! profile predicts the others' measured errors (held out); a node set that does not need it gets
//! β = 0 when that predicts as well. With one profile there is nothing to fit: β = 1 is assumed
//! and every prediction for another motion says so. A motion outside the profiled range is
//! flagged by [`MotionRange::covers`].

use serde::{Deserialize, Serialize};

/// How fast a session moves, measured from its geometry and camera (no rendering).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Motion {
    /// Mean over frames 1.. of the mean on-screen distance, in pixels, that a visible surface
    /// point moved since the previous frame (camera and object motion together).
    pub pixels_per_frame: f64,
    /// The same per frame (frame 0: 0), for segments of one session.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub per_frame: Vec<f64>,
    /// Mean per-frame change, in degrees, of the direction from a visible surface point to the
    /// camera, in the object's own frame: what view-dependent terms (reflections, specular)
    /// follow.
    pub view_deg_per_frame: f64,
    /// The same for the direction to the light.
    pub light_deg_per_frame: f64,
}

impl Motion {
    /// Whether every figure is a measurement (finite, not negative).
    pub fn check(&self) -> Result<(), String> {
        let ok = |x: f64| x.is_finite() && x >= 0.0;
        if ![
            self.pixels_per_frame,
            self.view_deg_per_frame,
            self.light_deg_per_frame,
        ]
        .into_iter()
        .all(ok)
            || !self.per_frame.iter().copied().all(ok)
        {
            return Err("a motion figure is negative or not finite".into());
        }
        Ok(())
    }

    /// `3.1 px/frame (view 0.4°/frame)`.
    pub fn display(&self) -> String {
        format!(
            "{:.2} px/frame (view {:.2}°/frame)",
            self.pixels_per_frame, self.view_deg_per_frame
        )
    }
}

/// Below this many pixels per frame a session is taken as static: no motion to scale by.
pub const STATIC_PIXELS: f64 = 1e-3;

/// The factor on the period's age, `r = (to / from)^β`, that carries an error model profiled at
/// motion `from` to motion `to` (pixels per frame); 1 when either is static or not finite.
pub fn period_scale(from: f64, to: f64, beta: f64) -> f64 {
    if !(from.is_finite() && to.is_finite() && beta.is_finite())
        || from < STATIC_PIXELS
        || to < STATIC_PIXELS
    {
        return 1.0;
    }
    (to / from).powf(beta)
}

/// The profiled period that corresponds to period `delta_n` on a session whose motion is `r`
/// times the profiled one's in age ([`period_scale`]): `1 + (Δn − 1)·r`.
pub fn warped_period(delta_n: f64, r: f64) -> f64 {
    1.0 + (delta_n - 1.0) * r
}

/// Where β came from.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum ExponentSource {
    /// Chosen by the held-out errors of two or more profiles of different motion.
    Fitted,
    /// Assumed (β = 1): one profiled motion, or profiles whose motions are too close to tell.
    Assumed,
}

/// The motion exponent β and how well it predicts.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct MotionExponent {
    pub beta: f64,
    pub source: ExponentSource,
    /// Held-out predictions it rests on (0 when assumed).
    pub samples: usize,
    /// Root-mean-square log ratio of predicted to measured error over them, at β and at β = 0
    /// (`None` when assumed): the gain motion brings.
    pub rms_log_error: Option<f64>,
    pub rms_log_error_static: Option<f64>,
}

impl MotionExponent {
    /// β = 1, assumed.
    pub fn assumed() -> MotionExponent {
        MotionExponent {
            beta: 1.0,
            source: ExponentSource::Assumed,
            samples: 0,
            rms_log_error: None,
            rms_log_error_static: None,
        }
    }
}

/// Profiles whose motions differ by less than this factor cannot tell β.
pub const MIN_MOTION_RATIO: f64 = 1.2;

/// The candidate exponents [`fit_exponent`] tries: 0, 0.1, …, 2.
pub fn exponent_grid() -> impl Iterator<Item = f64> {
    (0..=20).map(|i| f64::from(i) / 10.0)
}

/// Choose β from held-out predictions: `predict(beta)` gives, for every (profile A, profile B,
/// measurement of B) where the motions differ by at least [`MIN_MOTION_RATIO`], the pair
/// (predicted by A carried to B's motion, measured on B) — or `None` where A cannot predict that
/// period. The β with the least RMS log ratio wins; 0 when it predicts within 2 % of the best
/// (motion is modelled only where it predicts better). Assumed (β = 1) without any sample.
pub fn fit_exponent(predict: impl Fn(f64) -> Vec<(f64, f64)>) -> MotionExponent {
    let rms = |beta: f64| -> (f64, usize) {
        let logs: Vec<f64> = predict(beta)
            .into_iter()
            .filter(|(p, m)| p.is_finite() && m.is_finite() && *p > 0.0 && *m > 0.0)
            .map(|(p, m)| (p / m).ln().powi(2))
            .collect();
        if logs.is_empty() {
            return (f64::INFINITY, 0);
        }
        (
            (logs.iter().sum::<f64>() / logs.len() as f64).sqrt(),
            logs.len(),
        )
    };
    let (static_rms, n0) = rms(0.0);
    if n0 == 0 {
        return MotionExponent::assumed();
    }
    let (mut best, mut best_rms, mut best_n) = (0.0, static_rms, n0);
    for beta in exponent_grid() {
        let (r, n) = rms(beta);
        if r < best_rms {
            (best, best_rms, best_n) = (beta, r, n);
        }
    }
    if best_rms >= static_rms * 0.98 {
        (best, best_rms, best_n) = (0.0, static_rms, n0);
    }
    MotionExponent {
        beta: best,
        source: ExponentSource::Fitted,
        samples: best_n,
        rms_log_error: Some(best_rms),
        rms_log_error_static: Some(static_rms),
    }
}

/// The motions a set of profiles covers, pixels per frame.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MotionRange {
    pub min: f64,
    pub max: f64,
}

impl MotionRange {
    /// The range of `motions` (`None` without any).
    pub fn of(motions: impl IntoIterator<Item = f64>) -> Option<MotionRange> {
        motions
            .into_iter()
            .filter(|m| m.is_finite())
            .fold(None, |r: Option<MotionRange>, m| {
                Some(r.map_or(MotionRange { min: m, max: m }, |r| MotionRange {
                    min: r.min.min(m),
                    max: r.max.max(m),
                }))
            })
    }

    /// Whether `m` lies within the range, give or take 10 %.
    pub fn covers(&self, m: f64) -> bool {
        m >= self.min / 1.1 && m <= self.max * 1.1
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_period_scale_follows_the_motion_ratio_to_the_power_beta() {
        assert_eq!(period_scale(2.0, 4.0, 1.0), 2.0);
        assert!((period_scale(2.0, 8.0, 0.5) - 2.0).abs() < 1e-12);
        assert_eq!(period_scale(2.0, 8.0, 0.0), 1.0);
        // Static or broken: no scaling.
        assert_eq!(period_scale(0.0, 8.0, 1.0), 1.0);
        assert_eq!(period_scale(2.0, f64::NAN, 1.0), 1.0);
        assert_eq!(warped_period(11.0, 2.0), 21.0);
        assert_eq!(warped_period(1.0, 3.0), 1.0);
    }

    /// Errors that truly follow the time warp with β = 0.7: the fit finds it; errors that do not
    /// depend on motion at all: β = 0.
    #[test]
    fn the_exponent_is_fitted_from_held_out_errors_and_zero_when_motion_does_not_help() {
        let model = |dn: f64| 0.1 * (1.0 - (-0.05 * (dn - 1.0)).exp());
        let (ma, mb) = (1.0, 4.0);
        let true_beta = 0.7;
        let samples = move |beta: f64, truth: f64| -> Vec<(f64, f64)> {
            let mut out = Vec::new();
            for dn in [2.0, 6.0, 10.0, 20.0] {
                // A predicts B and B predicts A.
                for (from, to) in [(ma, mb), (mb, ma)] {
                    let measured_at = |m: f64| model(warped_period(dn, period_scale(ma, m, truth)));
                    let predicted = model(warped_period(
                        warped_period(dn, period_scale(from, to, beta)),
                        period_scale(ma, from, truth),
                    ));
                    out.push((predicted, measured_at(to)));
                }
            }
            out
        };
        let fit = fit_exponent(|b| samples(b, true_beta));
        assert_eq!(fit.source, ExponentSource::Fitted);
        assert!((fit.beta - true_beta).abs() < 0.11, "{fit:?}");
        assert!(fit.rms_log_error.unwrap() < fit.rms_log_error_static.unwrap());
        let flat = fit_exponent(|b| samples(b, 0.0));
        assert_eq!(flat.beta, 0.0, "{flat:?}");
        // Nothing to go by: assumed.
        assert_eq!(fit_exponent(|_| Vec::new()), MotionExponent::assumed());
    }

    #[test]
    fn a_range_covers_its_motions_give_or_take_ten_percent() {
        let r = MotionRange::of([2.0, 5.0]).unwrap();
        assert!(r.covers(1.9) && r.covers(5.4) && !r.covers(6.0) && !r.covers(1.0));
        assert!(MotionRange::of([]).is_none());
        let m = Motion {
            pixels_per_frame: 1.0,
            per_frame: vec![0.0, f64::NAN],
            view_deg_per_frame: 0.1,
            light_deg_per_frame: 0.0,
        };
        assert!(m.check().is_err());
    }
}
