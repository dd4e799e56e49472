use super::*;
use clap::Parser;

fn args(extra: &[&str]) -> EmitArgs {
    let mut a = vec!["reproj", "emit", "--max-error", "0.01"];
    a.extend_from_slice(extra);
    match crate::Cli::parse_from(a).command {
        crate::Command::Emit(args) => args,
        _ => unreachable!(),
    }
}

fn report(measured: serde_json::Value) -> reproj_emit::EmitReport {
    let mut v = serde_json::json!({
        "profile": "p.json", "shader": "s.wgsl", "max_error": 0.01, "original_ms": 2.0,
        "files": [], "adapter": "test",
        "measured_speedup": 2.0, "measured_speedup_ci95": [1.9, 2.1],
    });
    for (k, x) in measured.as_object().unwrap() {
        v[k] = x.clone();
    }
    serde_json::from_value(v).unwrap()
}

fn code(e: Option<anyhow::Error>) -> Option<u8> {
    e.map(|e| classify(&e).0)
}

use super::super::classify;

#[test]
fn a_choice_is_rejected_only_when_slower_beyond_doubt() {
    let r = |s: f64, ci: [f64; 2]| {
        report(serde_json::json!({
            "node": "680", "strategy": "2pass", "delta_n": 3, "measured_rounds": 48,
            "measured_speedup": s, "measured_speedup_ci95": ci,
        }))
    };
    assert_eq!(slower_beyond_doubt(&r(1.5, [1.4, 1.6])), None);
    // Slower by its estimate, but the interval reaches 1×: noise could say either.
    assert_eq!(slower_beyond_doubt(&r(0.97, [0.92, 1.02])), None);
    let why = slower_beyond_doubt(&r(0.83, [0.80, 0.86])).unwrap();
    assert!(
        why.contains("node 680 2pass at Δn 3") && why.contains("0.83x [0.80, 0.86]"),
        "{why}"
    );
    // Nothing measured (the original kept, or no --verify): nothing to reject.
    assert_eq!(
        slower_beyond_doubt(&report(serde_json::json!({
            "measured_speedup": null, "measured_speedup_ci95": null
        }))),
        None
    );
}

#[test]
fn a_verified_nan_or_infinity_never_passes() {
    let a = args(&["--min-speedup", "1.5"]);
    // Within budget, fast enough: passes.
    assert_eq!(
        code(gate(
            &report(serde_json::json!({"measured_error": 0.005})),
            &a
        )),
        None
    );
    // Non-finite pixels where the original is finite: exit 4, whatever the error reads.
    let r = report(serde_json::json!({"measured_error": 0.001, "measured_nonfinite_pixels": 12}));
    assert_eq!(code(gate(&r, &a)), Some(4));
    // A NaN error: exit 4.
    let r = report(serde_json::json!({"measured_error": null}));
    assert_eq!(
        code(gate(&r, &a)),
        None,
        "no measurement: nothing to gate on the error"
    );
    let mut r = report(serde_json::json!({}));
    r.measured_error = Some(f64::NAN);
    assert_eq!(code(gate(&r, &a)), Some(4));
    // The original's own NaN (left out of the error) does not fail a variant.
    let r = report(
        serde_json::json!({"measured_error": 0.005, "measured_nonfinite_reference_pixels": 40}),
    );
    assert_eq!(code(gate(&r, &a)), None);
    // Over budget: 4; slow: 3.
    assert_eq!(
        code(gate(
            &report(serde_json::json!({"measured_error": 0.02})),
            &a
        )),
        Some(4)
    );
    let r =
        report(serde_json::json!({"measured_error": 0.005, "measured_speedup_ci95": [1.2, 2.1]}));
    assert_eq!(code(gate(&r, &a)), Some(3));
}
