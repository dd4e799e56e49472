//! Selection and Pareto frontier on synthetic fits.

use reproj_models::{
    ErrorFit, ErrorFitFailure, ErrorFitOptions, ErrorFitStatus, FrameTiming, HitRateFit, TimingFit,
    fit_error, fit_timing,
};
use reproj_select::{
    Budget, NodeRecord, OriginalReason, SelectOptions, Selection, SkipReason, candidates,
    check_node, pareto, select,
};

const M: f64 = 500_000.0;
/// Original shader: 10 ms per frame (0.5 ms overhead + M · 1.9e-5 ms).
const ORIGINAL_MS: f64 = 10.0;

fn error_fit(alpha: f64, lambda: f64) -> ErrorFit {
    ErrorFit {
        alpha: Some(alpha),
        lambda: Some(lambda),
        r2: Some(1.0),
        rms_residual: Some(0.0),
        n_samples: 7,
        iterations: 0,
        status: ErrorFitStatus::Ok,
    }
}

fn node(id: u32, alpha: f64, lambda: f64, hit_ms: f64, miss_ms: f64) -> NodeRecord {
    NodeRecord {
        id,
        text: format!("node{id}"),
        strategy: "3pass".into(),
        error: error_fit(alpha, lambda),
        timing: TimingFit::from_costs(hit_ms, miss_ms, 0.5, M),
        mean_pixels: M,
        measured: None,
        measured_errors: Vec::new(),
    }
}

/// A: cheap hits, high error (caches most of the shader); B: moderate; C: low error, small gain.
fn nodes() -> Vec<NodeRecord> {
    vec![
        node(1, 0.08, 0.1, 1e-6, 2.0e-5),
        node(2, 0.02, 0.05, 6e-6, 2.0e-5),
        node(3, 0.002, 0.05, 1.4e-5, 2.0e-5),
    ]
}

fn choice(sel: &Selection) -> &reproj_select::Choice {
    match sel {
        Selection::Node(c) => c,
        Selection::Original { reason } => panic!("expected a node, got original: {reason}"),
    }
}

#[test]
fn tight_budget_keeps_original() {
    let mu = HitRateFit::from_mu(0.9);
    let sel = select(&nodes(), &mu, ORIGINAL_MS, &within(1e-5));
    match sel {
        Selection::Original {
            reason: OriginalReason::OverBudget { lowest_error, .. },
        } => {
            assert!(lowest_error > 1e-5);
        }
        s => panic!("{s:?}"),
    }
}

#[test]
fn moderate_budget_picks_a_node_within_budget() {
    let mu = HitRateFit::from_mu(0.9);
    let opts = within(0.01);
    let sel = select(&nodes(), &mu, ORIGINAL_MS, &opts);
    let c = choice(&sel);
    assert!(c.predicted_error <= 0.01);
    assert!(c.predicted_speedup > 1.0);
    assert!((c.predicted_speedup - ORIGINAL_MS / c.predicted_ms).abs() < 1e-12);
    // It is the fastest under the budget among all candidates.
    let best = candidates(&nodes(), &mu, 2, 50)
        .into_iter()
        .filter(|p| p.predicted_error <= 0.01)
        .map(|p| p.predicted_ms)
        .fold(f64::INFINITY, f64::min);
    assert_eq!(c.predicted_ms, best);
    assert_eq!(c.node_text, format!("node{}", c.node_id));
    // Node 1 fits only at Δn = 2 (6.2 ms); node 2 fits up to Δn = 14 (4.65 ms); node 3 is slower.
    assert_eq!((c.node_id, c.delta_n), (2, 14));
    let json = serde_json::to_string(&sel).unwrap();
    assert!(json.contains("\"kind\":\"node\""));
}

#[test]
fn loose_budget_picks_cheapest() {
    let mu = HitRateFit::from_mu(0.9);
    let sel = select(&nodes(), &mu, ORIGINAL_MS, &within(1.0));
    let c = choice(&sel);
    // Node 1 has the cheapest hits; the highest hit rate is at the largest Δn.
    assert_eq!((c.node_id, c.delta_n), (1, 50));
    assert!(c.predicted_speedup > 2.0);
}

#[test]
fn not_faster_keeps_original() {
    let mu = HitRateFit::from_mu(0.9);
    // Hits cost more than misses: caching only slows down.
    let slow = vec![node(1, 0.001, 0.1, 3e-5, 2e-5)];
    let sel = select(&slow, &mu, ORIGINAL_MS, &within(1.0));
    assert!(matches!(
        sel,
        Selection::Original {
            reason: OriginalReason::NotFaster { .. }
        }
    ));
}

#[test]
fn failed_fits_are_skipped() {
    let mu = HitRateFit::from_mu(0.9);
    let mut ns = nodes();
    // Node 1 (the cheapest) fails its error fit; node 2 its timing fit.
    ns[0].error.status = ErrorFitStatus::Failed {
        reason: ErrorFitFailure::DidNotConverge { iterations: 10 },
    };
    ns[1].timing = fit_timing(&[FrameTiming {
        hits: 10,
        misses: 10,
        time_ms: 1.0,
    }]);
    assert!(matches!(
        check_node(&ns[0]),
        Err(SkipReason::ErrorFitFailed { .. })
    ));
    assert_eq!(check_node(&ns[1]), Err(SkipReason::TimingNotUsable));
    let c = choice(&select(&ns, &mu, ORIGINAL_MS, &within(1.0))).clone();
    assert_eq!(c.node_id, 3);
    // A fit that failed on NaN input has no parameters and is skipped too.
    ns[2].error = fit_error(&[(2.0, f64::NAN)], &ErrorFitOptions::default());
    let sel = select(&ns, &mu, ORIGINAL_MS, &within(1.0));
    assert_eq!(
        sel,
        Selection::Original {
            reason: OriginalReason::NoUsableNodes { skipped: 3 }
        }
    );
    assert!(pareto(&ns, &mu, 2, 50).is_empty());
}

#[test]
fn ties_are_deterministic() {
    let mu = HitRateFit::from_mu(0.9);
    // Identical nodes 7 and 4, and timings independent of Δn (hit = miss cost): all predictions
    // tie in time, so the lowest Δn and then the lowest id win, whatever the input order.
    let a = node(7, 0.01, 0.1, 1e-5, 1e-5);
    let b = node(4, 0.01, 0.1, 1e-5, 1e-5);
    for ns in [vec![a.clone(), b.clone()], vec![b, a]] {
        let sel = select(&ns, &mu, ORIGINAL_MS, &within(1.0));
        let c = choice(&sel);
        assert_eq!((c.node_id, c.delta_n), (4, 2));
    }
}

#[test]
fn zero_error_node_is_lossless() {
    let mu = HitRateFit::from_mu(0.9);
    let ns = vec![node(5, 0.0, 0.0, 1e-6, 2e-5)];
    let sel = select(&ns, &mu, ORIGINAL_MS, &within(0.0));
    let c = choice(&sel);
    assert_eq!(c.delta_n, 50);
    assert_eq!(c.predicted_error, 0.0);
}

#[test]
fn invalid_inputs_keep_original() {
    let mu = HitRateFit::from_mu(0.9);
    let ns = nodes();
    let reason = |s: Selection| match s {
        Selection::Original { reason } => reason,
        s => panic!("{s:?}"),
    };
    // An invalid budget is no budget: the type refuses it before any selection.
    assert!(Budget::new(f64::NAN).is_err());
    let opts = SelectOptions {
        min_delta_n: 10,
        max_delta_n: 5,
        ..within(0.1)
    };
    assert!(matches!(
        reason(select(&ns, &mu, ORIGINAL_MS, &opts)),
        OriginalReason::InvalidDeltaNRange { .. }
    ));
    assert_eq!(
        reason(select(&ns, &mu, f64::NAN, &within(0.1))),
        OriginalReason::InvalidOriginalTime
    );
    let failed_mu = reproj_models::fit_hit_rate(&[]);
    assert_eq!(
        reason(select(&ns, &failed_mu, ORIGINAL_MS, &within(0.1))),
        OriginalReason::HitRateUnavailable
    );
    assert_eq!(
        reason(select(&[], &mu, ORIGINAL_MS, &within(0.1))),
        OriginalReason::NoUsableNodes { skipped: 0 }
    );
    // Every reason serializes (no NaN in JSON); an infinite budget is refused by its type.
    assert!(Budget::new(f64::INFINITY).is_err());
    for s in [
        select(&ns, &mu, ORIGINAL_MS, &within(0.0)),
        select(&ns, &failed_mu, ORIGINAL_MS, &within(0.1)),
        select(&[], &mu, ORIGINAL_MS, &within(0.1)),
    ] {
        assert!(matches!(s, Selection::Original { .. }), "{s:?}");
        let json = serde_json::to_string(&s).unwrap();
        assert_eq!(serde_json::from_str::<Selection>(&json).unwrap(), s);
    }
}

#[test]
fn pareto_frontier_is_monotone_and_undominated() {
    let mu = HitRateFit::from_mu(0.9);
    let ns = nodes();
    let front = pareto(&ns, &mu, 2, 50);
    assert!(!front.is_empty());
    for w in front.windows(2) {
        assert!(w[0].predicted_ms < w[1].predicted_ms);
        assert!(w[0].predicted_error > w[1].predicted_error);
    }
    let all = candidates(&ns, &mu, 2, 50);
    assert_eq!(all.len(), 3 * 49);
    for p in &front {
        assert!(!all.iter().any(|q| q.predicted_ms <= p.predicted_ms
            && q.predicted_error <= p.predicted_error
            && (q.predicted_ms < p.predicted_ms || q.predicted_error < p.predicted_error)));
    }
    // Selection under any budget lands on the frontier.
    for budget in [0.001, 0.005, 0.01, 0.03, 0.1] {
        if let Selection::Node(c) = select(&ns, &mu, ORIGINAL_MS, &within(budget)) {
            assert!(
                front
                    .iter()
                    .any(|p| p.node_id == c.node_id && p.delta_n == c.delta_n)
            );
        }
    }
}

/// Two nodes cached together: the hit rate is shared, the errors add, the hit savings add.
#[test]
fn a_set_combines_the_single_node_models() {
    use reproj_select::{best_set, combined_timing, predict, predict_set};
    let hr = HitRateFit::from_mu(0.9);
    // A hit of A costs 1.6e-5 less than its miss, of C 0.5e-5 less: a hit of the pair 2.1e-5
    // less than the pair's miss (the dearer one, 2.2e-5).
    let a = node(1, 0.02, 0.1, 0.6e-5, 2.2e-5);
    let c = node(3, 0.005, 0.1, 1.6e-5, 2.1e-5);
    let timing = combined_timing(&[&a, &c], ORIGINAL_MS).unwrap();
    assert!((timing.hit_ms.unwrap() - 0.1e-5).abs() < 1e-12);
    assert_eq!(timing.miss_ms, Some(2.2e-5));
    assert!((timing.overhead_ms.unwrap() - 0.5).abs() < 1e-12);
    // Fits that put the time in the overhead (hits clamped to 0, as lavapipe's do) combine to the
    // same frame times as fits that split it: only A + γ·B is determined.
    let pa = |n: &NodeRecord| {
        let (h, m, o) = (
            n.timing.hit_ms.unwrap(),
            n.timing.miss_ms.unwrap(),
            n.timing.overhead_ms.unwrap(),
        );
        NodeRecord {
            timing: TimingFit::from_costs(0.0, m - h, o + M * h, M),
            ..n.clone()
        }
    };
    let shifted = combined_timing(&[&pa(&a), &pa(&c)], ORIGINAL_MS).unwrap();
    for gamma in [0.0, 0.5, 0.9, 1.0] {
        let (x, y) = (
            timing.frame_ms(gamma, M).unwrap(),
            shifted.frame_ms(gamma, M).unwrap(),
        );
        assert!((x - y).abs() < 1e-9, "γ = {gamma}: {x} vs {y}");
    }
    let pair = predict_set(&[&a, &c], &hr, ORIGINAL_MS, 10).unwrap();
    let (pa, pc) = (predict(&a, &hr, 10).unwrap(), predict(&c, &hr, 10).unwrap());
    assert_eq!(pair.node_ids, vec![1, 3]);
    assert_eq!(pair.hit_rate, pa.hit_rate);
    assert!((pair.predicted_error - (pa.predicted_error + pc.predicted_error)).abs() < 1e-12);
    assert!(pair.predicted_ms < pa.predicted_ms.min(pc.predicted_ms));
    // Under a budget only the pair's summed error must fit.
    let best = best_set(&[&a, &c], &hr, ORIGINAL_MS, pa.predicted_error, (2, 50)).unwrap();
    assert!(best.predicted_error <= pa.predicted_error);
    assert!(best.delta_n < 10);
    assert!(best_set(&[&a, &c], &hr, ORIGINAL_MS, 0.0, (2, 50)).is_none());
}

/// A measured set with its own fits (error α, hit cost `hit_ms`).
fn set(members: &[u32], alpha: f64, hit_ms: f64) -> reproj_select::SetRecord {
    reproj_select::SetRecord {
        members: members.to_vec(),
        texts: members.iter().map(|id| format!("node{id}")).collect(),
        strategy: "3pass".into(),
        error: error_fit(alpha, 0.1),
        timing: TimingFit::from_costs(hit_ms, 2.0e-5, 0.5, M),
        mean_pixels: M,
        measured_errors: Vec::new(),
    }
}

#[test]
fn a_set_wins_only_when_predicted_faster_under_the_budget() {
    use reproj_select::select_with_sets;
    let mu = HitRateFit::from_mu(0.9);
    let ns = nodes();
    let opts = within(0.01);
    let single = choice(&select(&ns, &mu, ORIGINAL_MS, &opts)).clone();
    assert!(single.members.is_empty());
    // No set: what `select` picks.
    assert_eq!(
        select_with_sets(&ns, &[], &mu, ORIGINAL_MS, &opts),
        select(&ns, &mu, ORIGINAL_MS, &opts)
    );
    // A set faster than every node, with a low error: it wins.
    let fast = set(&[2, 3], 0.004, 3e-6);
    let c = choice(&select_with_sets(
        &ns,
        std::slice::from_ref(&fast),
        &mu,
        ORIGINAL_MS,
        &opts,
    ))
    .clone();
    assert_eq!(c.members, vec![2, 3]);
    assert_eq!((c.node_id, c.node_text.as_str()), (2, "node2 + node3"));
    assert!(c.predicted_ms < single.predicted_ms && c.predicted_error <= 0.01);
    assert!((c.predicted_speedup - ORIGINAL_MS / c.predicted_ms).abs() < 1e-12);
    // The same set over the budget at every Δn: the single node stays.
    let tight = within(0.002);
    let over = set(&[2, 3], 0.5, 3e-6);
    assert_eq!(
        select_with_sets(&ns, &[over], &mu, ORIGINAL_MS, &tight),
        select(&ns, &mu, ORIGINAL_MS, &tight)
    );
    // Slower than the chosen node: the node stays.
    let slow = set(&[2, 3], 0.001, 1.5e-5);
    assert_eq!(
        select_with_sets(&ns, &[slow], &mu, ORIGINAL_MS, &opts),
        Selection::Node(single.clone())
    );
    // Nothing under the budget but the set: the set, not the original.
    let c = choice(&select_with_sets(
        &ns,
        &[set(&[2, 3], 0.0, 1e-5)],
        &mu,
        ORIGINAL_MS,
        &within(0.0),
    ))
    .clone();
    assert_eq!(c.members, vec![2, 3]);
    // An invalid budget is refused by its type, whatever the sets.
    assert!(Budget::new(-1.0).is_err());
}

/// emit respects the profile's measurements: never below a measured error (the model anchored at
/// 0 at Δn = 1 underestimates a single resampling at Δn = 2), never below the line between two
/// measured periods, and never past the longest measured period.
#[test]
fn measured_errors_bound_the_prediction_and_the_range() {
    use reproj_select::{MeasuredBound, predict, predicted_error, respect_measurements};
    let hr = HitRateFit::from_mu(0.9);
    // α 0.02, λ 0.1: the model predicts ≈ 0.0019 at Δn = 2.
    let mut n = node(1, 0.02, 0.1, 1.0e-6, 2.0e-5);
    let model_at_2 = predict(&n, &hr, 2).unwrap().predicted_error;
    assert!(model_at_2 < 0.002, "{model_at_2}");
    n.measured_errors = vec![(2, 0.00356), (10, 0.009), (14, 0.011)];
    assert_eq!(
        respect_measurements(&n.measured_errors, 2),
        MeasuredBound::Exact(0.00356)
    );
    assert!(predict(&n, &hr, 2).unwrap().predicted_error >= 0.00356);
    // Between 2 and 10: at least the line through them, and at least the model scaled by how
    // much it fell short of its neighbours (here ×1.87 at Δn = 2).
    let MeasuredBound::Between { chord, .. } = respect_measurements(&n.measured_errors, 6) else {
        panic!()
    };
    assert!((chord - (0.00356 + 0.5 * (0.009 - 0.00356))).abs() < 1e-12);
    let at_6 = predicted_error(&n, 6).unwrap();
    let model_6 = n.error.predict(6.0).unwrap();
    assert!(
        at_6 >= chord && at_6 >= model_6 * 0.00356 / model_at_2 - 1e-12,
        "{at_6}"
    );
    // Past Δn = 14: refused, not extrapolated.
    assert_eq!(
        respect_measurements(&n.measured_errors, 50),
        MeasuredBound::Beyond { longest: 14 }
    );
    assert!(predict(&n, &hr, 50).is_none());
    // Under budget 0.002 the node is not chosen at Δn = 2 (the model alone would choose it).
    let opts = SelectOptions {
        max_error: Budget::new(0.002).unwrap(),
        min_delta_n: 2,
        max_delta_n: 50,
    };
    assert!(matches!(
        select(std::slice::from_ref(&n), &hr, ORIGINAL_MS, &opts),
        Selection::Original { .. }
    ));
    n.measured_errors.clear();
    assert!(matches!(
        select(&[n], &hr, ORIGINAL_MS, &opts),
        Selection::Node(c) if c.delta_n == 2
    ));
}

#[test]
fn several_sessions_hold_the_budget_on_every_one() {
    use reproj_select::{Scene, select_worst_case};
    let mu = HitRateFit::from_mu(0.9);
    // The same nodes under faster motion: every error three times as large, the hits a little
    // rarer.
    let fast: Vec<NodeRecord> = nodes()
        .into_iter()
        .map(|mut n| {
            n.error = error_fit(n.error.alpha.unwrap() * 3.0, n.error.lambda.unwrap());
            n
        })
        .collect();
    let mu_fast = HitRateFit::from_mu(0.85);
    let slow_nodes = nodes();
    let scenes = [
        Scene {
            name: "slow.json",
            nodes: &slow_nodes,
            sets: &[],
            hit_rate: &mu,
            original_ms: ORIGINAL_MS,
        },
        Scene {
            name: "fast.json",
            nodes: &fast,
            sets: &[],
            hit_rate: &mu_fast,
            original_ms: ORIGINAL_MS,
        },
    ];
    let opts = within(0.01);
    let (sel, per) = select_worst_case(&scenes, &opts);
    let c = choice(&sel);
    assert_eq!(per.len(), 2);
    // The budget holds on both; the choice's error is the worst of the two.
    assert!(per.iter().all(|p| p.predicted_error <= 0.01), "{per:?}");
    let worst = per.iter().map(|p| p.predicted_error).fold(0.0, f64::max);
    assert_eq!(c.predicted_error, worst);
    let slowest = per
        .iter()
        .map(|p| p.predicted_speedup)
        .fold(f64::INFINITY, f64::min);
    assert_eq!(c.predicted_speedup, slowest);
    // The slow session alone would choose something that breaks the budget on the fast one.
    let alone = select(&slow_nodes, &mu, ORIGINAL_MS, &opts);
    let a = choice(&alone);
    let fast_node = fast.iter().find(|n| n.id == a.node_id).unwrap();
    let on_fast = reproj_select::predict(fast_node, &mu_fast, a.delta_n).unwrap();
    assert!(on_fast.predicted_error > 0.01, "{on_fast:?}");
    assert!(c.predicted_speedup <= a.predicted_speedup);
    // One session: the single-session selection.
    let (one, per) = select_worst_case(&scenes[..1], &opts);
    assert_eq!(one, alone);
    assert_eq!(per.len(), 1);
    // A budget no session meets: the original, with the lowest worst-case error.
    let (tight, per) = select_worst_case(&scenes, &within(1e-6));
    assert!(matches!(
        tight,
        Selection::Original {
            reason: OriginalReason::OverBudget { .. }
        }
    ));
    assert!(per.is_empty());
}

/// Selection options with the default Δn range under the budget `max_error`.
fn within(max_error: f64) -> SelectOptions {
    SelectOptions::new(Budget::new(max_error).unwrap())
}

/// With a second race, the frame time follows the two races (linear in the hit rate between
/// them), not the timing model; the interval is interpolated between theirs.
#[test]
fn two_races_set_the_frame_time_and_its_interval() {
    use reproj_select::{Calibration, RaceLine, RacePoint, predict};
    let hr = HitRateFit::from_mu(0.9);
    let gamma = |dn: f64| hr.gamma(dn).unwrap();
    // Raced at Δn 2 (6 ms: 1.67×) and Δn 50 (4 ms: 2.5×); the replays' model says otherwise.
    let at = |delta_n: u32, ms: f64, rel: [f64; 2]| RacePoint {
        delta_n,
        gamma: gamma(f64::from(delta_n)),
        ms,
        rel_ci95: rel,
    };
    let line = RaceLine::new(at(50, 4.0, [0.98, 1.02]), at(2, 6.0, [0.9, 1.1])).unwrap();
    // The two races' order does not matter; equal hit rates give no line.
    assert_eq!(
        Some(line),
        RaceLine::new(at(2, 6.0, [0.9, 1.1]), at(50, 4.0, [0.98, 1.02]))
    );
    assert_eq!(
        RaceLine::new(at(2, 6.0, [0.9, 1.1]), at(2, 5.0, [0.9, 1.1])),
        None
    );
    let mut n = node(1, 0.02, 0.05, 1e-6, 2.0e-5);
    n.measured = Some(Calibration {
        delta_n: 50,
        ms_scale: 1.0,
        rel_ci95: [0.98, 1.02],
        line: Some(line),
    });
    for (dn, ms) in [(2, 6.0), (50, 4.0)] {
        let p = predict(&n, &hr, dn).unwrap();
        assert!((p.predicted_ms - ms).abs() < 1e-9, "Δn {dn}: {p:?}");
    }
    // Halfway in the hit rate: halfway in time, and in the interval.
    let g_mid = 0.5 * (gamma(2.0) + gamma(50.0));
    let dn_mid = (1.0 / (1.0 - g_mid / 0.9)).round() as u32;
    let p = predict(&n, &hr, dn_mid).unwrap();
    let t = (p.hit_rate - gamma(2.0)) / (gamma(50.0) - gamma(2.0));
    assert!((p.predicted_ms - (6.0 - 2.0 * t)).abs() < 1e-9, "{p:?}");
    let rel = p.rel_ci95.unwrap();
    assert!((rel[0] - (0.9 + 0.08 * t)).abs() < 1e-9, "{rel:?}");
    // Without the line: the model at the race's level, as before.
    n.measured = Some(Calibration {
        line: None,
        ..n.measured.unwrap()
    });
    let model = predict(&n, &hr, 50).unwrap();
    assert!((model.predicted_ms - 4.0).abs() > 0.1, "{model:?}");
}
