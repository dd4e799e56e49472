use super::*;

#[test]
fn cpu_share_of_others() {
    assert_eq!(others_share((0, 0, 0), (0, 0, 0)), None);
    // 400 ticks over the machine, 300 busy, 200 of them ours.
    let s = others_share((100, 1000, 50), (400, 1400, 250)).unwrap();
    assert!((s - 0.25).abs() < 1e-12);
    if cfg!(target_os = "linux") {
        assert!(cpu_ticks().is_some());
    }
}

/// A run of `rounds` rounds over the four windows: the baseline at 10 ms a frame, the
/// candidate at `10 / speedup` with a spread of ±`spread` alternating between rounds.
fn run(rounds: u32, speedup: f64, spread: f64) -> BenchReport {
    let windows: Vec<u32> = (0..rounds).map(speedup::stratum).collect();
    let sign = |r: u32| if r.is_multiple_of(2) { 1.0 } else { -1.0 };
    let cand: Vec<f64> = (0..rounds)
        .map(|r| 10.0 / speedup * (1.0 + sign(r / 4) * spread))
        .collect();
    serde_json::from_value(serde_json::json!({
        "schema": "reproj.bench", "version": 1,
        "machine": {"adapter": "test", "device_type": "Cpu", "cpu_rasterizer": true,
                    "lp_num_threads": null, "cpus": 2},
        "block_frames": 8, "session_frames": 150, "rounds": rounds, "seconds": 1.0,
        "others_cpu": null,
        "baseline": {"median_ms": 10.0, "blocks_ms": vec![10.0; rounds as usize],
                     "windows": windows},
        "candidates": [{"name": "c", "median_ms": 10.0 / speedup, "speedup": speedup,
                        "speedup_ci95": [speedup, speedup], "rounds": rounds,
                        "outliers": 0, "blocks_ms": cand}],
        "warnings": []
    }))
    .unwrap()
}

#[test]
fn two_runs_pooled_narrow_the_interval_around_the_same_speedup() {
    let (a, b) = (run(8, 0.9, 0.08), run(8, 0.9, 0.08));
    let one = speedup::estimate(
        &a.baseline.windows,
        &a.baseline.blocks_ms,
        &a.candidates[0].blocks_ms,
    )
    .unwrap();
    let both = a.pooled_estimate(0, &b, 0).unwrap();
    assert_eq!(both.rounds, 16);
    assert!((both.speedup - one.speedup).abs() < 1e-9);
    assert!(both.half_width() < one.half_width());
    assert!(a.pooled_estimate(1, &b, 0).is_none());
}
