//! `emit --verify` keeps the budget's promise: on a session with faster motion than the profile
//! saw, an error over the budget is a warning naming a tighter budget and exit 4 — never a silent
//! exit 0.

mod common;
use common::run;

#[test]
fn a_verified_error_over_the_budget_warns_and_exits_4() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    common::two_terms(dir, "two_terms.wgsl", "two_terms.json");
    common::two_terms_fast(dir, "fast.json");
    let (code, _, err) = run(
        dir,
        &[
            "analyze",
            "two_terms.wgsl",
            "--session",
            "two_terms.json",
            "--out",
            "t.profile.json",
            "--delta-n",
            "2,8,16,24",
            "--holdout",
            "4",
            "--max-nodes",
            "3",
            "--strategy",
            "3pass",
            "--no-sets",
            "--no-charts",
        ],
    );
    assert_eq!(code, 0, "{err}");
    let emit = |session: &str, out: &str| {
        run(
            dir,
            &[
                "emit",
                "--profile",
                "t.profile.json",
                "--max-error",
                "0.01",
                "--out",
                out,
                "--verify",
                "--session",
                session,
                "--json",
            ],
        )
    };
    let (code, out, err) = emit("fast.json", "fast");
    let report: serde_json::Value = serde_json::from_str(&out).unwrap_or_else(|_| panic!("{err}"));
    let measured = report["measured_error"].as_f64().unwrap();
    assert!(report["node"].is_string(), "{report}");
    assert!(
        measured > 0.01,
        "the fast session breaks the budget: {report}"
    );
    assert_eq!(code, 4, "{err}");
    assert!(err.contains("is over the budget 0.01"), "{err}");
    assert!(err.contains("--max-error"), "the next safe choice: {err}");
    // The output is still written, with the measured speed's interval.
    assert!(dir.join("fast/report.json").exists());
    assert!(report["measured_speedup_ci95"].is_array(), "{report}");
}
