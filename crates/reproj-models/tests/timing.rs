//! Timing model (eq. 3) fits: recovery, hold-out, clamping and every rank-deficient case.

use crate::common::Rng;
use reproj_models::{
    FrameTiming, HitRateFit, TimingFit, TimingFitFailure, TimingParam, TimingStatus, TimingWarning,
    fit_timing, fit_timing_with_holdout, predicted_frame_ms,
};

const H: f64 = 2e-6; // ms per hit pixel
const MISS: f64 = 2e-5; // ms per miss pixel
const O: f64 = 0.4; // ms per frame

/// Frames with varying coverage and hit rate, times with 1 % noise.
fn frames(rng: &mut Rng, n: usize, h: f64, m: f64, o: f64) -> Vec<FrameTiming> {
    (0..n)
        .map(|_| {
            let pixels = 200_000.0 + 600_000.0 * rng.uniform();
            let rate = 0.2 + 0.75 * rng.uniform();
            let hits = (pixels * rate) as u64;
            let misses = pixels as u64 - hits;
            let t = o + hits as f64 * h + misses as f64 * m;
            FrameTiming {
                hits,
                misses,
                time_ms: t * (1.0 + 0.01 * rng.normal()),
            }
        })
        .collect()
}

fn assert_finite(fit: &TimingFit) {
    let vals = [
        fit.hit_ms,
        fit.miss_ms,
        fit.overhead_ms,
        fit.mean_pixels,
        fit.r2,
        fit.rms_residual_ms,
        fit.holdout_rms_ms,
        fit.holdout_mean_relative_error,
    ];
    for v in vals.into_iter().flatten() {
        assert!(v.is_finite(), "non-finite output in {fit:?}");
    }
    let json = serde_json::to_string(fit).unwrap();
    let back: TimingFit = serde_json::from_str(&json).unwrap();
    assert_eq!(back.status, fit.status);
    assert_eq!(back.warnings.len(), fit.warnings.len());
}

fn rank_deficient(fit: &TimingFit) -> (usize, bool, Vec<TimingParam>) {
    match &fit.status {
        TimingStatus::RankDeficient {
            rank,
            overhead_absorbed,
            undetermined,
        } => (*rank, *overhead_absorbed, undetermined.clone()),
        s => panic!("expected rank deficient, got {s:?}"),
    }
}

#[test]
fn recovers_costs_with_noise_and_holdout() {
    let mut rng = Rng::new(5);
    let train = frames(&mut rng, 120, H, MISS, O);
    let hold = frames(&mut rng, 30, H, MISS, O);
    let fit = fit_timing_with_holdout(&train, &hold);
    assert_eq!(fit.status, TimingStatus::Ok, "{fit:?}");
    assert!(fit.warnings.is_empty(), "{fit:?}");
    assert_finite(&fit);
    assert!((fit.hit_ms.unwrap() - H).abs() / H < 0.1, "{fit:?}");
    assert!((fit.miss_ms.unwrap() - MISS).abs() / MISS < 0.03, "{fit:?}");
    assert!((fit.overhead_ms.unwrap() - O).abs() / O < 0.2, "{fit:?}");
    assert!(fit.r2.unwrap() > 0.98);
    assert_eq!(fit.n_holdout, 30);
    assert!(fit.holdout_mean_relative_error.unwrap() < 0.03, "{fit:?}");
    assert!(fit.holdout_rms_ms.unwrap() < 0.2);
    assert_eq!(fit.rank, 3);
}

#[test]
fn predictions_follow_eq5() {
    let fit = TimingFit::from_costs(1e-6, 1e-5, 0.5, 500_000.0);
    let mu = HitRateFit::from_mu(0.9);
    // Δn = 10: γ = 0.81, r̂ = 0.81e-6 + 0.19e-5.
    let r = fit.per_pixel_ms(0.81).unwrap();
    assert!((r - (0.81e-6 + 0.19e-5)).abs() < 1e-18);
    let t = predicted_frame_ms(&fit, &mu, 10.0, 500_000.0).unwrap();
    assert!((t - (0.5 + 500_000.0 * r)).abs() < 1e-12);
    assert_eq!(fit.predict_counts(10, 0), Some(0.5 + 10.0 * 1e-6));
}

#[test]
fn negative_cost_is_clamped_with_warning() {
    // True overhead is negative: clamp to 0, refit the per-pixel costs.
    let mut rng = Rng::new(9);
    let fr = frames(&mut rng, 60, H, MISS, -2.0);
    let fr: Vec<FrameTiming> = fr
        .into_iter()
        .map(|f| FrameTiming {
            time_ms: f.time_ms.max(0.0),
            ..f
        })
        .collect();
    let fit = fit_timing(&fr);
    assert_eq!(fit.status, TimingStatus::Ok);
    assert_eq!(fit.overhead_ms, Some(0.0));
    assert!(fit.warnings.iter().any(|w| matches!(
        w,
        TimingWarning::NegativeClamped { param: TimingParam::Overhead, raw } if *raw < 0.0
    )));
    assert!(fit.hit_ms.unwrap() >= 0.0 && fit.miss_ms.unwrap() >= 0.0);
    assert!(fit.is_usable());
    assert_finite(&fit);
}

#[test]
fn constant_pixel_count_absorbs_overhead() {
    // The paper's validation scene: M constant, so h + m is the same in every frame.
    let mut rng = Rng::new(1);
    let m_px = 400_000u64;
    let fr: Vec<FrameTiming> = (0..50)
        .map(|_| {
            let hits = (m_px as f64 * (0.1 + 0.8 * rng.uniform())) as u64;
            let misses = m_px - hits;
            let t = O + hits as f64 * H + misses as f64 * MISS;
            FrameTiming {
                hits,
                misses,
                time_ms: t * (1.0 + 0.005 * rng.normal()),
            }
        })
        .collect();
    let fit = fit_timing(&fr);
    let (rank, absorbed, undetermined) = rank_deficient(&fit);
    assert_eq!(rank, 2);
    assert!(absorbed);
    assert!(undetermined.is_empty());
    assert_eq!(fit.overhead_ms, Some(0.0));
    assert!(fit.is_usable());
    assert_finite(&fit);
    // Frame predictions at that pixel count are right.
    let t = fit.frame_ms(0.5, m_px as f64).unwrap();
    let truth = O + m_px as f64 * (0.5 * H + 0.5 * MISS);
    assert!((t - truth).abs() / truth < 0.01, "{t} vs {truth}");
}

#[test]
fn identical_hit_counts_are_rank_deficient() {
    let mut rng = Rng::new(2);
    let fr: Vec<FrameTiming> = (0..40)
        .map(|_| {
            let misses = 100_000 + (300_000.0 * rng.uniform()) as u64;
            let t = O + 50_000.0 * H + misses as f64 * MISS;
            FrameTiming {
                hits: 50_000,
                misses,
                time_ms: t,
            }
        })
        .collect();
    let fit = fit_timing(&fr);
    let (rank, absorbed, undetermined) = rank_deficient(&fit);
    assert_eq!(rank, 2);
    assert!(!absorbed);
    assert_eq!(undetermined, vec![TimingParam::Hit, TimingParam::Overhead]);
    assert!((fit.miss_ms.unwrap() - MISS).abs() / MISS < 1e-6, "{fit:?}");
    assert!(!fit.is_usable());
    assert_eq!(fit.frame_ms(0.5, 1e5), None);
    assert_finite(&fit);
}

#[test]
fn all_hit_frames_leave_miss_cost_undetermined() {
    let mut rng = Rng::new(4);
    let fr: Vec<FrameTiming> = (0..40)
        .map(|_| {
            let hits = 100_000 + (300_000.0 * rng.uniform()) as u64;
            FrameTiming {
                hits,
                misses: 0,
                time_ms: O + hits as f64 * H,
            }
        })
        .collect();
    let fit = fit_timing(&fr);
    let (_, absorbed, undetermined) = rank_deficient(&fit);
    assert!(!absorbed);
    assert_eq!(undetermined, vec![TimingParam::Miss]);
    assert!((fit.hit_ms.unwrap() - H).abs() / H < 1e-6);
    assert!((fit.overhead_ms.unwrap() - O).abs() / O < 1e-6);
    assert!(!fit.is_usable());
    assert_finite(&fit);
}

#[test]
fn all_miss_frames_leave_hit_cost_undetermined() {
    let mut rng = Rng::new(6);
    let fr: Vec<FrameTiming> = (0..40)
        .map(|_| {
            let misses = 100_000 + (300_000.0 * rng.uniform()) as u64;
            FrameTiming {
                hits: 0,
                misses,
                time_ms: O + misses as f64 * MISS,
            }
        })
        .collect();
    let fit = fit_timing(&fr);
    let (_, _, undetermined) = rank_deficient(&fit);
    assert_eq!(undetermined, vec![TimingParam::Hit]);
    assert!((fit.miss_ms.unwrap() - MISS).abs() / MISS < 1e-6);
    assert_finite(&fit);
}

#[test]
fn all_miss_frames_with_constant_coverage() {
    let fr: Vec<FrameTiming> = (0..10)
        .map(|i| FrameTiming {
            hits: 0,
            misses: 300_000,
            time_ms: 6.4 + 0.01 * (i % 3) as f64,
        })
        .collect();
    let fit = fit_timing(&fr);
    let (rank, absorbed, undetermined) = rank_deficient(&fit);
    assert_eq!(rank, 1);
    assert!(absorbed);
    assert_eq!(undetermined, vec![TimingParam::Hit]);
    assert!(fit.miss_ms.unwrap() > 0.0);
    assert_finite(&fit);
}

#[test]
fn constant_frames_determine_nothing_per_pixel() {
    let fr = vec![
        FrameTiming {
            hits: 1000,
            misses: 3000,
            time_ms: 2.0
        };
        20
    ];
    let fit = fit_timing(&fr);
    let (rank, absorbed, undetermined) = rank_deficient(&fit);
    assert_eq!(rank, 1);
    assert!(absorbed);
    assert_eq!(undetermined, vec![TimingParam::Hit, TimingParam::Miss]);
    assert!(!fit.is_usable());
    // The fitted times still reproduce the data.
    assert!(fit.rms_residual_ms.unwrap() < 1e-9);
    assert_finite(&fit);
}

#[test]
fn holdout_skipped_when_not_usable() {
    let fr = vec![
        FrameTiming {
            hits: 1000,
            misses: 3000,
            time_ms: 2.0
        };
        5
    ];
    let fit = fit_timing_with_holdout(&fr, &fr);
    assert_eq!(fit.holdout_rms_ms, None);
    assert!(
        fit.warnings
            .iter()
            .any(|w| matches!(w, TimingWarning::HoldoutSkipped { .. }))
    );
    let mut bad = fr.clone();
    bad[0].time_ms = f64::NAN;
    let fit = fit_timing_with_holdout(&frames(&mut Rng::new(1), 20, H, MISS, O), &bad);
    assert_eq!(fit.holdout_rms_ms, None);
    assert!(fit.is_usable());
    assert_finite(&fit);
}

#[test]
fn failures() {
    let f = fit_timing(&[]);
    assert_eq!(
        f.status,
        TimingStatus::Failed {
            reason: TimingFitFailure::Empty
        }
    );
    assert_finite(&f);
    for bad in [f64::NAN, f64::INFINITY] {
        let mut fr = frames(&mut Rng::new(8), 10, H, MISS, O);
        fr[2].time_ms = bad;
        let f = fit_timing(&fr);
        assert_eq!(
            f.status,
            TimingStatus::Failed {
                reason: TimingFitFailure::NonFiniteInput { count: 1 }
            }
        );
        assert!(!f.is_usable());
        assert_finite(&f);
    }
    let f = fit_timing(&[FrameTiming {
        hits: 0,
        misses: 0,
        time_ms: 1.0,
    }]);
    assert_eq!(
        f.status,
        TimingStatus::Failed {
            reason: TimingFitFailure::NoShadedPixels
        }
    );
    let f = fit_timing(&[FrameTiming {
        hits: 1,
        misses: 1,
        time_ms: -1.0,
    }]);
    assert!(matches!(
        f.status,
        TimingStatus::Failed {
            reason: TimingFitFailure::NegativeTime { .. }
        }
    ));
}

#[test]
fn single_frame_is_rank_deficient_not_garbage() {
    let f = fit_timing(&[FrameTiming {
        hits: 100,
        misses: 300,
        time_ms: 1.0,
    }]);
    let (rank, _, _) = rank_deficient(&f);
    assert_eq!(rank, 1);
    assert!(!f.is_usable());
    assert_finite(&f);
}

/// Nearly constant pixel counts make hits, misses and the overhead almost collinear: with noise
/// the raw solution can put both per-pixel costs below zero. Only the worst one is wrong; the miss
/// cost (what Δn actually changes) must survive.
#[test]
fn collinear_frames_keep_the_real_miss_cost() {
    let mut frames = Vec::new();
    let mut seed = 7u64;
    let mut noise = || {
        seed = seed
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        ((seed >> 33) as f64 / (1u64 << 31) as f64) - 0.5
    };
    for &miss_frac in &[0.5, 0.1, 0.06, 0.045, 0.035, 0.03, 0.026] {
        for i in 0..40 {
            let pixels = 50_000.0 + 800.0 * ((i % 7) as f64 / 7.0) + 300.0 * noise();
            let misses = (pixels * miss_frac).round() as u64;
            let hits = pixels as u64 - misses;
            // Truth: overhead 1.95 ms, a miss 1.28e-4 ms, a hit free; noise of ±0.4 ms.
            let time_ms = 1.95 + 1.28e-4 * misses as f64 + 0.8 * noise();
            frames.push(FrameTiming {
                hits,
                misses,
                time_ms,
            });
        }
    }
    let fit = fit_timing(&frames);
    let miss = fit.miss_ms.unwrap();
    assert!(miss > 0.8e-4 && miss < 1.8e-4, "{fit:?}");
    // The frame time at half misses is predicted, not just the overhead.
    let t = fit.predict_counts(25_000, 25_000).unwrap();
    assert!((t - (1.95 + 1.28e-4 * 25_000.0)).abs() < 0.6, "{t} {fit:?}");
}
