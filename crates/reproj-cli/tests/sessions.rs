//! Several sessions: `analyze --session A --session B` writes a profile per session,
//! and `emit --profile A --profile B`, one profile per session of the same shader, selects so that the budget holds on every session — the worst case — and reports
//! each session's prediction; verified on the faster session, it holds where the single-session
//! choice (`verify.rs`) broke it. Profiles of another shader are refused.

use crate::common;
use crate::common::run;

#[test]
fn the_budget_holds_on_every_profiled_session() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    common::two_terms(dir, "two_terms.wgsl", "slow.json");
    common::two_terms_fast(dir, "fast.json");
    // One analysis over both sessions: a profile each, the second named after its session.
    let (code, out, err) = run(
        dir,
        &[
            "analyze",
            "two_terms.wgsl",
            "--session",
            "slow.json",
            "--session",
            "fast.json",
            "--out",
            "slow.profile.json",
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
    assert!(
        out.contains("--profile slow.profile.json --profile slow.fast.profile.json"),
        "{out}"
    );
    std::fs::rename(
        dir.join("slow.fast.profile.json"),
        dir.join("fast.profile.json"),
    )
    .unwrap();
    let (code, out, err) = run(
        dir,
        &[
            "emit",
            "--profile",
            "slow.profile.json",
            "--profile",
            "fast.profile.json",
            "--max-error",
            "0.01",
            "--out",
            "both",
            "--json",
        ],
    );
    assert_eq!(code, 0, "{err}");
    let report: serde_json::Value = serde_json::from_str(&out).unwrap();
    let sessions = report["sessions"]
        .as_array()
        .expect("per-session predictions");
    assert_eq!(sessions.len(), 2, "{report}");
    let errors: Vec<f64> = sessions
        .iter()
        .map(|s| s["predicted_error"].as_f64().unwrap())
        .collect();
    assert!(errors.iter().all(|&e| e <= 0.01), "{report}");
    if report["node"].is_string() {
        let worst = errors.iter().copied().fold(0.0, f64::max);
        assert_eq!(
            report["predicted_error"].as_f64().unwrap(),
            worst,
            "{report}"
        );
        let slowest = sessions
            .iter()
            .map(|s| s["predicted_speedup"].as_f64().unwrap())
            .fold(f64::INFINITY, f64::min);
        assert_eq!(report["predicted_speedup"].as_f64().unwrap(), slowest);
    }
    // The text names each session.
    let (code, out, err) = run(
        dir,
        &[
            "emit",
            "--profile",
            "slow.profile.json",
            "--profile",
            "fast.profile.json",
            "--max-error",
            "0.01",
            "--out",
            "both",
        ],
    );
    assert_eq!(code, 0, "{err}");
    if report["node"].is_string() {
        assert!(
            out.contains("on slow.json") && out.contains("on fast.json"),
            "{out}"
        );
    }
    // Another shader's profile is refused, naming what differs.
    let mut other: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("fast.profile.json")).unwrap())
            .unwrap();
    other["shader"]["ir_hash"] = serde_json::json!("0000000000000000");
    std::fs::write(dir.join("other.profile.json"), other.to_string()).unwrap();
    let (code, _, err) = run(
        dir,
        &[
            "emit",
            "--profile",
            "slow.profile.json",
            "--profile",
            "other.profile.json",
            "--max-error",
            "0.01",
            "--out",
            "x",
        ],
    );
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("its shader differs"), "{err}");
    assert!(!dir.join("x").exists());

    // A node measured as another variant on one session (another refresh block, as a per-node
    // `--block auto` race may settle it) is another candidate: it is not chosen across both.
    if let Some(chosen) = report["node"].as_str() {
        let mut fast: serde_json::Value =
            serde_json::from_str(&std::fs::read_to_string(dir.join("fast.profile.json")).unwrap())
                .unwrap();
        for n in fast["nodes"].as_array_mut().unwrap() {
            let is_chosen = (chosen == "root" && n["root"] == true)
                || chosen.parse::<u64>().ok() == n["id"].as_u64();
            if is_chosen {
                n["block"] = serde_json::json!(8);
            }
        }
        std::fs::write(dir.join("fast8.profile.json"), fast.to_string()).unwrap();
        let (code, out, err) = run(
            dir,
            &[
                "emit",
                "--profile",
                "slow.profile.json",
                "--profile",
                "fast8.profile.json",
                "--max-error",
                "0.01",
                "--out",
                "k8",
                "--json",
            ],
        );
        assert_eq!(code, 0, "{err}");
        let k8: serde_json::Value = serde_json::from_str(&out).unwrap();
        assert_ne!(k8["node"].as_str(), Some(chosen), "{k8}");
    }
}
