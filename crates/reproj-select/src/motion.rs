//! A profile's records carried to a session of other motion (`reproj_models::motion`): the error
//! model time-warped, the measured errors moved to the periods they stand for there, and the
//! held-out predictions that choose the motion exponent β across profiles.

use reproj_models::ErrorFit;
use reproj_models::motion::{MIN_MOTION_RATIO, period_scale, warped_period};

use crate::{NodeRecord, SetRecord, respect_measurements};

/// `fit` on a session whose motion ages the cache `r` times as fast: ε̂'(Δn) = ε̂(1 + (Δn − 1)·r),
/// that is λ·r for the exponential model.
pub fn warp_fit(fit: &ErrorFit, r: f64) -> ErrorFit {
    let mut out = fit.clone();
    if let Some(l) = out.lambda.as_mut() {
        *l *= r;
    }
    out
}

/// The measured `(Δn, error)` pairs as bounds on a session `r` times as fast: a measurement at
/// Δn stands for period `1 + (Δn − 1)/r` there, rounded down (the error is then claimed at a
/// period no longer than the one it stands for: the cautious side); pairs that land below Δn = 2
/// are dropped.
pub fn warp_measured(measured: &[(u32, f64)], r: f64) -> Vec<(u32, f64)> {
    let mut out: Vec<(u32, f64)> = Vec::new();
    for &(dn, e) in measured {
        let p = warped_period(f64::from(dn), 1.0 / r).floor();
        if !(p.is_finite() && p >= 2.0) {
            continue;
        }
        let p = p.min(f64::from(u32::MAX)) as u32;
        // Two measurements on one period: the larger error holds.
        match out.iter_mut().find(|(q, _)| *q == p) {
            Some(slot) => slot.1 = slot.1.max(e),
            None => out.push((p, e)),
        }
    }
    out
}

impl NodeRecord {
    /// This node on a session whose motion ages the cache `r` times as fast as the profiled one
    /// ([`warp_fit`], [`warp_measured`]). The timing model is kept: the speed on the new session
    /// is measured by `--verify`, not predicted.
    pub fn at_motion(&self, r: f64) -> NodeRecord {
        NodeRecord {
            error: warp_fit(&self.error, r),
            measured_errors: warp_measured(&self.measured_errors, r),
            ..self.clone()
        }
    }
}

impl SetRecord {
    /// The set on a session of other motion, as [`NodeRecord::at_motion`].
    pub fn at_motion(&self, r: f64) -> SetRecord {
        SetRecord {
            error: warp_fit(&self.error, r),
            measured_errors: warp_measured(&self.measured_errors, r),
            ..self.clone()
        }
    }
}

/// One profiled session for [`cross_predictions`]: its motion (pixels per frame) and records.
#[derive(Debug, Clone, Copy)]
pub struct Profiled<'a> {
    pub motion: f64,
    pub nodes: &'a [NodeRecord],
}

/// Held-out predictions at exponent `beta`: for every ordered pair of profiles whose motions
/// differ by at least [`MIN_MOTION_RATIO`], every node both measured with a usable error model,
/// and every period the second measured (Δn ≥ 2) within what the first covers once carried over,
/// the pair (the first's model carried to the second's motion, the second's measurement).
pub fn cross_predictions(profiles: &[Profiled<'_>], beta: f64) -> Vec<(f64, f64)> {
    let mut out = Vec::new();
    for a in profiles {
        for b in profiles {
            let ratio = (b.motion / a.motion).max(a.motion / b.motion);
            if !(ratio.is_finite() && ratio >= MIN_MOTION_RATIO) {
                continue;
            }
            let r = period_scale(a.motion, b.motion, beta);
            for na in a.nodes.iter().filter(|n| n.error.is_ok()) {
                let Some(nb) = b.nodes.iter().find(|n| n.id == na.id) else {
                    continue;
                };
                let carried = na.at_motion(r);
                for &(dn, measured) in nb.measured_errors.iter().filter(|(dn, _)| *dn >= 2) {
                    let covered = !matches!(
                        respect_measurements(&carried.measured_errors, dn),
                        crate::MeasuredBound::Beyond { .. }
                    );
                    if let (true, Some(p)) = (covered, carried.error.predict(f64::from(dn))) {
                        out.push((p, measured));
                    }
                }
            }
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use reproj_models::{ErrorFitOptions, fit_error};

    #[test]
    fn a_faster_session_moves_the_measurements_to_shorter_periods() {
        let m = [(2, 0.01), (10, 0.05), (26, 0.08), (50, 0.1)];
        // Twice as fast: Δn 10 stands for 1 + 9/2 = 5.5 → 5; Δn 2 → 1.5: dropped.
        assert_eq!(
            warp_measured(&m, 2.0),
            vec![(5, 0.05), (13, 0.08), (25, 0.1)]
        );
        // Half as fast: longer periods.
        assert_eq!(warp_measured(&m, 0.5)[0], (3, 0.01));
        // Collapsing onto one period keeps the larger error.
        assert_eq!(warp_measured(&[(3, 0.01), (4, 0.02)], 4.0), Vec::new());
        assert_eq!(
            warp_measured(&[(9, 0.01), (10, 0.02)], 4.0),
            vec![(3, 0.02)]
        );
    }

    #[test]
    fn the_warped_fit_predicts_the_profiled_error_at_the_warped_period() {
        let samples: Vec<(f64, f64)> = [2.0, 6.0, 10.0, 20.0, 30.0]
            .iter()
            .map(|&d| (d, 0.1 * (1.0 - (-0.07f64 * (d - 1.0)).exp())))
            .collect();
        let fit = fit_error(&samples, &ErrorFitOptions::default());
        assert!(fit.is_ok(), "{fit:?}");
        let w = warp_fit(&fit, 3.0);
        for dn in [2.0, 5.0, 9.0] {
            let a = w.predict(dn).unwrap();
            let b = fit.predict(warped_period(dn, 3.0)).unwrap();
            assert!((a - b).abs() < 1e-12, "{dn}: {a} {b}");
        }
    }
}
