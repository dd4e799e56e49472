//! `emit` on synthetic profiles: no GPU needed.

use std::path::{Path, PathBuf};

use reproj_emit::{EmitError, EmitOptions, EmitReport, emit, load_profile};
use reproj_instance::CacheFormat;
use reproj_models::profile::{
    AnalysisTime, Machine, Measurement, NodeProfile, NodeStatus, OriginalRecord, Source,
};
use reproj_models::{
    ErrorFitOptions, FrameTiming, Metric, PROFILE_VERSION, Profile, content_hash, fit_error,
    fit_hit_rate, fit_timing,
};

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../..")
}

/// A node whose error saturates at `alpha` and whose miss/hit costs are given (ms per pixel).
fn node(id: u32, is_root: bool, text: &str, alpha: f64, hit: f64, miss: f64) -> NodeProfile {
    let lambda = 0.08;
    let train = [2u32, 10, 18, 26, 34, 42, 50];
    let samples: Vec<(f64, f64)> = train
        .iter()
        .map(|&d| (d as f64, alpha * (1.0 - (-lambda * (d as f64 - 1.0)).exp())))
        .collect();
    let frames: Vec<FrameTiming> = (0..40)
        .map(|i| {
            let hits = 20_000 + 150 * i;
            let misses = 3_000 + 97 * (i % 7);
            FrameTiming {
                hits,
                misses,
                time_ms: 1.0 + hit * hits as f64 + miss * misses as f64,
            }
        })
        .collect();
    NodeProfile {
        id,
        root: is_root,
        text: text.into(),
        line: 1,
        col: 1,
        ty: "f32".into(),
        cost: 100.0,
        overlap: 0.0,
        strategy: "3pass".into(),
        block: None,
        reconstruct: None,
        measurements: Vec::new(),
        error_fit: fit_error(&samples, &ErrorFitOptions::default()),
        flip_fit: None,
        dssim_fit: None,
        timing_fit: fit_timing(&frames),
        holdout: Vec::new(),
        status: NodeStatus::Ok,
    }
}

/// Ids of the turbulence sum and of the root in the shader's node table.
fn ids(shader: &Path) -> (u32, u32) {
    let s = reproj_front::load_file(shader).unwrap();
    let t = reproj_front::enumerate(
        &s,
        &reproj_front::normalize(&s, &Default::default()).unwrap(),
    );
    let sum = t.cacheable().find(|n| n.text == "s3 + n4").unwrap().id;
    (sum, t.root().id)
}

fn profile(shader: &Path) -> Profile {
    let source = std::fs::read(shader).unwrap();
    let (sum, root_id) = ids(shader);
    let hit_samples: Vec<(f64, f64)> = [2.0, 10.0, 50.0]
        .iter()
        .map(|&d: &f64| (d, 0.9 * (1.0 - 1.0 / d)))
        .collect();
    Profile {
        schema: "reproj.profile".into(),
        version: PROFILE_VERSION,
        shader: Source {
            path: shader.display().to_string(),
            hash: content_hash(&source),
            ir_hash: None,
        },
        entry: "fs_main".into(),
        session: Source {
            path: "sessions/marble.json".into(),
            hash: "0".into(),
            ir_hash: None,
        },
        machine: Machine {
            adapter: "synthetic".into(),
            backend: "none".into(),
            timing_method: "none".into(),
            cpu_cores: 1,
            lp_num_threads: None,
            cpu_rasterizer: false,
            driver: None,
            clock: None,
        },
        resolution: [256, 256],
        frames: 40,
        delta_n_train: vec![2, 10, 18, 26, 34, 42, 50],
        delta_n_holdout: vec![],
        perceptual_stride: None,
        unroll: 0,
        shader_input: Default::default(),
        block: 4,
        depth_epsilon: 0.01,
        reconstruct: "bilinear".into(),
        cache_format: "f32".into(),
        original: OriginalRecord {
            frame_ms: 1.0 + 25_000.0 * 0.001,
            mean_pixels: 25_000.0,
            frame_times_ms: vec![],
            nonfinite_pixels: 0,
        },
        hit_rate: fit_hit_rate(&hit_samples),
        nodes: vec![
            // The turbulence sum: accurate, good saving.
            node(sum, false, "s3 + n4", 0.02, 0.0001, 0.0009),
            // The whole pixel: lossy, the biggest saving.
            node(root_id, true, "vec4<f32>(color, 1.0)", 0.2, 0.00005, 0.0011),
        ],
        strategy_probes: Vec::new(),
        filter_probes: Vec::new(),
        block_probes: Vec::new(),
        period_probes: Vec::new(),
        timing_warnings: Vec::new(),
        sets: Vec::new(),
        time: AnalysisTime::default(),
        shard: None,
        motion: None,
        ceiling: None,
    }
}

fn opts(max_error: f64, out: &Path) -> EmitOptions {
    EmitOptions {
        max_error: reproj_select::Budget::new(max_error).unwrap(),
        metric: Metric::L2,
        min_delta_n: 2,
        max_delta_n: 50,
        out: out.to_owned(),
        cache_format: Some(reproj_instance::CacheFormatChoice::Exact(
            CacheFormat::Rgba32float,
        )),
        strategy: None,
        integration: Default::default(),
        shader: None,
        outputs: Default::default(),
        also: Vec::new(),
        target: None,
        period: Default::default(),
        node: None,
    }
}

/// A written variant replaced by the original (`emit --verify` found it slower beyond doubt): the
/// folder holds the shader unchanged and the report with the reason, and no pass or manifest.
#[test]
fn keep_original_replaces_a_written_variant() {
    let shader = root().join("shaders/marble.wgsl");
    let p = profile(&shader);
    let dir = tempfile::tempdir().unwrap();
    let pp = dir.path().join("marble.profile.json");
    let out = dir.path().join("v");
    let o = opts(0.015, &out);
    let (written, v) = emit(&p, &pp, &o).unwrap();
    assert!(v.is_some() && out.join("manifest.json").exists());
    let why = "verified slower than the original beyond doubt";
    let r = reproj_emit::keep_original(&p, &pp, &o, why, &written).unwrap();
    assert_eq!((r.node.as_deref(), r.reason.as_deref()), (None, Some(why)));
    assert_eq!(
        std::fs::read_to_string(out.join("marble.wgsl")).unwrap(),
        std::fs::read_to_string(&shader).unwrap()
    );
    for gone in [
        "manifest.json",
        "pass1_reproject.wgsl",
        "pass2_recompute.wgsl",
    ] {
        assert!(!out.join(gone).exists(), "{gone}");
    }
    let report: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("report.json")).unwrap()).unwrap();
    assert_eq!(report["reason"], why);
}

#[test]
fn budgets_pick_original_node_then_root() {
    let shader = root().join("shaders/marble.wgsl");
    let p = profile(&shader);
    let dir = tempfile::tempdir().unwrap();
    let pp = dir.path().join("marble.profile.json");

    let (r, v) = emit(&p, &pp, &opts(0.0001, &dir.path().join("tight"))).unwrap();
    assert!(
        v.is_none() && r.node.is_none() && r.reason.is_some(),
        "{r:?}"
    );
    let kept = std::fs::read_to_string(dir.path().join("tight/marble.wgsl")).unwrap();
    assert_eq!(
        kept,
        std::fs::read_to_string(&shader).unwrap(),
        "the original is written unchanged"
    );

    let (r, v) = emit(&p, &pp, &opts(0.015, &dir.path().join("moderate"))).unwrap();
    assert_eq!(r.node, Some(ids(&shader).0.to_string()), "{r:?}");
    assert!(v.is_some());
    assert!(r.predicted_error.unwrap() <= 0.015);
    assert!(r.predicted_speedup.unwrap() > 1.0);
    for f in [
        "pass1_reproject.wgsl",
        "pass2_recompute.wgsl",
        "pass3_shade.wgsl",
        "manifest.json",
        "report.json",
    ] {
        assert!(dir.path().join("moderate").join(f).exists(), "{f}");
    }
    let written: serde_json::Value = serde_json::from_str(
        &std::fs::read_to_string(dir.path().join("moderate/report.json")).unwrap(),
    )
    .unwrap();
    assert_eq!(written["schema"], reproj_emit::EMIT_REPORT_SCHEMA);
    assert_eq!(written["version"], reproj_emit::EMIT_REPORT_VERSION);

    let (r, _) = emit(&p, &pp, &opts(0.5, &dir.path().join("loose"))).unwrap();
    assert_eq!(r.node.as_deref(), Some("root"), "{r:?}");
}

/// The predicted PSNR is the PSNR of the measured MSE interpolated at the chosen Δn (the same
/// formula `render` uses), not derived from the L2 error; none from a profile without MSEs.
#[test]
fn predicted_psnr_comes_from_the_measured_mse() {
    let shader = root().join("shaders/marble.wgsl");
    let mut p = profile(&shader);
    let dir = tempfile::tempdir().unwrap();
    let pp = dir.path().join("marble.profile.json");
    let (r, _) = emit(&p, &pp, &opts(0.015, &dir.path().join("old"))).unwrap();
    assert!(r.node.is_some() && r.predicted_psnr.is_none(), "{r:?}");

    // MSE linear in Δn, measured at the training periods only: interpolation is exact.
    for n in &mut p.nodes {
        n.measurements = p
            .delta_n_train
            .iter()
            .map(|&d| Measurement {
                delta_n: d,
                error: 0.0,
                error_worst: None,
                flip: None,
                ssim: None,
                mse: Some(1e-5 * f64::from(d)),
                psnr: None,
                hit_rate: 0.0,
                frame_ms: 1.0,
                frames: Vec::new(),
                frame_errors: Vec::new(),
            })
            .collect();
    }
    let (r, _) = emit(&p, &pp, &opts(0.015, &dir.path().join("new"))).unwrap();
    let dn = f64::from(r.delta_n.unwrap());
    let expect = reproj_metrics::psnr(1e-5 * dn);
    assert!((r.predicted_psnr.unwrap() - expect).abs() < 1e-9, "{r:?}");
}

/// The error model `alpha (1 − e^(−0.08 (Δn − 1)))` fitted at the training periods.
fn saturating_fit(alpha: f64) -> reproj_models::ErrorFit {
    let samples: Vec<(f64, f64)> = [2u32, 10, 18, 26, 34, 42, 50]
        .iter()
        .map(|&d| (d as f64, alpha * (1.0 - (-0.08 * (d as f64 - 1.0)).exp())))
        .collect();
    fit_error(&samples, &ErrorFitOptions::default())
}

#[test]
fn metric_flip_bounds_the_flip_model() {
    let shader = root().join("shaders/marble.wgsl");
    let mut p = profile(&shader);
    let dir = tempfile::tempdir().unwrap();
    let pp = dir.path().join("marble.profile.json");
    let flip = |budget, out: &str| EmitOptions {
        metric: Metric::Flip,
        ..opts(budget, &dir.path().join(out))
    };
    // A profile without ꟻLIP (before version 4) cannot bound it: re-run analyze.
    let e = emit(&p, &pp, &flip(0.05, "old")).unwrap_err().to_string();
    assert!(
        e.contains("no flip measurements") && e.contains("re-run `reproj analyze`"),
        "{e}"
    );
    assert!(!dir.path().join("old").exists());

    // ꟻLIP sees more than L2 here: the same budget allows a shorter period.
    for n in &mut p.nodes {
        let l2_alpha = n.error_fit.alpha.unwrap();
        n.flip_fit = Some(saturating_fit(4.0 * l2_alpha));
    }
    let (l2, _) = emit(&p, &pp, &opts(0.012, &dir.path().join("l2"))).unwrap();
    let (fl, _) = emit(&p, &pp, &flip(0.012, "flip")).unwrap();
    assert_eq!((l2.metric, fl.metric), (Metric::L2, Metric::Flip));
    let (dl, df) = (l2.delta_n.unwrap(), fl.delta_n.unwrap());
    assert!(df < dl || fl.node != l2.node, "l2 {l2:?}\nflip {fl:?}");
    let node = p
        .nodes
        .iter()
        .find(|n| {
            Some(n.id.to_string()) == fl.node || (n.root && fl.node.as_deref() == Some("root"))
        })
        .unwrap();
    let predicted = node
        .flip_fit
        .as_ref()
        .unwrap()
        .predict(f64::from(df))
        .unwrap();
    assert_eq!(fl.predicted_error, Some(predicted));
    assert!(predicted <= 0.012);
    let written: EmitReport =
        serde_json::from_slice(&std::fs::read(dir.path().join("flip/report.json")).unwrap())
            .unwrap();
    assert_eq!(written.metric, Metric::Flip);
}

#[test]
fn emit_is_deterministic() {
    let shader = root().join("shaders/marble.wgsl");
    let p = profile(&shader);
    let dir = tempfile::tempdir().unwrap();
    let pp = dir.path().join("marble.profile.json");
    let (a, _) = emit(&p, &pp, &opts(0.015, &dir.path().join("a"))).unwrap();
    let (b, _) = emit(&p, &pp, &opts(0.015, &dir.path().join("b"))).unwrap();
    assert_eq!(a.delta_n, b.delta_n);
    for f in ["pass2_recompute.wgsl", "pass3_shade.wgsl", "manifest.json"] {
        assert_eq!(
            std::fs::read(dir.path().join("a").join(f)).unwrap(),
            std::fs::read(dir.path().join("b").join(f)).unwrap()
        );
    }
}

#[test]
fn stale_shader_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    let shader = dir.path().join("marble.wgsl");
    std::fs::copy(root().join("shaders/marble.wgsl"), &shader).unwrap();
    let p = profile(&shader);
    let mut text = std::fs::read_to_string(&shader).unwrap();
    text.push_str("\n// edited\n");
    std::fs::write(&shader, text).unwrap();
    let e = emit(
        &p,
        &dir.path().join("x.profile.json"),
        &opts(0.015, &dir.path().join("out")),
    )
    .unwrap_err();
    assert!(matches!(e, EmitError::Stale { .. }), "{e}");
}

#[test]
fn bad_profile_names_the_field() {
    let dir = tempfile::tempdir().unwrap();
    let shader = root().join("shaders/marble.wgsl");
    let mut v = serde_json::to_value(profile(&shader)).unwrap();
    v["original"]["frame_ms"] = serde_json::json!("fast");
    let path = dir.path().join("bad.profile.json");
    std::fs::write(&path, serde_json::to_vec(&v).unwrap()).unwrap();
    let e = load_profile(&path).unwrap_err().to_string();
    assert!(e.contains("original.frame_ms"), "{e}");
}

/// The runoff's contenders (`emit --verify`): the choice and every node whose own best choice
/// under the budget is predicted too close to tell apart — each with the variant `emit --node`
/// would write — and none where the choice stands alone, `--runoff 1` or `--node` is given.
#[test]
fn the_runoff_races_the_nodes_predicted_too_close_to_tell_apart() {
    let shader = root().join("shaders/marble.wgsl");
    let (sum, _) = ids(&shader);
    let mut p = profile(&shader);
    // The sum, nearly as fast as the root at its own best period: 5 % apart in prediction.
    p.nodes[0] = node(sum, false, "s3 + n4", 0.02, 0.00006, 0.0011);
    let dir = tempfile::tempdir().unwrap();
    let pp = dir.path().join("marble.profile.json");
    let o = opts(0.5, &dir.path().join("loose"));
    let (r, _) = emit(&p, &pp, &o).unwrap();
    assert_eq!(r.node.as_deref(), Some("root"), "{r:?}");
    let c = reproj_emit::contenders(&p, &pp, &o, &r, 3).unwrap();
    let names: Vec<&str> = c.iter().map(|c| c.node.as_str()).collect();
    assert_eq!(names, ["root", &sum.to_string()], "fastest predicted first");
    assert!(c[0].chosen_by_prediction && !c[1].chosen_by_prediction);
    assert!(c[1].selection.predicted_speedup >= 0.9 * r.predicted_speedup.unwrap());
    for k in &c {
        assert_eq!(k.variant.manifest.params.delta_n, k.selection.delta_n);
        assert!(k.selection.predicted_error <= 0.5);
    }
    // The sum's contender is what `emit --node` writes for it.
    let forced = EmitOptions {
        node: Some(reproj_emit::NodeChoice::Id(sum)),
        ..opts(0.5, &dir.path().join("forced"))
    };
    let (f, fv) = emit(&p, &pp, &forced).unwrap();
    assert_eq!(f.delta_n, Some(c[1].selection.delta_n));
    let wgsl = |v: &reproj_instance::Variant| -> Vec<String> {
        v.passes.iter().map(|p| p.wgsl.clone()).collect()
    };
    assert_eq!(wgsl(&fv.unwrap()), wgsl(&c[1].variant));

    // No runoff: one contender allowed, a forced node, or a node far slower than the choice.
    assert!(
        reproj_emit::contenders(&p, &pp, &o, &r, 1)
            .unwrap()
            .is_empty()
    );
    assert!(
        reproj_emit::contenders(&p, &pp, &forced, &f, 3)
            .unwrap()
            .is_empty()
    );
    p.nodes[0] = node(sum, false, "s3 + n4", 0.02, 0.0002, 0.0012);
    let (r, _) = emit(&p, &pp, &o).unwrap();
    assert_eq!(r.node.as_deref(), Some("root"));
    assert!(
        reproj_emit::contenders(&p, &pp, &o, &r, 3)
            .unwrap()
            .is_empty()
    );
}
