//! Charts of synthetic profiles. Set `REPROJ_CHARTS_KEEP=DIR` to keep the files for a look.

use std::collections::BTreeSet;
use std::path::Path;

use reproj_models::profile::{
    AnalysisTime, HoldoutCheck, Machine, Measurement, NodeProfile, NodeStatus, OriginalRecord,
    Source,
};
use reproj_models::{
    ErrorFitOptions, FrameTiming, HitRateFit, PROFILE_VERSION, Profile, fit_error, fit_hit_rate,
    fit_timing_with_holdout, predicted_frame_ms,
};
use reproj_select::{SelectOptions, Selection, select_with_sets};

use super::data::HIGHLIGHTED;
use super::*;

const TRAIN: [u32; 7] = [2, 10, 18, 26, 34, 42, 50];
const HOLDOUT: [u32; 2] = [6, 30];
const PIXELS: f64 = 200_000.0;
const MU: f64 = 0.88;

/// Deterministic noise in [-1, 1].
fn noise(seed: u64) -> f64 {
    let mut x = seed
        .wrapping_mul(0x9e37_79b9_7f4a_7c15)
        .wrapping_add(0x632b_e59b_d9b4_e019);
    x ^= x >> 29;
    x = x.wrapping_mul(0xbf58_476d_1ce4_e5b9);
    x ^= x >> 32;
    (x % 20_001) as f64 / 10_000.0 - 1.0
}

/// A node to simulate: error α(1 − e^(−λ(Δn − 1))), hit and miss cost per pixel (ms).
struct Sim {
    id: u32,
    text: &'static str,
    alpha: f64,
    lambda: f64,
    hit_ms: f64,
    miss_ms: f64,
    cost: f64,
    /// Error falling with Δn: the fit fails and the node is set aside.
    broken: bool,
}

fn measure(sim: &Sim, dn: u32) -> Measurement {
    let seed = u64::from(sim.id) * 1000 + u64::from(dn);
    let gamma = (MU * (1.0 - 1.0 / f64::from(dn)) + 0.015 * noise(seed)).clamp(0.0, 1.0);
    let mut error = sim.alpha * (1.0 - (-sim.lambda * (f64::from(dn) - 1.0)).exp());
    if sim.broken {
        error = sim.alpha * 30.0 / f64::from(dn);
    }
    error *= 1.0 + 0.04 * noise(seed + 7);
    let frames: Vec<FrameTiming> = (0..24)
        .map(|f| {
            let s = seed * 100 + f;
            let pixels = PIXELS * (1.0 + 0.2 * noise(s));
            let g = (gamma + 0.05 * noise(s + 1)).clamp(0.0, 1.0);
            let hits = (pixels * g) as u64;
            let misses = pixels as u64 - hits;
            let t = 0.8 + hits as f64 * sim.hit_ms + misses as f64 * sim.miss_ms;
            FrameTiming {
                hits,
                misses,
                time_ms: t * (1.0 + 0.01 * noise(s + 2)),
            }
        })
        .collect();
    let frame_ms = frames.iter().map(|f| f.time_ms).sum::<f64>() / frames.len() as f64;
    // A simulated MSE over the covered pixels, as if the per-pixel error were uniform.
    let mse = error * error / 3.0;
    Measurement {
        delta_n: dn,
        error,
        mse: Some(mse),
        psnr: (mse > 0.0).then(|| 10.0 * (1.0 / mse).log10()),
        hit_rate: gamma,
        frame_ms,
        frames,
        frame_errors: Vec::new(),
        error_worst: None,
        flip: None,
        ssim: None,
    }
}

fn profile_of(sims: &[Sim], original_ms: f64) -> Profile {
    let raw: Vec<Vec<Measurement>> = sims
        .iter()
        .map(|s| {
            TRAIN
                .iter()
                .chain(&HOLDOUT)
                .map(|&dn| measure(s, dn))
                .collect()
        })
        .collect();
    let is_train = |m: &Measurement| TRAIN.contains(&m.delta_n);
    let hit_samples: Vec<(f64, f64)> = raw
        .iter()
        .flatten()
        .filter(|m| is_train(m))
        .map(|m| (f64::from(m.delta_n), m.hit_rate))
        .collect();
    let hit_rate = fit_hit_rate(&hit_samples);
    let nodes = sims
        .iter()
        .zip(raw)
        .map(|(s, ms)| {
            let train: Vec<&Measurement> = ms.iter().filter(|m| is_train(m)).collect();
            let held: Vec<&Measurement> = ms.iter().filter(|m| !is_train(m)).collect();
            let error_fit = fit_error(
                &train
                    .iter()
                    .map(|m| (f64::from(m.delta_n), m.error))
                    .collect::<Vec<_>>(),
                &ErrorFitOptions::default(),
            );
            let frames = |v: &[&Measurement]| -> Vec<FrameTiming> {
                v.iter().flat_map(|m| m.frames.iter().copied()).collect()
            };
            let timing_fit = fit_timing_with_holdout(&frames(&train), &frames(&held));
            let holdout = held
                .iter()
                .map(|m| HoldoutCheck {
                    delta_n: m.delta_n,
                    measured_error: m.error,
                    predicted_error: error_fit.predict(f64::from(m.delta_n)),
                    measured_ms: m.frame_ms,
                    predicted_ms: predicted_frame_ms(
                        &timing_fit,
                        &hit_rate,
                        f64::from(m.delta_n),
                        PIXELS,
                    ),
                    measured_flip: None,
                    predicted_flip: None,
                })
                .collect();
            let status = if error_fit.is_ok() && timing_fit.is_usable() {
                NodeStatus::Ok
            } else {
                NodeStatus::SetAside {
                    reason: "error fit failed".to_string(),
                }
            };
            NodeProfile {
                id: s.id,
                root: s.id == 0,
                text: s.text.to_string(),
                line: 10 + s.id,
                col: 5,
                ty: "vec3<f32>".to_string(),
                cost: s.cost,
                overlap: 0.0,
                strategy: "3pass".to_string(),
                block: None,
                reconstruct: None,
                measurements: ms,
                error_fit,
                timing_fit,
                holdout,
                status,
                flip_fit: None,
                dssim_fit: None,
            }
        })
        .collect();
    Profile {
        perceptual_stride: None,
        unroll: 0,
        shader_input: Default::default(),
        schema: "reproj.profile".to_string(),
        version: PROFILE_VERSION,
        shader: Source {
            path: "shaders/marble.wgsl".to_string(),
            hash: "0".repeat(16),
            ir_hash: None,
        },
        entry: "fs_main".to_string(),
        session: Source {
            path: "sessions/marble.json".to_string(),
            hash: "0".repeat(16),
            ir_hash: None,
        },
        machine: Machine {
            adapter: "llvmpipe (LLVM 19.1.7, 256 bits)".to_string(),
            backend: "vulkan".to_string(),
            timing_method: "timestamp-queries".to_string(),
            cpu_cores: 2,
            lp_num_threads: None,
            cpu_rasterizer: false,
            driver: None,
            clock: None,
        },
        resolution: [640, 480],
        frames: 150,
        delta_n_train: TRAIN.to_vec(),
        delta_n_holdout: HOLDOUT.to_vec(),
        block: 2,
        depth_epsilon: 1e-3,
        reconstruct: "bilinear".into(),
        cache_format: "f32".into(),
        original: OriginalRecord {
            frame_ms: original_ms,
            mean_pixels: PIXELS,
            frame_times_ms: vec![original_ms; 10],
            nonfinite_pixels: 0,
        },
        hit_rate,
        nodes,
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

/// Marble-like: noise octaves (expensive, low error), the noise sum, a view-dependent term, the
/// final color, one node whose error falls with Δn (set aside).
fn marble() -> Vec<Sim> {
    let n = |id, text, alpha, lambda, hit_ms, miss_ms, cost| Sim {
        id,
        text,
        alpha,
        lambda,
        hit_ms,
        miss_ms,
        cost,
        broken: false,
    };
    let mut v = vec![
        n(3, "noise(p * 1.0)", 0.002, 0.08, 4.0e-5, 7.0e-5, 40.0),
        n(
            7,
            "noise(p * 1.0) + 0.5 * noise(p * 2.0) + 0.25 * noise(p * 4.0)",
            0.006,
            0.06,
            2.8e-5,
            7.6e-5,
            120.0,
        ),
        n(
            12,
            "marble_sum(p) /* five octaves of gradient noise */",
            0.012,
            0.05,
            1.7e-5,
            8.2e-5,
            200.0,
        ),
        n(
            15,
            "albedo * max(dot(n, l), 0.0)",
            0.05,
            0.3,
            1.6e-5,
            8.4e-5,
            210.0,
        ),
        n(0, "final color", 0.09, 0.4, 1.0e-5, 8.8e-5, 260.0),
    ];
    v.push(Sim {
        broken: true,
        ..n(
            21,
            "pow(max(dot(h, n), 0.0), 32.0)",
            0.003,
            0.1,
            6.0e-5,
            6.8e-5,
            12.0,
        )
    });
    v
}

fn keep(dir: &Path) {
    if let Some(keep) = std::env::var_os("REPROJ_CHARTS_KEEP") {
        let keep = Path::new(&keep);
        std::fs::create_dir_all(keep).unwrap();
        for e in std::fs::read_dir(dir).unwrap() {
            let e = e.unwrap();
            std::fs::copy(e.path(), keep.join(e.file_name())).unwrap();
        }
    }
}

fn check_files(paths: &ChartPaths, dir: &Path, stem: &str) {
    let names = ["tradeoff", "hitrate", "models"];
    assert_eq!(paths.svg.len(), 3);
    assert_eq!(paths.png.len(), 3);
    for (i, name) in names.iter().enumerate() {
        assert_eq!(paths.svg[i], dir.join(format!("{stem}.{name}.svg")));
        assert_eq!(paths.png[i], dir.join(format!("{stem}.{name}.png")));
        let svg = std::fs::read_to_string(&paths.svg[i]).unwrap();
        assert!(
            svg.starts_with("<svg") && svg.contains("<text"),
            "{name}.svg"
        );
        let png = std::fs::read(&paths.png[i]).unwrap();
        assert!(
            png.starts_with(b"\x89PNG\r\n\x1a\n") && png.len() > 1000,
            "{name}.png"
        );
        let img = image::load_from_memory(&png).unwrap();
        let (w, h) = if *name == "models" {
            (img.width(), img.height())
        } else {
            SIZE
        };
        assert_eq!((img.width(), img.height()), (w, h));
    }
    // No temporary file left behind.
    for e in std::fs::read_dir(dir).unwrap() {
        let name = e.unwrap().file_name().to_string_lossy().into_owned();
        assert!(!name.starts_with('.'), "left {name}");
    }
}

fn svg(paths: &ChartPaths, i: usize) -> String {
    std::fs::read_to_string(&paths.svg[i]).unwrap()
}

#[test]
fn synthetic_profile_charts() {
    let profile = profile_of(&marble(), 22.0);
    // The synthetic data are what the test means: fits Ok except the broken node.
    assert!(profile.hit_rate.is_usable());
    let ok = profile
        .nodes
        .iter()
        .filter(|n| n.status == NodeStatus::Ok)
        .count();
    assert_eq!(
        ok,
        5,
        "{:#?}",
        profile
            .nodes
            .iter()
            .map(|n| &n.error_fit.status)
            .collect::<Vec<_>>()
    );

    let dir = tempfile::tempdir().unwrap();
    let budgets = vec![0.002, 0.01, 0.03, 0.1];
    let opts = ChartOptions {
        budgets: budgets.clone(),
    };
    let paths = write_charts(&profile, dir.path(), "marble", &opts).unwrap();
    keep(dir.path());
    check_files(&paths, dir.path(), "marble");
    if paths.font.is_none() {
        assert!(paths.warnings.iter().any(|w| w.contains("no font")));
    }

    let tradeoff = svg(&paths, 0);
    for n in &profile.nodes {
        let max = if n.status == NodeStatus::Ok { 38 } else { 26 };
        let label = node_label(n, max);
        let escaped = label
            .replace('&', "&amp;")
            .replace('<', "&lt;")
            .replace('>', "&gt;");
        assert!(tradeoff.contains(&escaped), "trade-off lacks {label:?}");
    }
    assert!(tradeoff.contains("original"));
    assert!(tradeoff.contains("predicted Pareto frontier"));
    assert!(tradeoff.contains("(set aside)"));
    assert!(tradeoff.contains("mean frame time (ms)"));

    let hit = svg(&paths, 1);
    let mu = profile.hit_rate.mu.unwrap();
    assert!(
        hit.contains(&format!("µ = {mu:.3}")),
        "hit-rate title lacks µ"
    );
    assert!(hit.contains("R² = "));
    assert!(hit.contains("held-out"));

    let models = svg(&paths, 2);
    assert!(models.contains("frame time (ms)") && models.contains("error (L2 RGB)"));
    assert!(models.contains("held-out"));
    // Every usable node, and each node a selection caches.
    assert_eq!(models.matches("frame time (ms)").count(), ok);
    let mut chosen = BTreeSet::new();
    for &b in &budgets {
        let (nodes, sets) = records(&profile);
        if let Selection::Node(c) = select_with_sets(
            &nodes,
            &sets,
            &profile.hit_rate,
            profile.original.frame_ms,
            &SelectOptions::new(reproj_select::Budget::new(b).unwrap()),
        ) {
            // The trade-off chart marks it, labelled with the budget (a set by its members).
            let marks = super::tradeoff(&profile, &budgets).marks;
            let what = if c.members.is_empty() {
                chosen.insert(c.node_id);
                format!("node {}", c.node_id)
            } else {
                let ids: Vec<String> = c.members.iter().map(u32::to_string).collect();
                format!("set {}", ids.join("+"))
            };
            assert!(
                marks.iter().any(|m| m.2.contains(&format!("{b}"))
                    && (m.2.contains(&format!("{what},")) || m.2.contains(&format!("{what} ")))),
                "{b}: {marks:?}"
            );
        }
    }
    assert!(!chosen.is_empty(), "no budget selects a node");
    for id in chosen {
        let n = profile.nodes.iter().find(|n| n.id == id).unwrap();
        let label = node_label(n, 30)
            .replace('&', "&amp;")
            .replace('<', "&lt;")
            .replace('>', "&gt;");
        assert!(models.contains(&label), "models lack the chosen node {id}");
    }
    assert!(tradeoff.contains("selection at a budget"));
    assert_eq!(significant(0.012716541677974084), "0.0127");
    assert_eq!(significant(0.002), "0.002");
    assert_eq!(significant(0.1), "0.1");
}

#[test]
fn many_nodes_highlight_the_best() {
    // 20 nodes: only 8 get a legend entry, the rest are counted as thin grey.
    let texts: Vec<&'static str> = (0..20)
        .map(|i| &*Box::leak(format!("octave_{i} * weight").into_boxed_str()))
        .collect();
    let sims: Vec<Sim> = (0..20u32)
        .map(|i| Sim {
            id: i + 1,
            text: texts[i as usize],
            alpha: 0.001 * f64::from(i + 1),
            lambda: 0.03 + 0.02 * f64::from(i % 5),
            hit_ms: 1.5e-5 + 2.5e-6 * f64::from(i % 7),
            miss_ms: 8.0e-5,
            cost: f64::from(i * 10),
            broken: false,
        })
        .collect();
    let profile = profile_of(&sims, 17.0);
    let dir = tempfile::tempdir().unwrap();
    let paths = write_charts(&profile, dir.path(), "many", &ChartOptions::default()).unwrap();
    keep(dir.path());
    check_files(&paths, dir.path(), "many");
    let tsvg = svg(&paths, 0);
    assert!(tsvg.contains("12 other usable nodes (grey)"));
    let t = tradeoff(&profile, &[]);
    assert_eq!(
        t.paths.iter().filter(|p| p.color.is_some()).count(),
        HIGHLIGHTED
    );
    // Every node on the predicted frontier is highlighted (there are at most 8 here).
    let colored: BTreeSet<String> = t
        .paths
        .iter()
        .filter(|p| p.color.is_some())
        .map(|p| p.label.clone())
        .collect();
    let frontier: BTreeSet<u32> = t.pareto.iter().map(|p| p.3).collect();
    if frontier.len() <= HIGHLIGHTED {
        for id in frontier {
            assert!(
                colored.iter().any(|l| l.starts_with(&format!("{id}:"))),
                "{id}"
            );
        }
    }
}

fn empty_profile() -> Profile {
    let mut p = profile_of(&[], 0.0);
    p.hit_rate = fit_hit_rate(&[]);
    p
}

#[test]
fn degenerate_profiles_still_chart() {
    let dir = tempfile::tempdir().unwrap();

    // No node at all, no original time, failed hit-rate fit.
    let empty = empty_profile();
    let paths = write_charts(&empty, dir.path(), "empty", &ChartOptions::default()).unwrap();
    check_files(&paths, dir.path(), "empty");
    assert!(svg(&paths, 0).contains("no measurements"));
    assert!(svg(&paths, 1).contains("fit failed"));

    // Nodes without measurements.
    let mut bare = profile_of(&marble(), 22.0);
    for n in &mut bare.nodes {
        n.measurements.clear();
    }
    let paths = write_charts(&bare, dir.path(), "bare", &ChartOptions::default()).unwrap();
    check_files(&paths, dir.path(), "bare");

    // All errors 0, a single Δn, identical times and hit rates.
    let mut flat = profile_of(&marble(), 22.0);
    for n in &mut flat.nodes {
        n.measurements.truncate(1);
        for m in &mut n.measurements {
            m.error = 0.0;
            m.frame_ms = 22.0;
            m.hit_rate = 0.5;
            m.mse = Some(0.0);
            m.psnr = None;
        }
        n.error_fit = fit_error(&[(2.0, 0.0)], &ErrorFitOptions::default());
    }
    flat.hit_rate = HitRateFit::from_mu(1.0);
    let paths = write_charts(&flat, dir.path(), "flat", &ChartOptions::default()).unwrap();
    check_files(&paths, dir.path(), "flat");
    assert!(svg(&paths, 0).contains("original"));

    // Zero frame times everywhere, original included.
    let mut zero = flat.clone();
    zero.original.frame_ms = 0.0;
    for n in &mut zero.nodes {
        for m in &mut n.measurements {
            m.frame_ms = 0.0;
        }
    }
    let paths = write_charts(&zero, dir.path(), "zero", &ChartOptions::default()).unwrap();
    check_files(&paths, dir.path(), "zero");
    keep(dir.path());
}

#[test]
fn png_without_font_has_no_text_but_svg_does() {
    let profile = profile_of(&marble(), 22.0);
    let dir = tempfile::tempdir().unwrap();
    let paths = write_charts_with(
        &profile,
        dir.path(),
        "nofont",
        &ChartOptions::default(),
        None,
    )
    .unwrap();
    check_files(&paths, dir.path(), "nofont");
    assert!(svg(&paths, 0).contains("original"));
    // Lines and points are there: far from a blank page.
    let img = image::open(&paths.png[0]).unwrap().to_rgb8();
    let inked = img.pixels().filter(|p| p.0 != [255, 255, 255]).count();
    assert!(inked > 5_000, "{inked}");
    keep(dir.path());
}

#[test]
fn writes_into_a_missing_directory_and_replaces_files() {
    let profile = profile_of(&marble()[..2], 22.0);
    let dir = tempfile::tempdir().unwrap();
    let nested = dir.path().join("a/b");
    write_charts(&profile, &nested, "x", &ChartOptions::default()).unwrap();
    let paths = write_charts(&profile, &nested, "x", &ChartOptions::default()).unwrap();
    check_files(&paths, &nested, "x");
}
