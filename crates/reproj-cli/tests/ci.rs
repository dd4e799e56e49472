//! CI mode through the real binary: a committed profile used from another directory, comment
//! edits that keep it valid, code edits that make it stale, `--shader`, `--min-speedup` (exit 3),
//! a clean output directory, and progress lines without a terminal.

use std::path::Path;

use crate::common::{root, run as reproj};
use std::process::Command;

fn names(dir: &Path) -> Vec<String> {
    let mut v: Vec<String> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    v.sort();
    v
}

#[test]
fn a_committed_profile_drives_emit_from_anywhere() {
    let tmp = tempfile::tempdir().unwrap();
    let repo = tmp.path().join("repo");
    std::fs::create_dir_all(repo.join("profiles")).unwrap();
    let data = root().join("crates/reproj-replay/tests/data");
    std::fs::copy(data.join("tiny.wgsl"), repo.join("tiny.wgsl")).unwrap();
    std::fs::copy(data.join("tiny_moving.json"), repo.join("tiny.json")).unwrap();

    // Analyze, stderr not a terminal: one progress line per replay, with an ETA.
    let (code, _, err) = reproj(
        &repo,
        &[
            "analyze",
            "tiny.wgsl",
            "--session",
            "tiny.json",
            "--out",
            "profiles/tiny.profile.json",
            "--delta-n",
            "2,4,8",
            "--holdout",
            "6",
            "--max-nodes",
            "3",
            "--no-charts",
        ],
    );
    assert_eq!(code, 0, "{err}");
    let progress: Vec<&str> = err.lines().filter(|l| l.starts_with('[')).collect();
    assert!(progress.len() >= 4, "{err}");
    assert!(progress.iter().all(|l| l.contains("ETA")), "{err}");
    let profile: serde_json::Value = serde_json::from_str(
        &std::fs::read_to_string(repo.join("profiles/tiny.profile.json")).unwrap(),
    )
    .unwrap();
    assert_eq!(profile["shader"]["path"], "../tiny.wgsl");
    assert_eq!(profile["session"]["path"], "../tiny.json");

    // From another working directory; stale files of an earlier run are gone afterwards.
    let out = tmp.path().join("out");
    std::fs::create_dir_all(&out).unwrap();
    std::fs::write(out.join("pass3_shade.wgsl"), "// stale").unwrap();
    let emit = |extra: &[&str]| {
        let mut a = vec![
            "emit",
            "--max-error",
            "1",
            "--profile",
            "repo/profiles/tiny.profile.json",
            "--out",
            "out",
        ];
        a.extend(extra);
        reproj(tmp.path(), &a)
    };
    let (code, _, err) = emit(&[]);
    assert_eq!(code, 0, "{err}");
    let written = names(&out);
    assert!(written.contains(&"report.json".to_string()), "{written:?}");
    if !written.contains(&"manifest.json".to_string()) {
        // The original was kept: the stale pass must not survive beside it.
        assert!(
            !written.contains(&"pass3_shade.wgsl".to_string()),
            "{written:?}"
        );
    }
    assert!(
        names(tmp.path()).iter().all(|n| !n.starts_with(".out")),
        "no staging directory left: {:?}",
        names(tmp.path())
    );

    // A comment edit keeps the profile valid; a code edit makes it stale (exit 2).
    let shader = repo.join("tiny.wgsl");
    let text = std::fs::read_to_string(&shader).unwrap();
    std::fs::write(&shader, format!("// reviewed\n{text}\n// end\n")).unwrap();
    let (code, _, err) = emit(&[]);
    assert_eq!(code, 0, "{err}");
    let edited = text.replacen("0.5", "0.25", 1);
    assert_ne!(edited, text, "tiny.wgsl has a 0.5 to edit");
    std::fs::write(&shader, &edited).unwrap();
    let (code, _, err) = emit(&[]);
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("changed since the profile was made"), "{err}");
    // `--shader` names another copy of the profiled shader.
    let copy = tmp.path().join("elsewhere.wgsl");
    std::fs::write(&copy, &text).unwrap();
    let (code, _, err) = emit(&["--shader", copy.to_str().unwrap()]);
    assert_eq!(code, 0, "{err}");

    // An unreachable speedup: the output is still written, exit 3.
    let (code, _, err) = emit(&["--shader", copy.to_str().unwrap(), "--min-speedup", "1000"]);
    assert_eq!(code, 3, "{err}");
    assert!(err.contains("--min-speedup 1000"), "{err}");
    assert!(out.join("report.json").exists());

    // A directory holding other files is not replaced.
    let (code, _, err) = reproj(
        tmp.path(),
        &[
            "emit",
            "--max-error",
            "1",
            "--profile",
            "repo/profiles/tiny.profile.json",
            "--shader",
            copy.to_str().unwrap(),
            "--out",
            "repo",
        ],
    );
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("refusing to replace"), "{err}");
    assert!(repo.join("profiles/tiny.profile.json").exists());
}

/// Kill `analyze` mid-way, run it again: it resumes from the journal (every recorded replay reused,
/// none done twice) and writes what an uninterrupted run writes: the same error for every (node,
/// strategy, Δn) both measured. (Which nodes and strategies are measured at all depends on frame
/// times, which differ between two runs on a shared machine.)
#[test]
fn a_killed_analyze_resumes_from_its_journal() {
    let tmp = tempfile::tempdir().unwrap();
    let data = root().join("crates/reproj-replay/tests/data");
    std::fs::copy(data.join("tiny.wgsl"), tmp.path().join("tiny.wgsl")).unwrap();
    std::fs::copy(data.join("tiny_moving.json"), tmp.path().join("tiny.json")).unwrap();
    let args = |out: &str| {
        vec![
            "analyze".to_string(),
            "tiny.wgsl".into(),
            "--session".into(),
            "tiny.json".into(),
            "--out".into(),
            out.into(),
            "--delta-n".into(),
            "2,4,8".into(),
            "--holdout".into(),
            "6".into(),
            "--max-nodes".into(),
            "4".into(),
            // One strategy: which strategy a node keeps depends on noisy frame times.
            "--strategy".into(),
            "3pass".into(),
            "--no-charts".into(),
        ]
    };
    // Replays done and reused, races done and reused.
    let counts = |err: &str| -> [usize; 4] {
        let line = err
            .lines()
            .find(|l| l.starts_with("replayed "))
            .unwrap_or_else(|| panic!("no summary line: {err}"));
        let n: Vec<usize> = line
            .split(|c: char| !c.is_ascii_digit())
            .filter_map(|w| w.parse().ok())
            .collect();
        [n[0], n[1], n[2], n[3]]
    };

    // Uninterrupted.
    let whole = args("whole.profile.json");
    let whole: Vec<&str> = whole.iter().map(String::as_str).collect();
    let (code, _, err) = reproj(tmp.path(), &whole);
    assert_eq!(code, 0, "{err}");
    let [all, reused, raced, races_reused] = counts(&err);
    assert_eq!(reused + races_reused, 0);
    assert!(all >= 6, "{err}");
    assert!(raced >= 1, "every node races the original: {err}");
    assert!(!tmp.path().join("whole.profile.journal").exists());

    // Killed once its journal holds three replays.
    let mut child = Command::new(env!("CARGO_BIN_EXE_reproj"))
        .args(args("cut.profile.json"))
        .current_dir(tmp.path())
        .env("NODEVICE_SELECT", "1")
        .env("REPROJ_NO_CEILING", "1")
        .stderr(std::process::Stdio::null())
        .stdout(std::process::Stdio::null())
        .spawn()
        .unwrap();
    let journal_path = tmp.path().join("cut.profile.journal");
    loop {
        let lines = std::fs::read_to_string(&journal_path).map_or(0, |t| t.lines().count());
        // Header, the original, three replays.
        if lines >= 5 {
            child.kill().unwrap();
            break;
        }
        assert!(
            child.try_wait().unwrap().is_none(),
            "analyze ended before it could be killed"
        );
        std::thread::sleep(std::time::Duration::from_millis(2));
    }
    child.wait().unwrap();
    assert!(
        !tmp.path().join("cut.profile.json").exists(),
        "killed before the end"
    );
    let journal = std::fs::read_to_string(tmp.path().join("cut.profile.journal")).unwrap();
    // Header, then whole records (a torn last line does not count).
    let records: Vec<serde_json::Value> = journal
        .lines()
        .skip(1)
        .filter_map(|l| serde_json::from_str::<serde_json::Value>(l).ok())
        .filter(|r| r["strategy"] != "original")
        .collect();
    let races = records.iter().filter(|r| r.get("race").is_some()).count();
    let recorded = records.len() - races;
    assert!(records.len() >= 3, "{journal}");
    assert!(races >= 1, "the first node's race is journaled: {journal}");

    // Again: resumes.
    let cut = args("cut.profile.json");
    let cut: Vec<&str> = cut.iter().map(String::as_str).collect();
    let (code, _, err) = reproj(tmp.path(), &cut);
    assert_eq!(code, 0, "{err}");
    assert!(err.contains("resuming:"), "{err}");
    let [replayed, reused, _, races_reused] = counts(&err);
    assert_eq!(reused, recorded, "every recorded replay reused: {err}");
    assert_eq!(races_reused, races, "every recorded race reused: {err}");
    assert!(replayed >= 1, "{err}");
    assert!(!tmp.path().join("cut.profile.journal").exists());

    let load = |name: &str| -> serde_json::Value {
        serde_json::from_str(&std::fs::read_to_string(tmp.path().join(name)).unwrap()).unwrap()
    };
    // Per node: id, strategy, (Δn, error) per measurement.
    type Summary = Vec<(u64, String, Vec<(u64, f64)>)>;
    let summary = |p: &serde_json::Value| -> Summary {
        p["nodes"]
            .as_array()
            .unwrap()
            .iter()
            .map(|n| {
                (
                    n["id"].as_u64().unwrap(),
                    n["strategy"].as_str().unwrap().to_string(),
                    n["measurements"]
                        .as_array()
                        .unwrap()
                        .iter()
                        .map(|m| (m["delta_n"].as_u64().unwrap(), m["error"].as_f64().unwrap()))
                        .collect(),
                )
            })
            .collect()
    };
    let (a, b) = (
        summary(&load("whole.profile.json")),
        summary(&load("cut.profile.json")),
    );
    assert_eq!(a.len(), b.len(), "the same nodes");
    let mut compared = 0;
    for (x, y) in a.iter().zip(&b) {
        assert_eq!(x.0, y.0);
        if x.1 != y.1 {
            continue;
        }
        for (dx, ex) in &x.2 {
            if let Some((_, ey)) = y.2.iter().find(|(dy, _)| dy == dx) {
                assert!(
                    (ex - ey).abs() <= 1e-9 * ex.abs().max(1e-6),
                    "node {} Δn {dx}: {ex} vs {ey}",
                    x.0
                );
                compared += 1;
            }
        }
    }
    assert!(compared >= 1);

    // --fresh ignores a journal.
    std::fs::write(tmp.path().join("cut.profile.journal"), journal).unwrap();
    let mut fresh = cut.clone();
    fresh.push("--fresh");
    let (code, _, err) = reproj(tmp.path(), &fresh);
    assert_eq!(code, 0, "{err}");
    assert!(!err.contains("resuming"), "{err}");
    assert_eq!(counts(&err)[1], 0, "{err}");
}

/// Three shards merged give the unsharded profile: the same nodes, strategies, periods and errors,
/// and one hit-rate model over all of them. Shards that do not belong together are refused.
#[test]
fn three_shards_merge_into_the_unsharded_profile() {
    let tmp = tempfile::tempdir().unwrap();
    let data = root().join("crates/reproj-replay/tests/data");
    std::fs::copy(data.join("tiny.wgsl"), tmp.path().join("tiny.wgsl")).unwrap();
    std::fs::copy(data.join("tiny_moving.json"), tmp.path().join("tiny.json")).unwrap();
    let analyze = |out: &str, shard: Option<&str>| {
        let mut a = vec![
            "analyze",
            "tiny.wgsl",
            "--session",
            "tiny.json",
            "--out",
            out,
            "--delta-n",
            "2,4,8",
            "--holdout",
            "6",
            "--max-nodes",
            "5",
            "--strategy",
            "3pass",
            "--no-charts",
        ];
        if let Some(s) = shard {
            a.extend(["--shard", s]);
        }
        let (code, _, err) = reproj(tmp.path(), &a);
        assert_eq!(code, 0, "{err}");
    };
    analyze("whole.profile.json", None);
    std::fs::create_dir_all(tmp.path().join("shards")).unwrap();
    for i in 0..3 {
        analyze(
            &format!("shards/s{i}.profile.json"),
            Some(&format!("{i}/3")),
        );
    }
    let (code, out, err) = reproj(
        tmp.path(),
        &[
            "merge",
            "shards/s2.profile.json",
            "shards/s0.profile.json",
            "shards/s1.profile.json",
            "--out",
            "merged.profile.json",
        ],
    );
    assert_eq!(code, 0, "{err}");
    assert!(out.contains("merged 3 shards"), "{out}");
    let load = |name: &str| -> serde_json::Value {
        serde_json::from_str(&std::fs::read_to_string(tmp.path().join(name)).unwrap()).unwrap()
    };
    let (whole, merged) = (load("whole.profile.json"), load("merged.profile.json"));
    assert!(merged.get("shard").is_none());
    assert_eq!(merged["shader"]["path"], "tiny.wgsl");
    let nodes = |p: &serde_json::Value| -> Vec<(u64, String, Vec<u64>)> {
        p["nodes"]
            .as_array()
            .unwrap()
            .iter()
            .map(|n| {
                (
                    n["id"].as_u64().unwrap(),
                    n["strategy"].as_str().unwrap().to_string(),
                    n["measurements"]
                        .as_array()
                        .unwrap()
                        .iter()
                        .map(|m| m["delta_n"].as_u64().unwrap())
                        .collect(),
                )
            })
            .collect()
    };
    let (a, b) = (nodes(&whole), nodes(&merged));
    assert_eq!(
        a.iter().map(|n| n.0).collect::<Vec<_>>(),
        b.iter().map(|n| n.0).collect::<Vec<_>>(),
        "the same nodes"
    );
    // Errors are deterministic; which nodes are set aside after Δn = 8 depends on frame times.
    for (x, y) in whole["nodes"]
        .as_array()
        .unwrap()
        .iter()
        .zip(merged["nodes"].as_array().unwrap())
    {
        let (mx, my) = (x["measurements"][0].clone(), y["measurements"][0].clone());
        assert_eq!(mx["delta_n"], my["delta_n"]);
        let (ex, ey) = (mx["error"].as_f64().unwrap(), my["error"].as_f64().unwrap());
        assert!(
            (ex - ey).abs() <= 1e-9 * ex.abs().max(1e-6),
            "node {}: {ex} vs {ey}",
            x["id"]
        );
    }
    assert!(
        merged["hit_rate"]["mu"].as_f64().is_some(),
        "{}",
        merged["hit_rate"]
    );

    // A missing shard, a shard twice, a shard of another session: exit 2, nothing written.
    let refuse = |args: &[&str], says: &str| {
        let mut a = vec!["merge"];
        a.extend(args);
        a.extend(["--out", "bad.profile.json"]);
        let (code, _, err) = reproj(tmp.path(), &a);
        assert_eq!(code, 2, "{err}");
        assert!(err.contains(says), "{says}: {err}");
        assert!(!tmp.path().join("bad.profile.json").exists());
    };
    refuse(
        &["shards/s0.profile.json", "shards/s1.profile.json"],
        "missing shard(s) 2/3",
    );
    refuse(
        &[
            "shards/s0.profile.json",
            "shards/s0.profile.json",
            "shards/s1.profile.json",
        ],
        "both shard 0/3",
    );
    let mut other = load("shards/s2.profile.json");
    other["session"]["hash"] = "0123456789abcdef".into();
    std::fs::write(
        tmp.path().join("shards/other.profile.json"),
        serde_json::to_string(&other).unwrap(),
    )
    .unwrap();
    refuse(
        &[
            "shards/s0.profile.json",
            "shards/s1.profile.json",
            "shards/other.profile.json",
        ],
        "differ in `session.hash`",
    );
    refuse(&["whole.profile.json"], "is not a shard");
}
