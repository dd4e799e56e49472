//! `reproj compare` through the real binary on a tiny session: the table, `compare.json` (every
//! number finite), the chart and crops; reproj's own choice from a profile; bad input exits 2 and
//! writes nothing.

use std::path::Path;

use crate::common::{root, run as reproj};

fn numbers(v: &serde_json::Value, path: &str, out: &mut Vec<(String, f64)>) {
    match v {
        serde_json::Value::Number(n) => out.push((path.into(), n.as_f64().unwrap())),
        serde_json::Value::Array(a) => {
            for (i, x) in a.iter().enumerate() {
                numbers(x, &format!("{path}[{i}]"), out);
            }
        }
        serde_json::Value::Object(o) => {
            for (k, x) in o {
                numbers(x, &format!("{path}.{k}"), out);
            }
        }
        _ => {}
    }
}

fn setup(dir: &Path) {
    let data = root().join("crates/reproj-replay/tests/data");
    std::fs::copy(data.join("tiny.wgsl"), dir.join("tiny.wgsl")).unwrap();
    std::fs::copy(data.join("tiny_moving.json"), dir.join("tiny.json")).unwrap();
}

#[test]
fn compare_prints_the_table_and_writes_the_report_chart_and_crops() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    setup(dir);
    let (code, _, err) = reproj(
        dir,
        &[
            "analyze",
            "tiny.wgsl",
            "--session",
            "tiny.json",
            "--out",
            "tiny.profile.json",
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
    let args = [
        "compare",
        "tiny.wgsl",
        "--session",
        "tiny.json",
        "--speedup",
        "1.5",
        "--profile",
        "tiny.profile.json",
        "--max-frames",
        "6",
        "--candidates",
        "3",
        "--max-steps",
        "2",
        "--resize-tries",
        "2",
        "--out",
        "cmp",
    ];
    let (code, out, err) = reproj(dir, &args);
    assert_eq!(code, 0, "{err}");
    for method in [
        "original",
        "resize",
        "easu",
        "temporal",
        "simplify",
        "reproj",
        "reproj+temporal",
    ] {
        assert!(out.lines().any(|l| l.starts_with(method)), "{out}");
    }
    assert!(out.contains("vs 16 spp"), "{out}");
    let mut files: Vec<String> = std::fs::read_dir(dir.join("cmp"))
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    files.sort();
    assert_eq!(
        files,
        [
            "compare.json",
            "compare.png",
            "compare.svg",
            "crops.png",
            "simplified.wgsl"
        ]
    );
    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("cmp/compare.json")).unwrap())
            .unwrap();
    assert_eq!(json["schema"], "reproj.compare");
    assert_eq!(json["version"], 6);
    assert_eq!(json["supersample"], 16);
    assert!(
        json["original_vs_supersampled"]["psnr"].is_number(),
        "{json}"
    );
    assert_eq!(json["frames"], 4, "--max-frames 6 of a 4-frame session");
    let methods: Vec<&str> = json["methods"]
        .as_array()
        .unwrap()
        .iter()
        .map(|m| m["method"].as_str().unwrap())
        .collect();
    assert_eq!(
        methods,
        [
            "resize",
            "easu",
            "temporal",
            "simplify",
            "reproj",
            "reproj+temporal"
        ]
    );
    for m in json["methods"].as_array().unwrap() {
        // serde_json writes NaN as null: a missing number is a failure here.
        for key in ["speedup", "frame_ms", "error", "psnr", "flip"] {
            assert!(m[key].is_number(), "{key} of {m}");
        }
        // And against the supersampled reference, every method (reproj's frames read back raw).
        for key in ["psnr", "flip"] {
            assert!(
                m["supersampled"][key].is_number(),
                "supersampled {key} of {m}"
            );
        }
        // The speeds come from one interleaved run, each with its interval.
        let s = m["speedup"].as_f64().unwrap();
        let [lo, hi] = [
            m["speedup_ci95"][0].as_f64().unwrap(),
            m["speedup_ci95"][1].as_f64().unwrap(),
        ];
        assert!(lo <= s && s <= hi, "{m}");
    }
    let mut all = Vec::new();
    numbers(&json, "", &mut all);
    assert!(all.iter().all(|(_, v)| v.is_finite()), "{all:?}");
    assert!(json["reproj"]["delta_n"].as_u64().unwrap() >= 2);
    // At a target speedup reproj's point is steered by measurement: each try raced with its
    // interval, distinct, at most --reproj-tries, the reported point among them and the closest
    // to the target — unless the final run put reproj and resizing more than 3 % apart and the
    // profile's point for resizing's speed there is another one (a rematch that moved).
    let key = |t: &serde_json::Value| (t["node"].to_string(), t["delta_n"].as_u64().unwrap());
    let check = |tries: &[serde_json::Value]| {
        assert!((1..=4).contains(&tries.len()), "{tries:?}");
        for (i, t) in tries.iter().enumerate() {
            let s = t["speedup"].as_f64().unwrap();
            let (lo, hi) = (
                t["speedup_ci95"][0].as_f64().unwrap(),
                t["speedup_ci95"][1].as_f64().unwrap(),
            );
            assert!(lo <= s && s <= hi && s > 0.0, "{t}");
            assert!(tries[..i].iter().all(|u| key(u) != key(t)), "{tries:?}");
            // One race, or two pooled when the first could not place the try.
            assert!(matches!(t["races"].as_u64(), Some(1 | 2)), "{t}");
        }
    };
    let tries = json["reproj"]["tries"].as_array().expect("reproj's tries");
    check(tries);
    let reported = (
        json["reproj"]["node"].to_string(),
        json["reproj"]["delta_n"].as_u64().unwrap(),
    );
    let miss = |t: &serde_json::Value| (t["speedup"].as_f64().unwrap() / 1.5).ln().abs();
    // The try closest to the target: what the first steering kept.
    let closest = tries
        .iter()
        .min_by(|a, b| miss(a).total_cmp(&miss(b)))
        .unwrap();
    let rematch = &json["reproj"]["rematch"];
    if !rematch.is_null() {
        let (to, from) = (
            rematch["to_speedup"].as_f64().unwrap(),
            rematch["from_speedup"].as_f64().unwrap(),
        );
        assert!((from / to).ln().abs() > 1.03f64.ln(), "{rematch}");
        assert!(rematch["asked"].as_f64().unwrap() > 0.0, "{rematch}");
        // Moved: the reported point is the one for resizing's speed, not the tries' pick.
        assert_eq!(rematch["moved"] == true, key(closest) != reported, "{json}");
    }
    if rematch.is_null() || rematch["moved"] == false {
        // The reported point was raced, and is the closest to the target.
        assert_eq!(key(closest), reported, "{tries:?}");
    }
    assert!(json["measured_on"].as_str().is_some(), "{json}");
    // The simplified shader is valid WGSL.
    let wgsl = std::fs::read_to_string(dir.join("cmp/simplified.wgsl")).unwrap();
    reproj_front::parse_shader(Path::new("simplified.wgsl"), wgsl).unwrap();
    let crops = image::open(dir.join("cmp/crops.png")).unwrap();
    assert!(
        crops.width() > 3 * crops.height() / 2,
        "four panels side by side"
    );

    // The profile's report page shows the run: its table and its crops. A folder without a
    // compare.json: exit 2 naming the file, and no page.
    let (code, _, err) = reproj(
        dir,
        &[
            "report",
            "tiny.profile.json",
            "--compare",
            "cmp",
            "--max-rendered",
            "1",
            "--out",
            "page.html",
        ],
    );
    assert_eq!(code, 0, "{err}");
    let page = std::fs::read_to_string(dir.join("page.html")).unwrap();
    assert!(
        page.contains("Against other methods at equal time"),
        "no compare section"
    );
    assert!(page.contains("<td>reproj+temporal</td>"), "no composed row");
    assert!(page.contains("alt=\"crops of the middle frame"), "no crops");
    let (code, _, err) = reproj(
        dir,
        &[
            "report",
            "tiny.profile.json",
            "--compare",
            "nowhere",
            "--out",
            "bad.html",
        ],
    );
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("compare.json"), "{err}");
    assert!(!dir.join("bad.html").exists());

    // --json prints the same document.
    let mut json_args = args.to_vec();
    json_args.push("--json");
    *json_args.iter_mut().find(|a| **a == "cmp").unwrap() = "cmp2";
    let (code, out, err) = reproj(dir, &json_args);
    assert_eq!(code, 0, "{err}");
    let printed: serde_json::Value = serde_json::from_str(&out).unwrap();
    assert_eq!(printed["schema"], "reproj.compare");
    assert!(printed.get("max_error").is_none(), "{printed}");

    // An error budget instead of a speedup: every method aims at what reproj's selection under it
    // is predicted to reach — or, when reproj keeps the original there, one clear error.
    let budget_args: Vec<&str> = json_args
        .iter()
        .map(|a| match *a {
            "--speedup" => "--max-error",
            "1.5" => "0.5",
            "cmp2" => "cmp3",
            a => a,
        })
        .collect();
    let (code, out, err) = reproj(dir, &budget_args);
    if code == 0 {
        let printed: serde_json::Value = serde_json::from_str(&out).unwrap();
        assert_eq!(printed["max_error"], 0.5);
        let target = printed["target_speedup"].as_f64().unwrap();
        let predicted = printed["reproj"]["predicted_speedup"].as_f64().unwrap();
        assert!(
            target > 1.0 && (target - predicted).abs() < 1e-9,
            "{printed}"
        );
        assert!(printed["reproj"]["predicted_error"].as_f64().unwrap() <= 0.5);
    } else {
        assert_eq!(code, 2, "{err}");
        assert!(err.contains("keeps the original shader"), "{err}");
        assert!(!dir.join("cmp3").exists());
    }
}

#[test]
fn bad_compare_input_exits_2_and_writes_nothing() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    setup(dir);
    let cases: [&[&str]; 3] = [
        &[
            "compare",
            "tiny.wgsl",
            "--session",
            "tiny.json",
            "--speedup",
            "0.5",
            "--out",
            "o",
        ],
        &[
            "compare",
            "missing.wgsl",
            "--session",
            "tiny.json",
            "--speedup",
            "2",
            "--out",
            "o",
        ],
        &[
            "compare",
            "tiny.wgsl",
            "--session",
            "tiny.json",
            "--speedup",
            "2",
            "--profile",
            "nope.profile.json",
            "--out",
            "o",
        ],
    ];
    for args in cases {
        let (code, out, err) = reproj(dir, args);
        assert_eq!(code, 2, "{args:?}: {out}{err}");
        assert_eq!(
            err.trim().lines().count(),
            1,
            "{args:?}: one message: {err}"
        );
        assert!(!dir.join("o").exists(), "{args:?} wrote output");
    }
    // A budget needs a profile, and is given instead of a speedup: usage errors.
    let usage: [&[&str]; 2] = [
        &[
            "compare",
            "tiny.wgsl",
            "--session",
            "tiny.json",
            "--max-error",
            "0.01",
            "--out",
            "o",
        ],
        &[
            "compare",
            "tiny.wgsl",
            "--session",
            "tiny.json",
            "--speedup",
            "2",
            "--max-error",
            "0.01",
            "--profile",
            "p.json",
            "--out",
            "o",
        ],
    ];
    for args in usage {
        let (code, out, err) = reproj(dir, args);
        assert_eq!(code, 2, "{args:?}: {out}{err}");
        assert!(err.contains("--max-error"), "{args:?}: {err}");
        assert!(!dir.join("o").exists(), "{args:?} wrote output");
    }
}
