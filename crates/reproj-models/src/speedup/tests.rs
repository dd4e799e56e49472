use super::*;

/// SplitMix64: a small, well-mixed generator for the synthetic streams.
#[derive(Debug)]
struct SplitMix(u64);

impl SplitMix {
    fn next(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        z ^ (z >> 31)
    }
}

/// A deterministic stream of frame times: content that varies across the session, noise,
/// occasional stalls, and a load factor the caller sets per block.
struct Synth {
    rng: SplitMix,
}

impl Synth {
    fn uniform(&mut self) -> f64 {
        (self.rng.next() >> 11) as f64 / (1u64 << 53) as f64
    }

    /// `block` frames from `start` of a subject whose quiet frame time is `base_ms` scaled
    /// by the content curve, under `load`, with a stall of ×`spike` on `spike_p` of frames.
    fn block(
        &mut self,
        start: u32,
        block: u32,
        base_ms: f64,
        load: f64,
        spike_p: f64,
        spike: f64,
    ) -> Vec<f64> {
        (start..start + block)
            .map(|f| {
                let content = 1.0 + 0.3 * (f64::from(f) * 0.07).sin();
                let noise = 1.0 + 0.04 * (self.uniform() - 0.5);
                let stall = if self.uniform() < spike_p { spike } else { 1.0 };
                base_ms * content * noise * load * stall
            })
            .collect()
    }
}

/// A whole run: `rounds` rounds of the baseline (5 ms) and a candidate `ratio` times faster,
/// in [`round_order`], with `load(round, slot)` scaling each block.
fn run(
    seed: u64,
    rounds: u32,
    ratio: f64,
    spike_p: f64,
    load: impl Fn(u32, usize) -> f64,
) -> (Vec<u32>, Vec<f64>, Vec<f64>) {
    let mut s = Synth {
        rng: SplitMix(seed),
    };
    let (mut b, mut c) = (Vec::new(), Vec::new());
    let strata: Vec<u32> = (0..rounds).map(stratum).collect();
    for r in 0..rounds {
        let start = window_start(r, 150, 16);
        for (slot, who) in round_order(r, 1).into_iter().enumerate() {
            let l = load(r, slot);
            match who {
                Subject::Baseline => {
                    b.push(block_ms(&s.block(start, 16, 5.0, l, spike_p, 1.8)).unwrap())
                }
                Subject::Candidate(_) => {
                    c.push(block_ms(&s.block(start, 16, 5.0 / ratio, l, spike_p, 1.8)).unwrap())
                }
            }
        }
    }
    (strata, b, c)
}

#[test]
fn order_alternates_and_windows_fit() {
    assert_eq!(
        round_order(0, 2),
        [
            Subject::Baseline,
            Subject::Candidate(0),
            Subject::Candidate(1)
        ]
    );
    assert_eq!(round_order(1, 2), round_order(0, 2));
    assert_eq!(
        round_order(WINDOWS, 2),
        [
            Subject::Candidate(1),
            Subject::Candidate(0),
            Subject::Baseline
        ]
    );
    for r in 0..100 {
        let s = window_start(r, 150, 16);
        assert!(s + 16 <= 150);
    }
    assert_eq!(window_start(5, 10, 16), 0);
    // The windows spread over the session.
    let starts: Vec<u32> = (0..8).map(|r| window_start(r, 150, 16)).collect();
    assert!(starts.iter().any(|s| *s < 40) && starts.iter().any(|s| *s > 90));
}

#[test]
fn block_figure_trims_stalls_and_drops_bad_frames() {
    let mut v = vec![5.0; 10];
    v[3] = 50.0;
    assert!((block_ms(&v).unwrap() - 5.0).abs() < 1e-12);
    assert_eq!(block_ms(&[f64::NAN, -1.0, 0.0]), None);
    assert_eq!(block_ms(&[2.0, f64::INFINITY]), Some(2.0));
}

#[test]
fn a_quiet_run_covers_the_true_ratio_tightly() {
    let (st, b, c) = run(1, 12, 2.0, 0.0, |_, _| 1.0);
    let e = estimate(&st, &b, &c).unwrap();
    assert!(e.ci95[0] <= 2.0 && 2.0 <= e.ci95[1], "{}", e.display());
    assert!(e.half_width() < 0.03, "{}", e.display());
    assert_eq!(e.rounds, 12);
}

#[test]
fn stalls_and_a_spiky_round_do_not_move_the_estimate() {
    // One frame in seven stalls at 1.8× (marble's original on lavapipe), and two whole
    // rounds run the baseline under a 1.7× load.
    let (st, b, c) = run(2, 16, 2.5, 1.0 / 7.0, |r, slot| {
        if (r == 3 || r == 9) && slot == 0 {
            1.7
        } else {
            1.0
        }
    });
    let e = estimate(&st, &b, &c).unwrap();
    assert!(e.ci95[0] <= 2.5 && 2.5 <= e.ci95[1], "{}", e.display());
    assert!((e.speedup / 2.5 - 1.0).abs() < 0.03, "{}", e.display());
    assert!(e.outliers >= 1);
}

#[test]
fn a_speedup_that_depends_on_the_window_is_their_mean_with_a_narrow_interval() {
    // The candidate saves more where the object is large: 1.5× to 2.5× across the windows.
    let truth = [1.5f64, 1.8, 2.2, 2.5];
    let mut s = Synth { rng: SplitMix(7) };
    let (mut st, mut b, mut c) = (Vec::new(), Vec::new(), Vec::new());
    for r in 0..16 {
        let w = window_start(r, 150, 16);
        st.push(stratum(r));
        b.push(block_ms(&s.block(w, 16, 5.0, 1.0, 0.0, 1.0)).unwrap());
        let ratio = truth[stratum(r) as usize];
        c.push(block_ms(&s.block(w, 16, 5.0 / ratio, 1.0, 0.0, 1.0)).unwrap());
    }
    let e = estimate(&st, &b, &c).unwrap();
    let geo = truth.iter().map(|t| t.ln()).sum::<f64>() / 4.0;
    assert!((e.speedup.ln() - geo).abs() < 0.02, "{}", e.display());
    assert!(e.half_width() < 0.03, "{}", e.display());
    // Without the windows the same data would spread over ±25 %.
    let pooled = estimate(&[0; 16], &b, &c).unwrap();
    assert!(pooled.half_width() > e.half_width(), "{}", pooled.display());
    let w = condition_warnings(&st, &b, &[], &Conditions::default());
    assert!(w.is_empty(), "{w:?}");
}

#[test]
fn a_linear_drift_cancels_in_the_alternating_order() {
    // Load climbs 1 % per slot over the run: the unpaired ratio of means is biased, the ABBA
    // pairs are not.
    let (st, b, c) = run(3, 20, 1.5, 0.0, |r, slot| {
        1.0 + 0.01 * f64::from(r * 2 + slot as u32)
    });
    let e = estimate(&st, &b, &c).unwrap();
    assert!(e.ci95[0] <= 1.5 && 1.5 <= e.ci95[1], "{}", e.display());
    let warnings = condition_warnings(&st, &b, &[("v".into(), Some(e))], &Conditions::default());
    assert!(
        warnings.iter().any(|w| w.contains("conditions changed")),
        "{warnings:?}"
    );
}

#[test]
fn the_interval_covers_the_truth_in_most_runs() {
    let mut covered = 0;
    for seed in 0..100 {
        let (st, b, c) = run(100 + seed, 8, 1.8, 0.05, |_, _| 1.0);
        let e = estimate(&st, &b, &c).unwrap();
        if e.ci95[0] <= 1.8 && 1.8 <= e.ci95[1] {
            covered += 1;
        }
    }
    // A 95 % interval on 8 rounds (2 per window) with stalls in 5 % of the frames.
    assert!(covered >= 88, "covered {covered} of 100");
}

#[test]
fn a_against_a_holds_one() {
    let (st, b, c) = run(4, 10, 1.0, 0.05, |_, _| 1.0);
    let e = estimate(&st, &b, &c).unwrap();
    assert!(e.ci95[0] <= 1.0 && 1.0 <= e.ci95[1], "{}", e.display());
    assert!(!e.surely_faster() && !e.surely_slower());
}

#[test]
fn decisions_wait_for_separated_intervals() {
    let e = |s: f64, lo: f64, hi: f64| SpeedupEstimate {
        speedup: s,
        ci95: [lo, hi],
        rounds: 6,
        outliers: 0,
        baseline_ms: 1.0,
        candidate_ms: 1.0 / s,
    };
    assert!(e(0.9, 0.85, 0.95).surely_slower());
    assert!(!e(0.97, 0.9, 1.02).surely_slower());
    assert!(separates(&e(2.0, 1.9, 2.1), &e(1.5, 1.4, 1.6)));
    assert!(!separates(&e(2.0, 1.7, 2.3), &e(1.8, 1.6, 2.0)));
    assert!((e(2.0, 1.9, 2.2).half_width() - 0.1).abs() < 1e-12);
}

#[test]
fn stop_rule_needs_rounds_then_a_narrow_interval_or_the_cap() {
    let rule = StopRule::default();
    let narrow = SpeedupEstimate {
        speedup: 2.0,
        ci95: [1.98, 2.03],
        rounds: 6,
        outliers: 0,
        baseline_ms: 2.0,
        candidate_ms: 1.0,
    };
    let wide = SpeedupEstimate {
        ci95: [1.5, 2.5],
        ..narrow
    };
    assert!(!rule.done(3, 1.0, &[Some(narrow)]));
    assert!(rule.done(8, 1.0, &[Some(narrow)]));
    assert!(!rule.done(8, 1.0, &[Some(narrow), Some(wide)]));
    assert!(rule.done(8, 31.0, &[Some(wide)]));
    assert!(rule.done(48, 1.0, &[Some(wide)]));
    assert!(!rule.done(8, 1.0, &[None]));
}

#[test]
fn bad_input_never_yields_nan() {
    assert!(estimate(&[], &[], &[]).is_none());
    assert!(estimate(&[0, 1], &[f64::NAN, 0.0], &[1.0, 1.0]).is_none());
    let e = estimate(&[0], &[2.0], &[1.0]).unwrap();
    assert!((e.speedup - 2.0).abs() < 1e-12 && (e.ci95[0] - 2.0).abs() < 1e-12);
    let w = condition_warnings(
        &[0, 1],
        &[1.0, 1.0],
        &[("x".into(), None)],
        &Conditions {
            others_cpu: Some(0.5),
        },
    );
    assert_eq!(w.len(), 2, "{w:?}");
}

#[test]
fn settling_needs_two_blocks_within_the_tolerance() {
    let s = Settle::default();
    assert!(!s.reached(&[]));
    assert!(!s.reached(&[4.0]));
    // A clock ramping up: each block faster, until two agree within 3 %.
    assert!(!s.reached(&[8.0, 5.0]));
    assert!(s.reached(&[8.0, 5.0, 4.9]));
    assert!(!s.reached(&[4.0, f64::NAN]));
    let settling = Settling {
        blocks_ms: vec![8.0, 5.0, 4.9],
        seconds: 0.2,
        settled: true,
    };
    assert_eq!(settling.warning(), None);
    assert!((settling.drift().unwrap() - 4.9 / 8.0).abs() < 1e-12);
    let cold = Settling {
        settled: false,
        ..settling
    };
    let w = cold.warning().unwrap();
    assert!(w.starts_with("the clock did not settle"), "{w}");
    assert!(w.contains("5.000 and 4.900"), "{w}");
}
