//! `emit --verify` keeps the budget's promise: on a session with faster motion than the profile
//! saw, an error over the budget is a warning naming a tighter budget and exit 4 — never a silent
//! exit 0; and by default emit carries the profile to that session's motion first, so that the
//! choice holds there.

use crate::common;
use crate::common::run;

/// Given the session it is for, emit measures that session's motion and carries the profile to it
/// before selecting: the fast session (outside the one profiled motion) gets a warning saying so,
/// its own predicted error within the budget, a shorter period than the profiled motion alone
/// would allow, and a measured error that the carried prediction foresaw.
#[test]
fn emit_carries_the_profile_to_the_motion_of_the_session_it_is_for() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    common::two_terms(dir, "two_terms.wgsl", "two_terms.json");
    common::two_terms_fast(dir, "fast.json");
    let (code, _, err) = common::analyze_short(
        dir,
        "two_terms.wgsl",
        &["two_terms.json"],
        "t.profile.json",
        &["--strategy", "3pass"],
    );
    assert_eq!(code, 0, "{err}");
    let profile: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("t.profile.json")).unwrap())
            .unwrap();
    let profiled_motion = profile["motion"]["pixels_per_frame"].as_f64().unwrap();
    assert!(profiled_motion > 0.0, "{}", profile["motion"]);
    let emit = |motion: &str, out: &str| {
        let (code, out, err) = run(
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
                "fast.json",
                "--motion",
                motion,
                // The choice as predicted: this test is about motion, not the runoff.
                "--runoff",
                "1",
                "--json",
            ],
        );
        let report: serde_json::Value =
            serde_json::from_str(&out).unwrap_or_else(|_| panic!("{err}"));
        (code, report, err)
    };
    // Selected for the profiled motion alone, the fast session breaks the budget: exit 4.
    let (code, ignored, err) = emit("ignore", "ignored");
    assert!(ignored["node"].is_string(), "{ignored}");
    assert!(
        ignored["measured_error"].as_f64().unwrap() > 0.01,
        "the fast session breaks the budget: {ignored}"
    );
    assert_eq!(code, 4, "{err}");
    assert!(err.contains("is over the budget 0.01"), "{err}");
    assert!(err.contains("--max-error"), "the next safe choice: {err}");
    // The output is still written, with the measured speed's interval.
    assert!(dir.join("ignored/report.json").exists());
    assert!(ignored["measured_speedup_ci95"].is_array(), "{ignored}");

    // Carried to the fast session's motion (the default), the choice holds there.
    let (code, carried, err) = emit("carry", "carried");
    let m = &carried["motion"];
    assert_eq!(carried["version"], 6);
    let target = m["target"]["pixels_per_frame"].as_f64().unwrap();
    assert!(target > 1.5 * profiled_motion, "{m}");
    assert_eq!(m["exponent"]["source"], "assumed", "{m}");
    assert!(err.contains("outside the profiled"), "{err}");
    assert!(err.contains("assumed"), "{err}");
    let predicted = m["target_predicted_error"].as_f64().unwrap();
    assert!(predicted <= 0.01, "{m}");
    // The faster session allows less: a shorter period (or another node).
    assert!(
        carried["node"] != ignored["node"]
            || carried["delta_n"].as_u64() < ignored["delta_n"].as_u64(),
        "{carried} {ignored}"
    );
    let measured = carried["measured_error"].as_f64().unwrap();
    assert!(measured <= 0.01, "{carried}");
    assert_eq!(code, 0, "{err}");
}

/// `emit --adaptive` chooses for a Δn that follows the motion frame by frame: over a session with
/// a burst of fast motion it writes a schedule whose periods differ across the frames, every frame
/// predicted within the budget, and `--verify` renders it adapting and checks the worst band
/// (the frames given one Δn) against the budget too.
#[test]
fn emit_adaptive_chooses_for_the_schedule_and_verifies_every_band() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    common::two_terms(dir, "two_terms.wgsl", "unused.json");
    let sessions = common::root().join("sessions/adaptive");
    for s in [
        "two_terms_slow.json",
        "two_terms_fast.json",
        "two_terms_burst.json",
    ] {
        std::fs::copy(sessions.join(s), dir.join(s)).unwrap();
    }
    let (code, _, err) = common::analyze_short(
        dir,
        "two_terms.wgsl",
        &["two_terms_slow.json", "two_terms_fast.json"],
        "tt.profile.json",
        &["--strategy", "3pass"],
    );
    assert_eq!(code, 0, "{err}");
    let (code, out, err) = run(
        dir,
        &[
            "emit",
            "--profile",
            "tt.profile.json",
            "--profile",
            "tt.two_terms_fast.profile.json",
            "--max-error",
            "0.01",
            "--out",
            "adaptive",
            "--session",
            "two_terms_burst.json",
            "--adaptive",
            "--verify",
            "--json",
        ],
    );
    let report: serde_json::Value = serde_json::from_str(&out).unwrap_or_else(|_| panic!("{err}"));
    assert_eq!(report["version"], 6);
    let a = &report["adaptive"];
    assert_eq!(a["frames"], 96, "{a}");
    assert!(a["delta_n_min"].as_u64() < a["delta_n_max"].as_u64(), "{a}");
    assert!(a["predicted_worst_error"].as_f64().unwrap() <= 0.01, "{a}");
    assert!(a["fixed_node"].is_string(), "{a}");
    let manifest: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("adaptive/manifest.json")).unwrap())
            .unwrap();
    assert!(
        manifest["params"]["schedule"].as_array().unwrap().len() >= 2,
        "{manifest}"
    );
    let band = &a["measured_worst_band"];
    assert!(band["frames"].as_u64().unwrap() > 0, "{a}");
    // The budget holds on the whole session and in the worst band, or the run says so (exit 4).
    let holds = band["error"].as_f64().unwrap() <= 0.01
        && report["measured_error"].as_f64().unwrap() <= 0.01;
    assert_eq!(code, if holds { 0 } else { 4 }, "{err}");
    assert!(holds, "{report}");
}

/// `emit --verify`'s runoff: nodes predicted alike (here two nodes given one timing model and no
/// race, under a budget both hold at the longest period) are timed together, interleaved with the
/// original, and the fastest measured is the one written and verified.
#[test]
fn the_runoff_writes_the_fastest_measured_of_the_nodes_predicted_alike() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    two_terms_profiled_in_2pass(dir);
    let mut profile = two_terms_profile(dir);
    // Every node timed as the first one is, and no interleaved race to scale them apart: their
    // predictions differ only by their periods under the budget.
    let timing = profile["nodes"][0]["timing_fit"].clone();
    let nodes = profile["nodes"].as_array_mut().unwrap();
    assert!(nodes.len() >= 2, "{nodes:?}");
    for n in nodes.iter_mut() {
        n["timing_fit"] = timing.clone();
    }
    for probes in ["strategy_probes", "filter_probes", "block_probes"] {
        profile[probes] = serde_json::json!([]);
    }
    // One node, not the pair of both terms the set search may have profiled (a pair is written
    // without a runoff).
    profile["sets"] = serde_json::json!([]);
    std::fs::write(dir.join("alike.profile.json"), profile.to_string()).unwrap();
    let emit = |out: &str, extra: &[&str]| {
        let mut args = vec![
            "emit",
            "--profile",
            "alike.profile.json",
            "--max-error",
            "1.0",
            "--out",
            out,
            "--verify",
            "--session",
            "two_terms.json",
        ];
        args.extend(extra);
        run(dir, &args)
    };
    let (code, out, err) = emit("alike", &["--json"]);
    assert_eq!(code, 0, "{err}");
    let report: serde_json::Value = serde_json::from_str(&out).unwrap_or_else(|_| panic!("{err}"));
    let r = &report["runoff"];
    let entries = r["entries"]
        .as_array()
        .unwrap_or_else(|| panic!("no runoff ran: {report}"));
    assert!(entries.len() >= 2, "{r}");
    assert!(r["rounds"].as_u64().unwrap() >= 8, "{r}");
    let written: Vec<&serde_json::Value> =
        entries.iter().filter(|e| e["written"] == true).collect();
    assert_eq!(written.len(), 1, "{r}");
    let w = written[0];
    // The written one is the fastest measured, and it is what the report and manifest name.
    let fastest = entries
        .iter()
        .map(|e| e["measured_speedup"].as_f64().unwrap())
        .fold(f64::MIN, f64::max);
    assert_eq!(w["measured_speedup"].as_f64().unwrap(), fastest, "{r}");
    assert_eq!(report["node"], w["node"], "{report}");
    assert_eq!(report["delta_n"], w["delta_n"], "{report}");
    let manifest: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("alike/manifest.json")).unwrap())
            .unwrap();
    assert_eq!(
        manifest["node"]["id"].as_str(),
        w["node"].as_str(),
        "{manifest}"
    );
    assert_eq!(manifest["params"]["delta_n"], w["delta_n"], "{manifest}");
    // Whether the written one is the prediction's choice, the report says.
    let predicted: Vec<&serde_json::Value> = entries
        .iter()
        .filter(|e| e["predicted_choice"] == true)
        .collect();
    assert_eq!(predicted.len(), 1, "{r}");
    assert_eq!(r["changed"], predicted[0]["written"] == false, "{r}");
    // Verified: the written variant's own error and speed.
    assert!(
        report["measured_error"].as_f64().unwrap() <= 1.0,
        "{report}"
    );
    assert!(report["measured_speedup"].as_f64().is_some(), "{report}");

    // The text output lists the contenders, the written one marked.
    let (code, out, err) = emit("alike_text", &[]);
    assert_eq!(code, 0, "{err}");
    assert!(out.contains("runoff "), "{out}");
    assert!(out.contains("→ node"), "{out}");
}

/// A profile records the driver beside the adapter (one adapter name covers lavapipe in Mesa 22.3
/// and in Mesa 25, which keep different strategies), and `emit --verify` on another driver says
/// that the profile's choices were measured elsewhere.
#[test]
fn verify_names_a_profile_measured_on_another_driver() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    let analyzed = two_terms_profiled_in_2pass(dir);
    let mut profile = two_terms_profile(dir);
    assert_eq!(profile["version"], 14);
    let driver = profile["machine"]["driver"]
        .as_str()
        .unwrap_or_else(|| panic!("the adapter names its driver: {}", profile["machine"]))
        .to_owned();
    assert!(
        analyzed.contains(&driver),
        "analyze names the driver: {analyzed}"
    );
    let emit = |profile: &str, out: &str| {
        run(
            dir,
            &[
                "emit",
                "--profile",
                profile,
                "--max-error",
                "0.05",
                "--out",
                out,
                "--verify",
                "--session",
                "two_terms.json",
                "--runoff",
                "1",
                "--json",
            ],
        )
    };
    let (code, out, err) = emit("t.profile.json", "same");
    assert_eq!(code, 0, "{err}");
    assert!(!err.contains("the profile was measured on"), "{err}");
    let report: serde_json::Value = serde_json::from_str(&out).unwrap();
    assert!(
        report["measured_on"].as_str().unwrap().contains(&driver),
        "{report}"
    );
    profile["machine"]["driver"] = "Mesa 0.0 (another driver)".into();
    std::fs::write(dir.join("other.profile.json"), profile.to_string()).unwrap();
    let (code, out, err) = emit("other.profile.json", "other");
    assert_eq!(code, 0, "{err}");
    assert!(
        err.contains("the profile was measured on")
            && err.contains("Mesa 0.0 (another driver)")
            && err.contains(&driver),
        "{err}"
    );
    let report: serde_json::Value = serde_json::from_str(&out).unwrap();
    assert!(
        report["timing_warnings"][0]
            .as_str()
            .unwrap()
            .contains("re-run `reproj analyze`"),
        "{report}"
    );
}

/// `two_terms.wgsl` over `two_terms.json` in `dir`, profiled short in `2pass` into
/// `t.profile.json`: what `analyze` said on stderr.
fn two_terms_profiled_in_2pass(dir: &std::path::Path) -> String {
    common::two_terms(dir, "two_terms.wgsl", "two_terms.json");
    let (code, _, err) = common::analyze_short(
        dir,
        "two_terms.wgsl",
        &["two_terms.json"],
        "t.profile.json",
        &["--strategy", "2pass"],
    );
    assert_eq!(code, 0, "{err}");
    err
}

/// `t.profile.json` in `dir`, as JSON.
fn two_terms_profile(dir: &std::path::Path) -> serde_json::Value {
    serde_json::from_str(&std::fs::read_to_string(dir.join("t.profile.json")).unwrap()).unwrap()
}

/// A shader whose shading costs less than a variant's own passes: `analyze` races the root (and
/// its narrower node `d`) cached and never refreshed against the original first, finds even that
/// slower, profiles no node and says why with the figures, in seconds; `emit` keeps the original with that reason, and
/// `--verify` then reports no speedup and no interval (nothing was raced), only the frame time.
#[test]
fn analyze_stops_at_the_ceiling_where_caching_cannot_pay_and_emit_says_why() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    common::two_terms(dir, "unused.wgsl", "s.json");
    std::fs::write(
        dir.join("cheap.wgsl"),
        "struct In {\n    @location(0) world_pos: vec3<f32>,\n    @location(1) normal: vec3<f32>,\n};\n\
         struct Scene { camera_pos: vec3<f32>, time: f32, light_pos: vec3<f32>, gain: f32, tint: vec3<f32> };\n\
         @group(0) @binding(0) var<uniform> scene: Scene;\n\
         @fragment\nfn fs_main(in: In) -> @location(0) vec4<f32> {\n    \
         let l = normalize(scene.light_pos - in.world_pos);\n    \
         let d = max(dot(normalize(in.normal), l), 0.0);\n    \
         return vec4<f32>(scene.tint * d * scene.gain, 1.0);\n}\n",
    )
    .unwrap();
    let started = std::time::Instant::now();
    let (code, out, err) = common::run_with_ceiling(
        dir,
        &[
            "analyze",
            "cheap.wgsl",
            "--session",
            "s.json",
            "--out",
            "c.profile.json",
            "--delta-n",
            "2,8,16,24",
            "--holdout",
            "4",
            "--no-sets",
            "--no-charts",
        ],
    );
    assert_eq!(code, 0, "{err}");
    assert!(out.contains("caching cannot pay on this device"), "{out}");
    assert!(out.contains("no node profiled"), "{out}");
    assert!(
        started.elapsed().as_secs() < 60,
        "the answer took {:?}",
        started.elapsed()
    );
    let profile: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("c.profile.json")).unwrap())
            .unwrap();
    let ceiling = &profile["ceiling"];
    assert_eq!(ceiling["pays"], false, "{ceiling}");
    assert!(ceiling["ci95"][1].as_f64().unwrap() < 1.1, "{ceiling}");
    assert!(ceiling["original_ms"].as_f64().unwrap() > 0.0, "{ceiling}");
    // The root (4 floats) and the narrower node saving the most (`d`, 1 float) were raced: the
    // payload is the winner's.
    let payload = ceiling["payload"].as_u64().unwrap();
    assert!(
        payload == 4 && ceiling.get("node").is_none() || payload < 4 && ceiling["node"].is_u64(),
        "{ceiling}"
    );
    assert_eq!(
        profile["nodes"].as_array().map(Vec::len),
        Some(0),
        "{profile}"
    );
    let (code, out, err) = run(
        dir,
        &[
            "emit",
            "--profile",
            "c.profile.json",
            "--max-error",
            "0.01",
            "--out",
            "e",
            "--verify",
            "--session",
            "s.json",
            "--json",
        ],
    );
    assert_eq!(code, 0, "{err}");
    let report: serde_json::Value = serde_json::from_str(&out).unwrap_or_else(|_| panic!("{err}"));
    assert!(report["node"].is_null(), "{report}");
    assert!(
        report["reason"]
            .as_str()
            .is_some_and(|r| r.contains("caching cannot pay")),
        "{report}"
    );
    assert!(report["measured_speedup"].is_null(), "{report}");
    assert!(report["measured_speedup_ci95"].is_null(), "{report}");
    assert!(
        report["measured_original_ms"].as_f64().unwrap() > 0.0,
        "{report}"
    );
    let (code, out, err) = run(
        dir,
        &[
            "emit",
            "--profile",
            "c.profile.json",
            "--max-error",
            "0.01",
            "--out",
            "e2",
            "--verify",
            "--session",
            "s.json",
        ],
    );
    assert_eq!(code, 0, "{err}");
    assert!(
        out.contains("the original shader is kept: nothing to time"),
        "{out}"
    );
    assert!(!out.contains("1.00x [1.00, 1.00]"), "{out}");
}

/// Analyze `fixture` (a shader of the two-term fixture's inputs) over the two-term session, emit
/// with `--verify` under 0.02, and check the variant's bindings sit in group 3 from
/// `binding_base` on.
fn analyzed_and_verified_in_group_3(fixture: &str, binding_base: u64) {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    common::two_terms(dir, "unused.wgsl", "s.json");
    std::fs::copy(
        common::root()
            .join("crates/reproj-cli/tests/data")
            .join(fixture),
        dir.join("s.wgsl"),
    )
    .unwrap();
    let (code, out, err) = common::analyze_short(
        dir,
        "s.wgsl",
        &["s.json"],
        "g.profile.json",
        &["--strategy", "2pass"],
    );
    assert_eq!(code, 0, "{err}");
    assert!(out.contains("usable"), "{out}");
    let (code, out, err) = run(
        dir,
        &[
            "emit",
            "--profile",
            "g.profile.json",
            "--max-error",
            "0.02",
            "--out",
            "e",
            "--verify",
            "--session",
            "s.json",
            "--runoff",
            "1",
            "--json",
        ],
    );
    // The budget holds, or --verify says it does not (exit 4: the selection's Δn rests on timings,
    // and a loaded machine can move it to a period whose error lands just over): either way the
    // variant was drawn and measured in the shader's groups.
    assert!(code == 0 || code == 4, "{err}");
    let report: serde_json::Value = serde_json::from_str(&out).unwrap_or_else(|_| panic!("{err}"));
    assert!(report["node"].is_string(), "{report}");
    let measured = report["measured_error"].as_f64().unwrap();
    assert_eq!(code == 0, measured <= 0.02, "{report}");
    assert!(measured <= 0.03, "{report}");
    let manifest: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("e/manifest.json")).unwrap())
            .unwrap();
    assert_eq!(manifest["group"], 3, "{manifest}");
    assert_eq!(
        manifest["binding_base"].as_u64().unwrap_or(0),
        binding_base,
        "{manifest}"
    );
}

/// A shader that uses three bind groups, as engines do (view, material, mesh): the variant takes
/// the fourth and the replay's own vertex transforms a fifth, so it analyzes, emits and verifies
/// like any other (it used to be refused: "every bind group 0..4").
#[test]
fn a_shader_with_three_bind_groups_is_analyzed_and_verified() {
    analyzed_and_verified_in_group_3("three_groups.wgsl", 0);
}

/// A shader that uses all four bind groups: the variant's bindings join its group 3 past its own
/// (`binding_base` 1), so it analyzes, emits and verifies like any other.
#[test]
fn a_shader_with_four_bind_groups_shares_one_and_is_analyzed_and_verified() {
    analyzed_and_verified_in_group_3("four_groups.wgsl", 1);
}
