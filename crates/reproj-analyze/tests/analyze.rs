//! `analyze` end to end on the machine's adapter (lavapipe in CI): a short static session, so every
//! node's error is zero — the degenerate case the models must survive — then `emit` from the profile.

use std::path::PathBuf;

use reproj_analyze::{AnalyzeInput, AnalyzeOptions, Silent, analyze, verify};
use reproj_emit::{EmitOptions, emit, load_profile};
use reproj_front::{enumerate, load_file, normalize};
use reproj_models::profile::NodeStatus;
use reproj_replay::{RenderOptions, Renderer, RendererOptions, VariantInput};
use reproj_scene::Session;

/// The tests time replays (races, set-aside, the set search): one at a time, so that one test's
/// rendering does not load another's timings.
static TIMED: std::sync::Mutex<()> = std::sync::Mutex::new(());

fn timed() -> std::sync::MutexGuard<'static, ()> {
    TIMED.lock().unwrap_or_else(|e| e.into_inner())
}

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../..")
}

/// Two nodes profiled: the first raced (the larger saving) raced all three strategies, and the
/// second every one of them but those the first race pruned decisively (a strategy at least twice
/// as slow as the winner, the intervals apart: fused on lavapipe).
fn assert_raced_every_strategy_but_the_decisively_pruned(profile: &reproj_models::Profile) {
    let probes = &profile.strategy_probes;
    let mut nodes: Vec<u32> = probes.iter().map(|p| p.node).collect();
    nodes.dedup();
    assert_eq!(nodes.len(), 2, "{probes:?}");
    let of = |id: u32| probes.iter().filter(move |p| p.node == id);
    let (first, second) = if of(nodes[0]).count() >= of(nodes[1]).count() {
        (nodes[0], nodes[1])
    } else {
        (nodes[1], nodes[0])
    };
    assert_eq!(of(first).count(), 3, "{probes:?}");
    let winner = of(first).find(|p| p.kept).expect("a kept strategy");
    for lost in of(first) {
        if of(second).any(|p| p.strategy == lost.strategy) {
            continue;
        }
        let (w, l) = (
            winner.timed.speedup_ci95.unwrap(),
            lost.timed.speedup_ci95.unwrap(),
        );
        assert!(
            l[1] < w[0] && winner.timed.speedup.unwrap() >= 2.0 * lost.timed.speedup.unwrap(),
            "{} pruned without a decisive loss: {probes:?}",
            lost.strategy
        );
    }
}

#[test]
fn static_session_profiles_without_nan_and_emits() {
    let _timed = timed();
    let shader = load_file(&root().join("shaders/marble.wgsl")).unwrap();
    let norm = normalize(&shader, &Default::default()).unwrap();
    let table = enumerate(&shader, &norm);
    let sum = table.cacheable().find(|n| n.text == "s3 + n4").unwrap().id;
    let session_path = root().join("sessions/test_static.json");
    let session_bytes = std::fs::read(&session_path).unwrap();
    let session = Session::load(&session_path).unwrap();
    let renderer =
        Renderer::new(&RendererOptions::default()).expect("a Vulkan adapter (lavapipe in CI)");
    let opts = AnalyzeOptions {
        delta_n_train: vec![2, 6, 10],
        delta_n_holdout: vec![4],
        nodes: Some(vec![sum]),
        max_frames: Some(6),
        ..AnalyzeOptions::default()
    };
    let input = AnalyzeInput {
        shader: &shader,
        norm: &norm,
        table: &table,
        session_path: &session_path,
        session_bytes: &session_bytes,
        session: &session,
    };
    let profile = analyze(&input, &renderer, &opts, &Silent).unwrap();
    assert_eq!(profile.nodes.len(), 2, "the chosen node and the root");
    assert!(profile.nodes.iter().any(|n| n.root));
    // ꟻLIP and SSIM on every frame of the 6 (the default scores about 15 frames per replay),
    // fitted like the L2 error.
    assert_eq!(profile.perceptual_stride, Some(1));
    for n in &profile.nodes {
        assert!(
            n.flip_fit.is_some() && n.dssim_fit.is_some(),
            "node {}",
            n.id
        );
        for m in &n.measurements {
            let (flip, ssim) = (m.flip.unwrap(), m.ssim.unwrap());
            assert_eq!((flip.frames, ssim.frames), (6, 6), "{m:?}");
            assert!(
                (0.0..=1.0).contains(&flip.mean) && ssim.mean <= 1.0,
                "{m:?}"
            );
            assert!(m.error_worst.unwrap().value >= m.error, "{m:?}");
        }
    }
    // Every strategy was tried on each node at the longest period (but one the first node's race
    // pruned decisively), and the fastest kept.
    assert_raced_every_strategy_but_the_decisively_pruned(&profile);
    for n in &profile.nodes {
        let probes: Vec<_> = profile
            .strategy_probes
            .iter()
            .filter(|p| p.node == n.id)
            .collect();
        let kept: Vec<_> = probes.iter().filter(|p| p.kept).collect();
        assert_eq!(kept.len(), 1, "{probes:?}");
        assert_eq!(kept[0].strategy, n.strategy);
        // No strategy is faster than the kept one beyond doubt (noise never decides a race).
        let [_, kept_hi] = kept[0].timed.speedup_ci95.unwrap();
        for p in &probes {
            let [lo, hi] = p.timed.speedup_ci95.unwrap();
            assert!(
                lo <= p.timed.speedup.unwrap() && p.timed.speedup.unwrap() <= hi,
                "{p:?}"
            );
            assert!(
                p.kept || p.timed.speedup < kept[0].timed.speedup || lo <= kept_hi,
                "{p:?} beats {:?}",
                kept[0]
            );
        }
        assert_eq!(n.measurements[0].delta_n, 10, "the longest period first");
    }
    for n in &profile.nodes {
        match &n.status {
            NodeStatus::Ok => {
                // Nothing moves: reuse is exact up to filtering round-off, the error curve is flat
                // at (nearly) zero.
                assert!(n.error_fit.alpha.is_some_and(|a| a < 1e-5), "{n:?}");
                assert_eq!(n.measurements.len(), 4);
            }
            NodeStatus::SetAside { reason } => assert!(!reason.is_empty()),
        }
        assert!(n.measurements.iter().all(|m| m.error < 1e-4));
        assert!(n.measurements.iter().all(|m| m.mse.is_some()));
    }
    let json = serde_json::to_string(&profile).unwrap();
    // No NaN or infinity anywhere: serde_json writes both as `null`, so a non-finite number either
    // fails to read back (a plain f64 field) or reads back changed (an optional one, or NaN, which
    // equals nothing): the profile must read back equal to itself.
    let back: reproj_models::Profile = serde_json::from_str(&json).unwrap();
    if back != profile {
        let (a, b) = (
            serde_json::to_value(&profile).unwrap(),
            serde_json::to_value(&back).unwrap(),
        );
        panic!(
            "the profile does not read back equal (a non-finite number?): {}",
            first_difference(&a, &b, String::new())
        );
    }

    // The profile reads back and drives `emit` without a GPU.
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("marble.profile.json");
    std::fs::write(&path, &json).unwrap();
    let back = load_profile(&path).unwrap();
    assert_eq!(back.nodes.len(), profile.nodes.len());
    let (mut report, variant) = emit(
        &back,
        &path,
        &EmitOptions {
            max_error: reproj_select::Budget::new(0.01).unwrap(),
            metric: Default::default(),
            min_delta_n: 2,
            max_delta_n: 50,
            out: dir.path().join("out"),
            cache_format: Some(reproj_instance::CacheFormatChoice::Exact(
                reproj_instance::CacheFormat::Rgba32float,
            )),
            strategy: None,
            integration: Default::default(),
            shader: None,
            outputs: Default::default(),
            also: Vec::new(),
            target: None,
            period: Default::default(),
            node: None,
        },
    )
    .unwrap();
    // Either a node (zero error fits any budget) or the original, said plainly: never a panic.
    assert!(
        report.node.is_some() || report.reason.is_some(),
        "{report:?}"
    );
    assert!(dir.path().join("out/report.json").exists());

    // `emit --verify` measures the PSNR exactly as `render` does: the same number for the same
    // variant over the same (here moving) session.
    let mut moving = Session::load(root().join("sessions/marble.json")).unwrap();
    moving.resolution = [64, 64];
    moving.frames = 5;
    let out = dir.path().join("out");
    verify(
        &mut report,
        &out,
        variant.as_ref(),
        (&back, &path),
        &moving,
        &renderer,
        &reproj_bench::BenchOptions {
            stop: reproj_models::speedup::StopRule {
                min_rounds: 3,
                max_rounds: 3,
                ..Default::default()
            },
            ..Default::default()
        },
    )
    .unwrap();
    let entry = shader.fragment_entry(None).unwrap();
    let opts = RenderOptions {
        classify: false,
        raw_frames: false,
        ..RenderOptions::default()
    };
    let reference = renderer
        .render_original(&shader, entry, &moving, &opts)
        .unwrap();
    let rendered = match &variant {
        Some(v) => {
            let input = VariantInput::new(
                v.passes.iter().map(|p| p.wgsl.clone()).collect(),
                v.manifest.clone(),
                report.delta_n.unwrap(),
            );
            renderer
                .render_variant(&shader, &moving, &input, &reference, &opts)
                .unwrap()
        }
        None => reference.report.clone(),
    };
    assert_eq!(report.measured_psnr, Some(rendered.psnr), "{report:?}");
    assert_eq!(report.measured_error, Some(rendered.error));
}

/// A node's strategies race the original interleaved (`reproj-bench`), on windows of the
/// session's first `probe_frames` frames; the kept one is then replayed over the whole session, or
/// the node is set aside when its interval lies wholly below 1×.
#[test]
fn strategies_race_interleaved_then_the_kept_one_replays_the_session() {
    let _timed = timed();
    let shader = load_file(&root().join("shaders/marble.wgsl")).unwrap();
    let norm = normalize(&shader, &Default::default()).unwrap();
    let table = enumerate(&shader, &norm);
    let sum = table.cacheable().find(|n| n.text == "s3 + n4").unwrap().id;
    let session_path = root().join("sessions/marble.json");
    let session_bytes = std::fs::read(&session_path).unwrap();
    let mut session = Session::load(&session_path).unwrap();
    session.resolution = [64, 64];
    let renderer =
        Renderer::new(&RendererOptions::default()).expect("a Vulkan adapter (lavapipe in CI)");
    let opts = AnalyzeOptions {
        delta_n_train: vec![2, 6, 10],
        delta_n_holdout: vec![4],
        nodes: Some(vec![sum]),
        max_frames: Some(8),
        probe_frames: Some(4),
        ..AnalyzeOptions::default()
    };
    let input = AnalyzeInput {
        shader: &shader,
        norm: &norm,
        table: &table,
        session_path: &session_path,
        session_bytes: &session_bytes,
        session: &session,
    };
    let profile = analyze(&input, &renderer, &opts, &Silent).unwrap();
    assert_raced_every_strategy_but_the_decisively_pruned(&profile);
    for p in &profile.strategy_probes {
        assert!(p.original_ms.is_some_and(|ms| ms > 0.0), "{p:?}");
        assert!(p.timed.rounds.is_some_and(|r| r >= 8), "{p:?}");
        assert!(p.timed.speedup.is_some_and(f64::is_finite), "{p:?}");
        assert_eq!(p.error, None, "a race measures no error");
    }
    for n in &profile.nodes {
        let kept = profile
            .strategy_probes
            .iter()
            .find(|p| p.node == n.id && p.kept)
            .unwrap();
        assert_eq!(kept.strategy, n.strategy);
        if let NodeStatus::SetAside { reason } = &n.status
            && reason.contains("timed interleaved")
        {
            // Set aside by the race: only a non-root node slower beyond doubt; the profile keeps
            // its replay at the longest period and no other.
            assert!(!n.root);
            assert!(kept.timed.speedup_ci95.unwrap()[1] < 1.0, "{kept:?}");
            assert_eq!(n.measurements.len(), 1, "{n:?}");
            continue;
        }
        // The kept strategy's replay at the longest period covers the whole session (7 timed
        // frames: frame 0 is left out), like every other period's.
        let m0 = &n.measurements[0];
        assert_eq!(m0.delta_n, 10);
        for m in &n.measurements {
            assert_eq!(m.frames.len(), 7, "Δn = {}", m.delta_n);
        }
    }
}

/// Path and values of the first place two JSON values differ.
fn first_difference(a: &serde_json::Value, b: &serde_json::Value, at: String) -> String {
    use serde_json::Value as V;
    match (a, b) {
        (V::Object(x), V::Object(y)) => {
            for (k, v) in x {
                match y.get(k) {
                    Some(w) if w == v => {}
                    Some(w) => return first_difference(v, w, format!("{at}.{k}")),
                    None => return format!("{at}.{k} missing"),
                }
            }
            format!("{at}: keys differ")
        }
        (V::Array(x), V::Array(y)) if x.len() == y.len() => {
            for (i, (v, w)) in x.iter().zip(y).enumerate() {
                if v != w {
                    return first_difference(v, w, format!("{at}[{i}]"));
                }
            }
            format!("{at}: equal as JSON (a NaN?)")
        }
        _ => format!("{at}: {a} vs {b}"),
    }
}

/// The set search on a shader with two independent expensive terms (`a`, `b`: each a loop's sum
/// over the surface point, lit by a moving light): the pair is replayed at the single nodes'
/// periods, a second run with the same journal replays nothing (set replays are keyed too), and
/// `emit` picks the pair, writing one payload for both.
#[test]
fn two_independent_terms_make_a_pair_that_emit_picks() {
    let _timed = timed();
    let data = root().join("crates/reproj-cli/tests/data");
    let shader_path = data.join("two_terms.wgsl");
    let shader = load_file(&shader_path).unwrap();
    let norm = normalize(&shader, &Default::default()).unwrap();
    let table = enumerate(&shader, &norm);
    let id = |text: &str| table.cacheable().find(|n| n.text == text).unwrap().id;
    let (a, b) = (id("a"), id("b"));
    let session_path = data.join("two_terms.json");
    let session_bytes = std::fs::read(&session_path).unwrap();
    let session = Session::load(&session_path).unwrap();
    let renderer =
        Renderer::new(&RendererOptions::default()).expect("a Vulkan adapter (lavapipe in CI)");
    let dir = tempfile::tempdir().unwrap();
    let opts = AnalyzeOptions {
        delta_n_train: vec![2, 8, 16, 24],
        delta_n_holdout: vec![4],
        nodes: Some(vec![a, b]),
        // Two passes, not three: on lavapipe three passes' fixed cost leaves each term's variant
        // near 1×, where the strategy race could set one aside by noise and no pair formed.
        strategies: vec![reproj_instance::Strategy::TwoPass],
        journal: Some(reproj_analyze::JournalOptions {
            path: dir.path().join("two_terms.profile.journal"),
            fresh: false,
        }),
        ..AnalyzeOptions::default()
    };
    let input = AnalyzeInput {
        shader: &shader,
        norm: &norm,
        table: &table,
        session_path: &session_path,
        session_bytes: &session_bytes,
        session: &session,
    };
    let profile = analyze(&input, &renderer, &opts, &Silent).unwrap();
    assert_eq!(profile.sets.len(), 1, "one pair, nothing to grow it with");
    let set = &profile.sets[0];
    let mut members = set.members.clone();
    members.sort_unstable();
    assert_eq!(members, {
        let mut m = vec![a, b];
        m.sort_unstable();
        m
    });
    assert_eq!(set.status, NodeStatus::Ok, "{set:?}");
    // The longest period first, then the single nodes' plan; a prediction beside each.
    assert_eq!(set.measurements[0].delta_n, 24);
    assert!(set.measurements.len() >= 4);
    assert_eq!(set.predicted.len(), set.measurements.len());
    assert!(set.predicted.iter().all(|p| p.frame_ms.is_some()));

    // Resumed from the journal: the same measurements, no replay.
    let again = analyze(&input, &renderer, &opts, &Silent).unwrap();
    assert_eq!(again.sets[0].measurements, set.measurements);

    let path = dir.path().join("two_terms.profile.json");
    std::fs::write(&path, serde_json::to_string(&profile).unwrap()).unwrap();
    let (report, variant) = emit(
        &load_profile(&path).unwrap(),
        &path,
        &EmitOptions {
            max_error: reproj_select::Budget::new(0.01).unwrap(),
            metric: Default::default(),
            min_delta_n: 2,
            max_delta_n: 50,
            out: dir.path().join("out"),
            cache_format: Default::default(),
            strategy: None,
            integration: Default::default(),
            shader: Some(shader_path.clone()),
            outputs: Default::default(),
            also: Vec::new(),
            target: None,
            period: Default::default(),
            node: None,
        },
    )
    .unwrap();
    assert_eq!(
        report.node.as_deref(),
        Some(set.name().as_str()),
        "{report:?}"
    );
    assert_eq!(report.version, reproj_emit::EMIT_REPORT_VERSION);
    let variant = variant.unwrap();
    assert_eq!(variant.manifest.also.len(), 1);
}
