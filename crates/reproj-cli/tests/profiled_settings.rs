//! What `emit` writes is what `analyze` measured: a profile records its variants' reconstruction
//! and cache format, and the emitted manifest uses them (`--cache-format` overrides the format).

use crate::common;
use crate::common::run;

#[test]
fn emit_writes_the_reconstruction_and_format_the_profile_measured() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    common::two_terms(dir, "t.wgsl", "t.json");
    let (code, _, err) = common::analyze_short(
        dir,
        "t.wgsl",
        &["t.json"],
        "t.profile.json",
        &[
            "--strategy",
            "3pass",
            "--reconstruct",
            "catmull-rom",
            "--cache-format",
            "f16",
        ],
    );
    assert_eq!(code, 0, "{err}");
    let read = |p: &str| -> serde_json::Value {
        serde_json::from_str(&std::fs::read_to_string(dir.join(p)).unwrap()).unwrap()
    };
    let profile = read("t.profile.json");
    assert_eq!(profile["reconstruct"], "catmull-rom");
    assert_eq!(profile["cache_format"], "f16");
    let emit = |out: &str, extra: &[&str]| {
        let mut a = vec![
            "emit",
            "--profile",
            "t.profile.json",
            "--max-error",
            "0.05",
            "--out",
            out,
        ];
        a.extend_from_slice(extra);
        run(dir, &a)
    };
    let (code, _, err) = emit("v", &[]);
    assert_eq!(code, 0, "{err}");
    let manifest = read("v/manifest.json");
    assert_eq!(manifest["reconstruct"], "catmull-rom", "{manifest}");
    assert!(
        manifest["cache_format"]
            .as_str()
            .unwrap()
            .contains("16float"),
        "{manifest}"
    );
    // --cache-format overrides the profile's.
    let (code, _, err) = emit("w", &["--cache-format", "f32"]);
    assert_eq!(code, 0, "{err}");
    let manifest = read("w/manifest.json");
    assert!(
        manifest["cache_format"]
            .as_str()
            .unwrap()
            .contains("32float"),
        "{manifest}"
    );
    assert_eq!(manifest["reconstruct"], "catmull-rom");
}

/// `analyze --reconstruct auto` races Catmull-Rom against bilinear per node and records each
/// node's filter, the races behind it, and the filter each node kept; `emit` writes the chosen
/// node's own filter into the manifest (and a profile is data: a node whose record says
/// `catmull-rom` is written so, its neighbour `bilinear`; a profile without per-node filters
/// reads the profile's).
#[test]
fn analyze_auto_records_each_node_s_filter_and_emit_writes_it() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    common::two_terms(dir, "t.wgsl", "t.json");
    let (code, _, err) = common::analyze_short(
        dir,
        "t.wgsl",
        &["t.json"],
        "t.profile.json",
        &["--strategy", "2pass", "--reconstruct", "auto"],
    );
    assert_eq!(code, 0, "{err}");
    let read = |p: &str| -> serde_json::Value {
        serde_json::from_str(&std::fs::read_to_string(dir.join(p)).unwrap()).unwrap()
    };
    let profile = read("t.profile.json");
    assert_eq!(profile["version"], 14);
    assert_eq!(profile["reconstruct"], "bilinear", "the base filter");
    let nodes = profile["nodes"].as_array().unwrap();
    let probes = profile["filter_probes"]
        .as_array()
        .cloned()
        .unwrap_or_default();
    let mut raced = 0;
    for n in nodes {
        let filter = n["reconstruct"]
            .as_str()
            .expect("every node names its filter");
        assert!(["bilinear", "catmull-rom"].contains(&filter), "{n}");
        // The challenger's probe says whether it was kept, and the node agrees.
        let challenger = probes
            .iter()
            .find(|p| p["node"] == n["id"] && p["reconstruct"] == "catmull-rom");
        if let Some(p) = challenger {
            raced += 1;
            // Only a node whose base pays at the longest period is raced.
            let base = profile["strategy_probes"]
                .as_array()
                .unwrap()
                .iter()
                .find(|s| s["node"] == n["id"] && s["kept"] == true)
                .unwrap();
            assert!(base["speedup"].as_f64().unwrap() > 1.0, "{base}");
            assert!(p["note"].is_string(), "{p}");
            assert_eq!(p["kept"] == true, filter == "catmull-rom", "{p} {n}");
            assert!(p["error"].as_f64().unwrap() >= 0.0);
        } else {
            assert_eq!(filter, "bilinear", "an unraced node keeps the base: {n}");
        }
        // A kept challenger's measurements are its own: every period replayed again.
        if filter == "catmull-rom" && n["status"] == "ok" {
            assert!(n["measurements"].as_array().unwrap().len() >= 3, "{n}");
        }
    }
    assert!(raced > 0, "at least one node was raced: {probes:?}");
    // Every raced node kept exactly one filter.
    for p in probes.iter().filter(|p| p["reconstruct"] == "catmull-rom") {
        let kept = probes
            .iter()
            .filter(|q| q["node"] == p["node"] && q["kept"] == true)
            .count();
        assert!(kept <= 1, "{probes:?}");
    }

    // emit writes the chosen node's own filter.
    let emit = |profile: &str, out: &str, extra: &[&str]| {
        let mut a = vec![
            "emit",
            "--profile",
            profile,
            "--max-error",
            "0.5",
            "--out",
            out,
        ];
        a.extend_from_slice(extra);
        run(dir, &a)
    };
    let (code, _, err) = emit("t.profile.json", "v", &[]);
    assert_eq!(code, 0, "{err}");
    let report = read("v/report.json");
    if let Some(chosen) = report["node"].as_str() {
        let node = nodes
            .iter()
            .find(|n| {
                (chosen == "root" && n["root"] == true)
                    || chosen.parse::<u64>().ok() == n["id"].as_u64()
            })
            .unwrap();
        let manifest = read("v/manifest.json");
        assert_eq!(manifest["reconstruct"], node["reconstruct"], "{manifest}");
        assert_eq!(report["reconstruct"], node["reconstruct"], "{report}");
    }

    // Per-node filters as data: the usable nodes given one filter each, emitted node by node.
    let mut edited = profile.clone();
    let usable: Vec<u64> = nodes
        .iter()
        .filter(|n| n["status"] == "ok" && n["root"] == false)
        .map(|n| n["id"].as_u64().unwrap())
        .collect();
    assert!(!usable.is_empty(), "{profile}");
    for (i, n) in edited["nodes"]
        .as_array_mut()
        .unwrap()
        .iter_mut()
        .enumerate()
    {
        n["reconstruct"] = if i % 2 == 0 {
            "catmull-rom"
        } else {
            "bilinear"
        }
        .into();
    }
    std::fs::write(
        dir.join("e.profile.json"),
        serde_json::to_string(&edited).unwrap(),
    )
    .unwrap();
    for (i, n) in edited["nodes"].as_array().unwrap().iter().enumerate() {
        if !usable.contains(&n["id"].as_u64().unwrap()) {
            continue;
        }
        let out = format!("e{i}");
        let id = n["id"].to_string();
        let (code, _, err) = emit("e.profile.json", &out, &["--node", &id]);
        assert_eq!(code, 0, "{err}");
        if read(&format!("{out}/report.json"))["node"].is_null() {
            continue; // not selectable under the budget: the original is written
        }
        let manifest = read(&format!("{out}/manifest.json"));
        assert_eq!(manifest["reconstruct"], n["reconstruct"], "node {id}");
    }
    // A profile before version 9: no per-node filter, the profile's for every node.
    let mut old = profile.clone();
    old["version"] = 8.into();
    old["reconstruct"] = "catmull-rom".into();
    old.as_object_mut().unwrap().remove("filter_probes");
    for n in old["nodes"].as_array_mut().unwrap() {
        n.as_object_mut().unwrap().remove("reconstruct");
    }
    std::fs::write(
        dir.join("o.profile.json"),
        serde_json::to_string(&old).unwrap(),
    )
    .unwrap();
    let id = usable[0].to_string();
    let (code, _, err) = emit("o.profile.json", "o", &["--node", &id]);
    assert_eq!(code, 0, "{err}");
    assert_eq!(read("o/manifest.json")["reconstruct"], "catmull-rom");
}

/// One variant has one filter: `auto` is for `analyze` alone.
#[test]
fn instance_refuses_reconstruct_auto() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    common::two_terms(dir, "t.wgsl", "t.json");
    let (code, _, err) = run(
        dir,
        &[
            "instance",
            "t.wgsl",
            "--node",
            "root",
            "--reconstruct",
            "auto",
            "--out",
            "v",
        ],
    );
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("--reconstruct auto"), "{err}");
    assert!(!dir.join("v").exists());
}

/// `analyze --block auto` races a larger refresh block per node (at 64×64, k=8: an eighth of the
/// side) against the strategy's default at Δn 8 (the longest training period at most half the
/// 24 frames) and records the race; every node's block is one of the
/// two, the larger kept exactly where its probe says so, and `emit` writes the chosen node's own
/// block into the manifest.
#[test]
fn analyze_block_auto_records_each_node_s_block_and_emit_writes_it() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    common::two_terms(dir, "t.wgsl", "t.json");
    let (code, _, err) = common::analyze_short(
        dir,
        "t.wgsl",
        &["t.json"],
        "t.profile.json",
        &["--strategy", "2pass", "--block", "auto"],
    );
    assert_eq!(code, 0, "{err}");
    let read = |p: &str| -> serde_json::Value {
        serde_json::from_str(&std::fs::read_to_string(dir.join(p)).unwrap()).unwrap()
    };
    let profile = read("t.profile.json");
    assert_eq!(profile["version"], 14);
    let probes = profile["block_probes"]
        .as_array()
        .cloned()
        .unwrap_or_default();
    assert!(!probes.is_empty(), "at least one node was raced: {profile}");
    for n in profile["nodes"].as_array().unwrap() {
        let block = n["block"].as_u64().expect("every node names its block");
        let challenger = probes
            .iter()
            .find(|p| p["node"] == n["id"] && p["block"] == 8);
        match challenger {
            Some(p) => {
                assert!(p["note"].is_string(), "{p}");
                assert_eq!(p["kept"] == true, block == 8, "{p} {n}");
                // Both replayed at the same (longest) period; the base's probe is there too.
                let base = probes
                    .iter()
                    .find(|q| q["node"] == n["id"] && q["block"] == 4)
                    .expect("the base's probe");
                assert_eq!(base["delta_n"], p["delta_n"]);
                // The 24-frame session: the longest training period at most half of it.
                assert_eq!(p["delta_n"], 8, "{p}");
                assert_eq!(base["kept"] == true, block == 4, "{base} {n}");
                if block == 8 {
                    // Kept only when more accurate, and its periods are its own.
                    assert!(p["error"].as_f64() < base["error"].as_f64(), "{p} {base}");
                    assert!(p["speedup"].is_number(), "{p}");
                    // Its own measurements at the race's period and at the longest one.
                    let periods: Vec<u64> = n["measurements"]
                        .as_array()
                        .unwrap()
                        .iter()
                        .map(|m| m["delta_n"].as_u64().unwrap())
                        .collect();
                    assert!(periods.contains(&8) && periods.contains(&24), "{n}");
                }
            }
            None => assert_eq!(block, 4, "an unraced node keeps the default: {n}"),
        }
    }
    let (code, _, err) = run(
        dir,
        &[
            "emit",
            "--profile",
            "t.profile.json",
            "--max-error",
            "0.5",
            "--out",
            "v",
        ],
    );
    assert_eq!(code, 0, "{err}");
    let report = read("v/report.json");
    if let Some(chosen) = report["node"].as_str() {
        let node = profile["nodes"]
            .as_array()
            .unwrap()
            .iter()
            .find(|n| {
                (chosen == "root" && n["root"] == true)
                    || chosen.parse::<u64>().ok() == n["id"].as_u64()
            })
            .unwrap();
        let manifest = read("v/manifest.json");
        assert_eq!(manifest["params"]["block"], node["block"], "{manifest}");
    }
}

/// One variant has one block size: `--block auto` is for `analyze` alone.
#[test]
fn instance_refuses_block_auto() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    common::two_terms(dir, "t.wgsl", "t.json");
    let (code, _, err) = run(
        dir,
        &[
            "instance", "t.wgsl", "--node", "root", "--block", "auto", "--out", "v",
        ],
    );
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("--block auto"), "{err}");
    assert!(!dir.join("v").exists());
    // A bad size names both forms.
    let (code, _, err) = run(
        dir,
        &["analyze", "t.wgsl", "--session", "t.json", "--block", "3"],
    );
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("auto"), "{err}");
}
