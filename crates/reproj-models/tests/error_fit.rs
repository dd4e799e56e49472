//! Error model (eq. 2) fits: recovery from noisy synthetic data and every failure path.

use crate::common::{DELTA_NS, Rng};
use reproj_models::{
    ErrorFit, ErrorFitFailure, ErrorFitOptions, ErrorFitStatus, LAMBDA_MAX, fit_error,
};

fn curve(alpha: f64, lambda: f64, dn: f64) -> f64 {
    alpha * (1.0 - (-lambda * (dn - 1.0)).exp())
}

fn assert_finite(fit: &ErrorFit) {
    for v in [fit.alpha, fit.lambda, fit.r2, fit.rms_residual]
        .into_iter()
        .flatten()
    {
        assert!(v.is_finite(), "non-finite output in {fit:?}");
    }
    // Round-trips through JSON (no NaN/inf that JSON cannot hold).
    let json = serde_json::to_string(fit).unwrap();
    let back: ErrorFit = serde_json::from_str(&json).unwrap();
    assert_eq!(back.is_ok(), fit.is_ok());
    assert_eq!(back.alpha.is_some(), fit.alpha.is_some());
}

fn reason(fit: &ErrorFit) -> &ErrorFitFailure {
    match &fit.status {
        ErrorFitStatus::Failed { reason } => reason,
        ErrorFitStatus::Ok => panic!("expected a failure, got {fit:?}"),
    }
}

#[test]
fn recovers_alpha_lambda_with_noise() {
    let mut rng = Rng::new(7);
    for &(alpha, lambda) in &[(0.02, 0.08), (0.1, 0.02), (0.005, 0.3), (0.3, 0.05)] {
        // Several noisy repetitions per Δn, 2 % relative noise.
        let samples: Vec<(f64, f64)> = DELTA_NS
            .iter()
            .flat_map(|&dn| std::iter::repeat_n(dn, 3))
            .map(|dn| {
                let e = curve(alpha, lambda, dn) * (1.0 + 0.02 * rng.normal());
                (dn, e.max(0.0))
            })
            .collect();
        let fit = fit_error(&samples, &ErrorFitOptions::default());
        assert!(fit.is_ok(), "{fit:?}");
        assert_finite(&fit);
        let (a, l) = (fit.alpha.unwrap(), fit.lambda.unwrap());
        assert!(
            (a - alpha).abs() / alpha < 0.05,
            "α {a} vs {alpha}: {fit:?}"
        );
        assert!(
            (l - lambda).abs() / lambda < 0.15,
            "λ {l} vs {lambda}: {fit:?}"
        );
        assert!(fit.r2.unwrap() > 0.95, "{fit:?}");
        assert!(fit.predict(1.0).unwrap().abs() < 1e-15);
    }
}

#[test]
fn recovers_exact_data_precisely() {
    let samples: Vec<(f64, f64)> = DELTA_NS
        .iter()
        .map(|&dn| (dn, curve(0.04, 0.1, dn)))
        .collect();
    let fit = fit_error(&samples, &ErrorFitOptions::default());
    assert!(fit.is_ok(), "{fit:?}");
    assert!((fit.alpha.unwrap() - 0.04).abs() < 1e-5, "{fit:?}");
    assert!((fit.lambda.unwrap() - 0.1).abs() < 1e-3, "{fit:?}");
    assert!(fit.rms_residual.unwrap() < 1e-6);
}

#[test]
fn constant_nonzero_error_gives_large_lambda() {
    let samples: Vec<(f64, f64)> = DELTA_NS.iter().map(|&dn| (dn, 0.03)).collect();
    let fit = fit_error(&samples, &ErrorFitOptions::default());
    assert!(fit.is_ok(), "{fit:?}");
    assert_finite(&fit);
    assert!((fit.alpha.unwrap() - 0.03).abs() < 1e-6, "{fit:?}");
    assert!(
        fit.lambda.unwrap() > 10.0 && fit.lambda.unwrap() <= LAMBDA_MAX,
        "{fit:?}"
    );
}

#[test]
fn constant_error_with_noise_is_ok() {
    let mut rng = Rng::new(3);
    let samples: Vec<(f64, f64)> = DELTA_NS
        .iter()
        .map(|&dn| (dn, 0.03 * (1.0 + 0.03 * rng.normal())))
        .collect();
    let fit = fit_error(&samples, &ErrorFitOptions::default());
    assert!(fit.is_ok(), "{fit:?}");
    assert_finite(&fit);
}

#[test]
fn linear_error_is_ok_with_small_lambda() {
    let samples: Vec<(f64, f64)> = DELTA_NS.iter().map(|&dn| (dn, 1e-3 * (dn - 1.0))).collect();
    let fit = fit_error(&samples, &ErrorFitOptions::default());
    assert!(fit.is_ok(), "{fit:?}");
    assert_finite(&fit);
    let p = fit.predict(26.0).unwrap();
    assert!((p - 0.025).abs() < 0.001, "{p} {fit:?}");
}

#[test]
fn zero_error_is_a_perfect_cache() {
    let samples: Vec<(f64, f64)> = DELTA_NS.iter().map(|&dn| (dn, 0.0)).collect();
    let fit = fit_error(&samples, &ErrorFitOptions::default());
    assert_eq!(fit.status, ErrorFitStatus::Ok);
    assert_eq!(fit.alpha, Some(0.0));
    assert_eq!(fit.predict(50.0), Some(0.0));
    assert_finite(&fit);
}

#[test]
fn decreasing_error_is_not_exponential() {
    let samples: Vec<(f64, f64)> = DELTA_NS.iter().map(|&dn| (dn, 0.05 / dn)).collect();
    let fit = fit_error(&samples, &ErrorFitOptions::default());
    assert!(
        matches!(reason(&fit), ErrorFitFailure::Decreasing { .. }),
        "{fit:?}"
    );
    assert_finite(&fit);
}

#[test]
fn non_monotone_error_is_not_exponential() {
    let samples: Vec<(f64, f64)> = DELTA_NS
        .iter()
        .enumerate()
        .map(|(i, &dn)| (dn, if i % 2 == 0 { 0.001 } else { 0.05 }))
        .collect();
    let fit = fit_error(&samples, &ErrorFitOptions::default());
    assert!(
        matches!(reason(&fit), ErrorFitFailure::PoorFit { .. }),
        "{fit:?}"
    );
    assert_finite(&fit);
}

#[test]
fn single_delta_n_fails() {
    let samples = vec![(10.0, 0.02), (10.0, 0.021), (10.0, 0.019)];
    let fit = fit_error(&samples, &ErrorFitOptions::default());
    assert_eq!(
        reason(&fit),
        &ErrorFitFailure::TooFewDistinctDeltaN {
            found: 1,
            required: 3
        }
    );
    assert_finite(&fit);
}

#[test]
fn empty_input_fails() {
    let fit = fit_error(&[], &ErrorFitOptions::default());
    assert_eq!(reason(&fit), &ErrorFitFailure::Empty);
    assert_finite(&fit);
}

#[test]
fn nan_and_infinite_measurements_fail() {
    for bad in [f64::NAN, f64::INFINITY, f64::NEG_INFINITY] {
        let mut samples: Vec<(f64, f64)> = DELTA_NS
            .iter()
            .map(|&dn| (dn, curve(0.02, 0.1, dn)))
            .collect();
        samples[3].1 = bad;
        let fit = fit_error(&samples, &ErrorFitOptions::default());
        assert_eq!(reason(&fit), &ErrorFitFailure::NonFiniteInput { count: 1 });
        assert_finite(&fit);
        samples[3] = (bad, 0.01);
        let fit = fit_error(&samples, &ErrorFitOptions::default());
        assert_eq!(reason(&fit), &ErrorFitFailure::NonFiniteInput { count: 1 });
    }
}

#[test]
fn invalid_delta_n_and_negative_error_fail() {
    let fit = fit_error(
        &[(0.5, 0.1), (2.0, 0.1), (3.0, 0.1)],
        &ErrorFitOptions::default(),
    );
    assert!(matches!(
        reason(&fit),
        ErrorFitFailure::InvalidDeltaN { .. }
    ));
    let fit = fit_error(
        &[(2.0, -0.1), (3.0, 0.1), (4.0, 0.1)],
        &ErrorFitOptions::default(),
    );
    assert!(matches!(
        reason(&fit),
        ErrorFitFailure::NegativeError { .. }
    ));
}

#[test]
fn iteration_limit_reports_non_convergence() {
    let samples: Vec<(f64, f64)> = DELTA_NS
        .iter()
        .map(|&dn| (dn, curve(0.04, 0.05, dn)))
        .collect();
    let opts = ErrorFitOptions {
        max_iters: 2,
        ..ErrorFitOptions::default()
    };
    let fit = fit_error(&samples, &opts);
    assert!(
        matches!(reason(&fit), ErrorFitFailure::DidNotConverge { .. }),
        "{fit:?}"
    );
    assert_finite(&fit);
}

#[test]
fn failure_reasons_read_well() {
    let r = ErrorFitFailure::TooFewDistinctDeltaN {
        found: 1,
        required: 3,
    };
    assert_eq!(r.to_string(), "only 1 distinct Δn > 1, need 3");
}

#[test]
fn noisy_exponential_curves_are_not_rejected() {
    // Random α in [1e-4, 0.5], λ in [0.005, 3] (log-uniform), 3 % noise: all Ok, predictions close.
    let mut rng = Rng::new(42);
    for _ in 0..200 {
        let alpha = (1e-4f64.ln() + rng.uniform() * (0.5f64.ln() - 1e-4f64.ln())).exp();
        let lambda = (0.005f64.ln() + rng.uniform() * (3f64.ln() - 0.005f64.ln())).exp();
        let samples: Vec<(f64, f64)> = DELTA_NS
            .iter()
            .map(|&dn| (dn, curve(alpha, lambda, dn) * (1.0 + 0.03 * rng.normal())))
            .collect();
        let fit = fit_error(&samples, &ErrorFitOptions::default());
        assert!(fit.is_ok(), "α {alpha} λ {lambda}: {fit:?}");
        for &dn in &DELTA_NS {
            let (p, t) = (fit.predict(dn).unwrap(), curve(alpha, lambda, dn));
            assert!(
                (p - t).abs() < 0.1 * alpha,
                "α {alpha} λ {lambda} Δn {dn}: {p} vs {t}"
            );
        }
    }
}
