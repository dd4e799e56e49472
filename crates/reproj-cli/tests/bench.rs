//! `reproj bench` through the real binary: the A/A check (the original against itself measures
//! ≈ 1.00× with an interval that holds 1, or says the machine was disturbed), a variant directory
//! beside it, the `reproj.bench` v1 JSON, and bad input (exit 2).

use std::path::Path;

use crate::common::{root, run as reproj};

/// marble over a smaller, shorter copy of its session (the timing needs work to measure, not
/// pixels to look at).
fn setup(dir: &Path) {
    let text = std::fs::read_to_string(root().join("sessions/marble.json")).unwrap();
    let mut session: serde_json::Value = serde_json::from_str(&text).unwrap();
    session["resolution"] = serde_json::json!([128, 128]);
    session["frames"] = serde_json::json!(48);
    std::fs::write(
        dir.join("s.json"),
        serde_json::to_string_pretty(&session).unwrap(),
    )
    .unwrap();
    std::fs::copy(root().join("shaders/marble.wgsl"), dir.join("marble.wgsl")).unwrap();
}

#[test]
fn the_original_against_itself_holds_one_and_a_variant_is_timed_beside_it() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    setup(dir);
    let (code, _, err) = reproj(
        dir,
        &[
            "instance",
            "marble.wgsl",
            "--node",
            "root",
            "--strategy",
            "2pass",
            "--out",
            "v",
        ],
    );
    assert_eq!(code, 0, "{err}");
    let args = [
        "bench",
        "marble.wgsl",
        "--session",
        "s.json",
        "marble.wgsl",
        "v",
        "--delta-n",
        "16",
        "--rounds",
        "12",
        "--min-rounds",
        "12",
        "--block-frames",
        "6",
        "--json",
    ];
    let (code, out, err) = reproj(dir, &args);
    assert_eq!(code, 0, "{err}");
    let r: serde_json::Value = serde_json::from_str(&out).unwrap();
    assert_eq!(r["schema"], "reproj.bench");
    assert_eq!(r["version"], 2);
    // The clock settled (or a warning says it did not) before the first round: at least two
    // blocks of the original, each a figure.
    let settling = &r["settling"];
    let blocks = settling["blocks_ms"].as_array().unwrap();
    assert!(blocks.len() >= 2, "{settling}");
    assert!(
        blocks.iter().all(|b| b.as_f64().unwrap() > 0.0),
        "{settling}"
    );
    if settling["settled"] == false {
        assert!(
            r["warnings"]
                .to_string()
                .contains("the clock did not settle"),
            "{out}"
        );
    }
    assert_eq!(r["rounds"], 12);
    assert_eq!(r["block_frames"], 6);
    assert!(r["baseline"]["median_ms"].as_f64().unwrap() > 0.0);
    assert_eq!(r["baseline"]["blocks_ms"].as_array().unwrap().len(), 12);
    assert!(r["machine"]["adapter"].as_str().is_some());
    let warnings = r["warnings"].as_array().unwrap();
    let cands = r["candidates"].as_array().unwrap();
    assert_eq!(cands.len(), 2);
    assert_eq!(cands[0]["name"], "marble.wgsl");
    assert_eq!(cands[1]["name"], "v (Δn 16)");

    // A/A: the same shader measures ≈ 1; its interval holds 1 unless the run says it was
    // disturbed (a busy CI machine may).
    let s = cands[0]["speedup"].as_f64().unwrap();
    let [lo, hi] = [
        cands[0]["speedup_ci95"][0].as_f64().unwrap(),
        cands[0]["speedup_ci95"][1].as_f64().unwrap(),
    ];
    assert!(lo <= s && s <= hi, "{s} [{lo}, {hi}]");
    assert!((0.8..=1.25).contains(&s), "A/A measured {s}: {out}");
    assert!(
        (lo <= 1.0 && 1.0 <= hi) || !warnings.is_empty(),
        "A/A interval [{lo}, {hi}] excludes 1 without a warning: {out}"
    );

    // The variant: a finite speedup with its interval and every block recorded.
    let v = &cands[1];
    assert!(v["speedup"].as_f64().unwrap().is_finite());
    assert_eq!(v["rounds"], 12);
    assert_eq!(v["blocks_ms"].as_array().unwrap().len(), 12);

    // The table names the machine and the interval.
    let text_args: Vec<&str> = args.iter().copied().filter(|a| *a != "--json").collect();
    let (code, out, err) = reproj(dir, &text_args);
    assert_eq!(code, 0, "{err}");
    assert!(out.contains("original (baseline)"), "{out}");
    assert!(out.contains("speedup [95 % CI]"), "{out}");
    assert!(out.contains("LP_NUM_THREADS="), "{out}");
}

#[test]
fn bad_bench_input_exits_2_with_one_clear_line() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    setup(dir);
    std::fs::create_dir(dir.join("empty")).unwrap();
    let cases: [(&[&str], &str); 5] = [
        (&["missing.wgsl"], "missing.wgsl"),
        (&["empty"], "not a variant directory"),
        (
            &["marble.wgsl", "--min-rounds", "9", "--rounds", "8"],
            "--min-rounds",
        ),
        (&["marble.wgsl", "--max-time", "0"], "--max-time"),
        (&["marble.wgsl", "--target", "NaN"], "--target"),
    ];
    for (extra, says) in cases {
        let mut args = vec!["bench", "marble.wgsl", "--session", "s.json"];
        args.extend_from_slice(extra);
        let (code, _, err) = reproj(dir, &args);
        assert_eq!(code, 2, "{args:?}: {err}");
        assert!(err.contains(says), "{args:?}: {err}");
        assert!(!err.contains("panicked"), "{err}");
    }
}
