//! Strategy benchmark (`cargo bench -p reproj-replay --bench strategies`, or
//! `scripts/bench-strategies.sh`): for each sample shader and resolution, the original and every
//! variant strategy (3pass, 2pass, fused) caching the root and the best inner node, side by side in
//! one run on one adapter. Prints, per replay, the mean frame time and per-pass times (GPU
//! timestamps where the adapter has them; frame 0, which compiles the shaders, excluded), the
//! error (mean per-pixel L2 over all pixels) and PSNR (over the covered pixels) against the
//! original, the hit rate, and the speedup as a ratio of mean frame times. The original is replayed
//! before and after the variants of a shader; the speedup uses the mean of the two.
//!
//! Options (after `--`): `--shaders a,b,c` (names under `shaders/`, each with its session under
//! `sessions/`), `--resolutions 256x256,640x480`, `--delta-n N`, `--frames F` (frames per replay),
//! `--markdown` (rows of a Markdown table instead of aligned columns).

use std::path::PathBuf;

use reproj_front::{enumerate, load_file, normalize};
use reproj_instance::{InstanceOptions, NodeSelector, Strategy, instance};
use reproj_metrics::RenderReport;
use reproj_replay::{RenderOptions, Renderer, RendererOptions, VariantInput};
use reproj_scene::Session;

struct Args {
    shaders: Vec<String>,
    resolutions: Vec<[u32; 2]>,
    delta_n: u32,
    frames: u32,
    markdown: bool,
}

fn parse_args() -> Args {
    let mut a = Args {
        shaders: vec!["marble".into(), "envmap".into(), "ambient_occlusion".into()],
        resolutions: vec![[256, 256], [640, 480]],
        delta_n: 16,
        frames: 60,
        markdown: false,
    };
    let args: Vec<String> = std::env::args().skip(1).collect();
    let mut i = 0;
    while i < args.len() {
        let next = || args.get(i + 1).cloned().unwrap_or_default();
        match args[i].as_str() {
            "--shaders" => a.shaders = next().split(',').map(str::to_owned).collect(),
            "--resolutions" => {
                a.resolutions = next()
                    .split(',')
                    .map(|r| {
                        let (w, h) = r.split_once('x').expect("--resolutions WxH,...");
                        [w.parse().expect("width"), h.parse().expect("height")]
                    })
                    .collect()
            }
            "--delta-n" => a.delta_n = next().parse().expect("--delta-n N"),
            "--frames" => a.frames = next().parse().expect("--frames F"),
            "--markdown" => {
                a.markdown = true;
                i += 1;
                continue;
            }
            // `cargo bench` passes `--bench`; ignore what is not ours.
            _ => {
                i += 1;
                continue;
            }
        }
        i += 2;
    }
    a
}

/// Mean per-pass times over frames 1.. (frame 0 compiles the shaders).
fn pass_ms(r: &RenderReport) -> Vec<f64> {
    let frames: Vec<_> = r.frames.iter().skip(1).collect();
    let n = frames.iter().map(|f| f.pass_ms.len()).max().unwrap_or(0);
    (0..n)
        .map(|i| {
            frames.iter().filter_map(|f| f.pass_ms.get(i)).sum::<f64>() / frames.len().max(1) as f64
        })
        .collect()
}

fn fmt_passes(p: &[f64]) -> String {
    if p.is_empty() {
        return "-".into();
    }
    p.iter()
        .map(|x| format!("{x:.2}"))
        .collect::<Vec<_>>()
        .join(" + ")
}

fn main() {
    let args = parse_args();
    let root = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../..");
    let renderer = Renderer::new(&RendererOptions::default()).unwrap_or_else(|e| panic!("{e}"));
    let opts = RenderOptions {
        png_dir: None,
        max_frames: Some(args.frames),
        first_frame: 0,
        timing_only: false,
        classify: false,
        raw_frames: false,
        perceptual_stride: None,
    };
    println!(
        "strategy benchmark: Δn = {}, {} frames per replay; adapter: {} ({}) [{:?}]; cores: {}; LP_NUM_THREADS={}",
        args.delta_n,
        args.frames,
        renderer.adapter().name,
        renderer.adapter().backend,
        renderer.timing_method(),
        std::thread::available_parallelism().map_or(1, |n| n.get()),
        std::env::var("LP_NUM_THREADS").unwrap_or_else(|_| "unset".into())
    );
    if args.markdown {
        println!(
            "| shader | size | replay | frame ms | per pass ms | error | PSNR dB | hit rate | speedup |"
        );
        println!("|---|---|---|---:|---|---:|---:|---:|---:|");
    } else {
        println!(
            "{:<18} {:>8} {:<34} {:>9} {:<24} {:>8} {:>7} {:>6} {:>7}",
            "shader",
            "size",
            "replay",
            "frame ms",
            "per pass ms",
            "error",
            "PSNR",
            "hits",
            "speedup"
        );
    }
    for name in &args.shaders {
        let shader_path = root.join("shaders").join(format!("{name}.wgsl"));
        let session_path = root.join("sessions").join(format!("{name}.json"));
        let shader = load_file(&shader_path).unwrap_or_else(|e| panic!("{e}"));
        let norm = normalize(&shader, &Default::default()).unwrap_or_else(|e| panic!("{e}"));
        let table = enumerate(&shader, &norm);
        let entry = shader.fragment_entry(None).unwrap();
        // The root and the cacheable node saving the most while costing clearly less than the
        // whole shader (marble: the turbulence sum; AO: the static occlusion sum).
        let inner = table
            .cacheable()
            .filter(|n| !n.root && n.cost <= 0.97 * table.total_cost)
            .max_by(|a, b| (a.cost - a.overlap).total_cmp(&(b.cost - b.overlap)));
        let mut nodes = vec![("root".to_string(), NodeSelector::Root)];
        if let Some(n) = inner {
            nodes.push((format!("node {}", n.id), NodeSelector::Id(n.id)));
        }
        for &res in &args.resolutions {
            let mut session = Session::load(&session_path).unwrap_or_else(|e| panic!("{e}"));
            session.resolution = res;
            let size = format!("{}x{}", res[0], res[1]);
            let row = |label: &str, r: &RenderReport, base: Option<f64>| {
                let speedup =
                    base.map_or("1.00x".to_string(), |b| format!("{:.2}x", b / r.frame_ms));
                let (error, psnr, hits) = if base.is_some() {
                    (
                        format!("{:.5}", r.error),
                        format!("{:.1}", r.psnr),
                        format!("{:.3}", r.hit_rate),
                    )
                } else {
                    ("-".into(), "-".into(), "-".into())
                };
                let passes = fmt_passes(&pass_ms(r));
                if args.markdown {
                    println!(
                        "| {name} | {size} | {label} | {:.2} | {passes} | {error} | {psnr} | {hits} | {speedup} |",
                        r.frame_ms
                    );
                } else {
                    println!(
                        "{name:<18} {size:>8} {label:<34} {:>9.2} {passes:<24} {error:>8} {psnr:>7} {hits:>6} {speedup:>7}",
                        r.frame_ms
                    );
                }
            };
            let reference = renderer
                .render_original(&shader, entry, &session, &opts)
                .unwrap_or_else(|e| panic!("{e}"));
            let mut variants = Vec::new();
            for (label, sel) in &nodes {
                for strategy in Strategy::ALL {
                    let options = InstanceOptions {
                        strategy,
                        block: strategy.default_block(),
                        delta_n: args.delta_n,
                        ..InstanceOptions::default()
                    };
                    let v = instance(&shader, &norm, &table, *sel, &options)
                        .unwrap_or_else(|e| panic!("{e}"));
                    let input = VariantInput {
                        // The per-pass columns: every pass in its own render pass.
                        pass_times: true,
                        ..VariantInput::new(
                            v.passes.iter().map(|p| p.wgsl.clone()).collect(),
                            v.manifest.clone(),
                            args.delta_n,
                        )
                    };
                    let r = renderer
                        .render_variant(&shader, &session, &input, &reference, &opts)
                        .unwrap_or_else(|e| panic!("{e}"));
                    variants.push((format!("{label} {strategy} k={}", options.block), r));
                }
            }
            let again = renderer
                .render_original(&shader, entry, &session, &opts)
                .unwrap_or_else(|e| panic!("{e}"));
            let base = 0.5 * (reference.report.frame_ms + again.report.frame_ms);
            row("original", &reference.report, None);
            row("original (again)", &again.report, None);
            for (label, r) in &variants {
                row(&format!("{label} Δn={}", args.delta_n), r, Some(base));
            }
        }
    }
}
