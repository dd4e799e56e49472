//! Hit-rate model (eq. 4) fits.

use crate::common::{DELTA_NS, Rng};
use reproj_models::{HitRateFit, HitRateFitFailure, HitRateStatus, fit_hit_rate};

fn failure(fit: &HitRateFit) -> &HitRateFitFailure {
    match &fit.status {
        HitRateStatus::Failed { reason } => reason,
        _ => panic!("expected failure: {fit:?}"),
    }
}

#[test]
fn recovers_mu_with_noise() {
    let mut rng = Rng::new(11);
    let samples: Vec<(f64, f64)> = DELTA_NS
        .iter()
        .flat_map(|&dn| std::iter::repeat_n(dn, 4))
        .map(|dn| {
            (
                dn,
                (0.9 * (1.0 - 1.0 / dn) + 0.01 * rng.normal()).clamp(0.0, 1.0),
            )
        })
        .collect();
    let fit = fit_hit_rate(&samples);
    assert_eq!(fit.status, HitRateStatus::Ok);
    assert!((fit.mu.unwrap() - 0.9).abs() < 0.01, "{fit:?}");
    assert!(fit.r2.unwrap() > 0.8, "{fit:?}");
    assert!((fit.gamma(2.0).unwrap() - fit.mu.unwrap() * 0.5).abs() < 1e-12);
    let json = serde_json::to_string(&fit).unwrap();
    assert_eq!(
        serde_json::from_str::<HitRateFit>(&json).unwrap().status,
        fit.status
    );
}

#[test]
fn clamps_mu_to_one() {
    let fit = fit_hit_rate(&[(2.0, 1.0), (3.0, 1.0)]);
    assert!(matches!(fit.status, HitRateStatus::Clamped { raw_mu } if raw_mu > 1.0));
    assert_eq!(fit.mu, Some(1.0));
    assert!(fit.is_usable());
}

#[test]
fn constant_hit_rate_fits_with_a_finite_r2() {
    let samples: Vec<(f64, f64)> = DELTA_NS.iter().map(|&dn| (dn, 0.5)).collect();
    let fit = fit_hit_rate(&samples);
    assert!(fit.is_usable());
    assert!(fit.r2.unwrap().is_finite() && fit.rms_residual.unwrap().is_finite());
}

#[test]
fn single_delta_n_is_enough_for_mu() {
    let fit = fit_hit_rate(&[(10.0, 0.72)]);
    assert!((fit.mu.unwrap() - 0.8).abs() < 1e-12);
}

#[test]
fn failures() {
    assert_eq!(failure(&fit_hit_rate(&[])), &HitRateFitFailure::Empty);
    assert_eq!(
        failure(&fit_hit_rate(&[(2.0, f64::NAN), (3.0, 0.5)])),
        &HitRateFitFailure::NonFiniteInput { count: 1 }
    );
    assert_eq!(
        failure(&fit_hit_rate(&[(f64::INFINITY, 0.5)])),
        &HitRateFitFailure::NonFiniteInput { count: 1 }
    );
    assert_eq!(
        failure(&fit_hit_rate(&[(1.0, 0.0), (1.0, 0.0)])),
        &HitRateFitFailure::NoSampleAboveOne
    );
    assert!(matches!(
        failure(&fit_hit_rate(&[(2.0, 1.5)])),
        HitRateFitFailure::OutOfRange { .. }
    ));
    assert!(matches!(
        failure(&fit_hit_rate(&[(0.0, 0.5)])),
        HitRateFitFailure::InvalidDeltaN { .. }
    ));
    let f = fit_hit_rate(&[]);
    assert_eq!(f.gamma(10.0), None);
    assert!(!f.is_usable());
}
