//! A NaN is never scored as "no error" (issue: NaN became error 0 and was selected).
//!
//! - The original's own NaN pixels are counted, said and recorded in the profile, and left out
//!   of every error (nothing can be measured against them); the errors stay numbers.
//! - A variant that renders NaN or ∞ where the original is finite is set aside with that reason.
//! - `emit --verify` fails on such a variant (exit 4): tested on the gate in `cmd/emit.rs`.

use crate::common::{root, run};

fn setup(files: &[(&str, &str)]) -> tempfile::TempDir {
    let tmp = tempfile::tempdir().unwrap();
    for (from, to) in files {
        std::fs::copy(root().join(from), tmp.path().join(to)).unwrap();
    }
    tmp
}

#[test]
fn the_original_s_nan_is_counted_said_recorded_and_left_out_of_the_error() {
    let tmp = setup(&[
        ("crates/reproj-cli/tests/data/nan_half.wgsl", "nan.wgsl"),
        (
            "crates/reproj-replay/tests/data/tiny_moving.json",
            "tiny.json",
        ),
    ]);
    let dir = tmp.path();
    let (code, out, err) = run(dir, &["render", "nan.wgsl", "--session", "tiny.json"]);
    assert_eq!(code, 0, "{err}");
    assert!(
        err.contains("the shader renders") && err.contains("NaN or infinite"),
        "{out}\n{err}"
    );
    let (code, _, err) = run(
        dir,
        &[
            "analyze",
            "nan.wgsl",
            "--session",
            "tiny.json",
            "--out",
            "p.json",
            "--delta-n",
            "2,4,8",
            "--holdout",
            "6",
            "--max-nodes",
            "1",
            "--strategy",
            "3pass",
            "--no-sets",
            "--no-charts",
        ],
    );
    assert_eq!(code, 0, "{err}");
    assert!(
        err.contains("the original shader renders") && err.contains("left out"),
        "{err}"
    );
    let p: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("p.json")).unwrap()).unwrap();
    let bad = p["original"]["nonfinite_pixels"].as_u64().unwrap();
    assert!(bad > 100, "{bad}");
    let root_node = &p["nodes"][0];
    let errors: Vec<f64> = root_node["measurements"]
        .as_array()
        .unwrap()
        .iter()
        .map(|m| m["error"].as_f64().unwrap())
        .collect();
    // The camera moves: the cached color has an error, measured on the finite half.
    assert!(
        errors.len() == 4 && errors.iter().all(|e| e.is_finite() && *e > 0.0),
        "{errors:?}"
    );
}

#[test]
fn a_variant_that_renders_nan_where_the_original_is_finite_is_set_aside() {
    let tmp = setup(&[
        ("crates/reproj-cli/tests/data/cliff.wgsl", "cliff.wgsl"),
        ("crates/reproj-cli/tests/data/two_terms.json", "s.json"),
    ]);
    let dir = tmp.path();
    let (code, out, err) = run(dir, &["nodes", "cliff.wgsl", "--json"]);
    assert_eq!(code, 0, "{err}");
    let nodes: serde_json::Value = serde_json::from_str(&out).unwrap();
    let a_id = nodes["nodes"]
        .as_array()
        .unwrap()
        .iter()
        .find(|n| n["text"] == "a")
        .expect("node `a`")["id"]
        .clone();
    let a = a_id.to_string();
    let (code, _, err) = run(
        dir,
        &[
            "analyze",
            "cliff.wgsl",
            "--session",
            "s.json",
            "--out",
            "p.json",
            "--nodes",
            &a,
            "--delta-n",
            "2,8,16,24",
            "--holdout",
            "4",
            "--strategy",
            "3pass",
            "--no-sets",
            "--no-charts",
        ],
    );
    assert_eq!(code, 0, "{err}");
    let p: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("p.json")).unwrap()).unwrap();
    let node = p["nodes"]
        .as_array()
        .unwrap()
        .iter()
        .find(|n| n["id"] == a_id)
        .unwrap();
    assert_eq!(node["status"], "set-aside", "{node}");
    let reason = node["reason"].as_str().unwrap();
    assert!(
        reason.contains("NaN or infinite where the original is finite"),
        "{reason}"
    );
    assert!(
        p["original"].get("nonfinite_pixels").is_none(),
        "the original is finite"
    );
}
