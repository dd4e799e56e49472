//! The comparison on lavapipe over a tiny session: greedy simplification removes the node that
//! costs the least error per saved time first, resizing searches a scale, every number is finite.

use std::path::PathBuf;

use reproj_analyze::Silent;
use reproj_compare::{CompareInput, CompareOptions, compare, simplify::SimplifyOptions};
use reproj_front::{LoadOptions, load};
use reproj_replay::{Renderer, RendererOptions};
use reproj_scene::Session;

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../..")
}

#[test]
fn simplification_removes_the_least_error_node_first() {
    let loaded = load(
        &root().join("crates/reproj-compare/tests/data/flat_and_stripes.wgsl"),
        None,
        &LoadOptions::default(),
    )
    .unwrap();
    let session =
        Session::load(root().join("crates/reproj-replay/tests/data/tiny_moving.json")).unwrap();
    let renderer = Renderer::new(&RendererOptions::default()).unwrap();
    let input = CompareInput {
        loaded: &loaded,
        entry: None,
        session: &session,
        profile: None,
    };
    let opts = CompareOptions {
        // Out of reach: the search takes its two steps.
        target: reproj_compare::Target::Speedup(1000.0),
        max_frames: Some(4),
        simplify: SimplifyOptions {
            candidates: 10,
            max_steps: 2,
        },
        perceptual_stride: 2,
        ..Default::default()
    };
    let c = compare(&renderer, &input, &opts, &Silent).unwrap();
    let steps = &c.report.simplify.steps;
    assert_eq!(steps.len(), 2, "{steps:#?}");
    let first = &steps[0];
    // A uniform-only term: the same value everywhere, so no error for its saving.
    assert!(first.text.contains("g * 1.3"), "{first:#?}");
    for varying in ["world_pos", "uv", "stripes", "tex"] {
        assert!(!first.text.contains(varying), "{first:#?}");
    }
    assert!(first.error < 1e-6, "{first:#?}");
    // It was chosen over candidates that do cost error.
    assert!(first.rejected.iter().any(|&(_, e)| e > 1e-3), "{first:#?}");
    // Its subtree is gone from the candidates of the next step.
    assert_ne!(steps[1].node, first.node);
    assert!(steps[1].error >= first.error);

    let methods: Vec<&str> = c.report.methods.iter().map(|m| m.method.as_str()).collect();
    assert_eq!(methods, ["resize", "easu", "temporal", "simplify"]);
    let floor = c
        .report
        .original_vs_supersampled
        .expect("16 samples by default");
    assert!(floor.psnr.is_finite() && floor.flip.is_some_and(f64::is_finite));
    for m in &c.report.methods {
        let ss = m.scores.supersampled.unwrap_or_else(|| panic!("{m:?}"));
        assert!(
            ss.psnr.is_finite() && ss.flip.is_some_and(f64::is_finite),
            "{m:?}"
        );
        assert!(m.speedup.is_finite() && m.speedup > 0.0, "{m:?}");
        assert!(
            m.scores.error.is_finite() && m.scores.psnr.is_finite(),
            "{m:?}"
        );
        assert!(m.scores.flip.is_some_and(f64::is_finite), "{m:?}");
        assert!(!m.reached_target);
    }
    let resize = &c.report.resize;
    assert!(!resize.tries.is_empty() && resize.chosen < resize.tries.len());
    // The searches steer on interleaved timings: every try and step has its interval, and the
    // speedup lies in it.
    for (s, ci) in resize
        .tries
        .iter()
        .map(|t| (t.speedup, t.speedup_ci95))
        .chain(steps.iter().map(|t| (t.speedup, t.speedup_ci95)))
    {
        let [lo, hi] = ci.unwrap_or_else(|| panic!("no interval: {resize:?} {steps:?}"));
        assert!(lo <= s && s <= hi && s > 0.0, "{s} [{lo}, {hi}]");
    }
    // Resized frames lose detail: some error.
    assert!(c.report.methods[0].scores.error > 0.0);
    assert_eq!(c.crop_frames.len(), 5);
    let temporal = c.report.temporal.as_ref().expect("compared by default");
    assert!(!temporal.tries.is_empty() && temporal.chosen < temporal.tries.len());
}

/// Where the final run leaves reproj against resizing undecided (more than `equal_time` apart,
/// the faster one with the larger error), reproj moves along its node's curve to resizing's speed
/// in that run, and every method is timed again where that is another period. With no margin at
/// all any gap counts: where a rematch is recorded, its figures are consistent and, where it
/// moved, the table's reproj row is the new period, timed and scored; with a margin wider than any
/// gap nothing is recorded. (Which period `reproj::along` takes is tested on a fixed profile.)
#[test]
fn reproj_moves_to_resizings_speed_where_the_final_run_puts_them_apart() {
    use reproj_analyze::{AnalyzeInput, AnalyzeOptions, analyze};
    let loaded = load(
        &root().join("shaders/marble.wgsl"),
        None,
        &LoadOptions::default(),
    )
    .unwrap();
    let session_path = root().join("sessions/marble.json");
    let session_bytes = std::fs::read(&session_path).unwrap();
    let mut session = Session::load(&session_path).unwrap();
    session.resolution = [64, 64];
    let renderer = Renderer::new(&RendererOptions::default()).unwrap();
    let sum = loaded
        .table
        .cacheable()
        .find(|n| n.text == "s3 + n4")
        .unwrap()
        .id;
    let profile = analyze(
        &AnalyzeInput {
            shader: &loaded.shader,
            norm: &loaded.norm,
            table: &loaded.table,
            session_path: &session_path,
            session_bytes: &session_bytes,
            session: &session,
        },
        &renderer,
        &AnalyzeOptions {
            delta_n_train: vec![2, 6, 10],
            delta_n_holdout: vec![4],
            nodes: Some(vec![sum]),
            max_frames: Some(8),
            probe_frames: Some(4),
            ..AnalyzeOptions::default()
        },
        &Silent,
    )
    .unwrap();
    // Not written: it names the profile in messages.
    let profile_path = root().join("marble.profile.json");
    let input = CompareInput {
        loaded: &loaded,
        entry: None,
        session: &session,
        profile: Some((&profile, &profile_path)),
    };
    let at = |equal_time: f64| CompareOptions {
        target: reproj_compare::Target::Speedup(1.5),
        max_frames: Some(8),
        resize: reproj_compare::resize::ResizeOptions {
            tries: 2,
            ..Default::default()
        },
        simplify: SimplifyOptions {
            candidates: 2,
            max_steps: 1,
        },
        reproj_tries: 2,
        equal_time,
        perceptual_stride: 4,
        // What this test is about does not need them.
        temporal: false,
        supersample: 0,
        ..Default::default()
    };
    let c = compare(&renderer, &input, &at(0.0), &Silent).unwrap();
    let r = c.report.reproj.as_ref().unwrap();
    assert!((1..=2).contains(&r.tries.len()), "{r:?}");
    if let Some(m) = r.rematch.as_ref() {
        assert!(
            m.to_speedup > 0.0 && m.from_speedup > 0.0 && m.asked > 0.0,
            "{m:?}"
        );
        // The first steering kept the try closest to the target; moved, another period of the
        // same node is reported.
        let miss = |s: f64| (s / 1.5).ln().abs();
        let kept = r
            .tries
            .iter()
            .min_by(|a, b| miss(a.speedup).total_cmp(&miss(b.speedup)))
            .unwrap();
        assert_eq!(kept.node, r.node, "{r:?}");
        assert_eq!(m.moved, kept.delta_n != r.delta_n, "{r:?}");
    }
    let row = c
        .report
        .methods
        .iter()
        .find(|x| x.method == "reproj")
        .unwrap();
    assert!(
        row.setting.contains(&format!("Δn = {}", r.delta_n)),
        "{row:?} {r:?}"
    );
    let [lo, hi] = row.speedup_ci95.expect("timed interleaved");
    assert!(
        lo <= row.speedup && row.speedup <= hi && lo > 0.0,
        "{row:?}"
    );
    assert!(row.scores.error.is_finite(), "{row:?}");
    let c = compare(&renderer, &input, &at(10.0), &Silent).unwrap();
    assert!(c.report.reproj.unwrap().rematch.is_none());
}

/// On a session without motion the temporal upsampler still runs (its best case) and the report
/// says so; nothing is split into still and moving frames. At scale ½ it beats bilinear resizing
/// against the supersampled reference (its history fills in what a still frame's jitter shows).
#[test]
fn a_still_session_gets_a_note_and_the_upsampler_its_best_case() {
    let loaded = load(
        &root().join("shaders/marble.wgsl"),
        None,
        &LoadOptions::default(),
    )
    .unwrap();
    let mut session = Session::load(root().join("sessions/test_static.json")).unwrap();
    session.frames = 16;
    let renderer = Renderer::new(&RendererOptions::default()).unwrap();
    let input = CompareInput {
        loaded: &loaded,
        entry: None,
        session: &session,
        profile: None,
    };
    let opts = CompareOptions {
        target: reproj_compare::Target::Speedup(3.0),
        simplify: SimplifyOptions {
            candidates: 2,
            max_steps: 1,
        },
        supersample: 8,
        perceptual_stride: 4,
        ..Default::default()
    };
    let c = compare(&renderer, &input, &opts, &Silent).unwrap();
    let r = &c.report;
    assert_eq!(r.moving_frames, 0);
    assert!(
        r.notes.iter().any(|n| n.contains("no motion")),
        "{:?}",
        r.notes
    );
    let by = |name: &str| r.methods.iter().find(|m| m.method == name).unwrap();
    for m in &r.methods {
        assert!(m.scores.split.is_none(), "{m:?}");
    }
    let (t, z) = (by("temporal"), by("resize"));
    let ss = |m: &reproj_compare::MethodResult| m.scores.supersampled.unwrap().psnr;
    eprintln!(
        "still marble at 3×: temporal {:.2}× {:.2} dB, resize {:.2}× {:.2} dB (vs 8 spp)",
        t.speedup,
        ss(t),
        z.speedup,
        ss(z)
    );
    let detail = |d: &reproj_compare::resize::ResizeDetail| d.tries[d.chosen].resolution;
    if detail(r.temporal.as_ref().unwrap()) == detail(&r.resize) {
        assert!(ss(t) > ss(z), "{t:?} {z:?}");
    }
}
