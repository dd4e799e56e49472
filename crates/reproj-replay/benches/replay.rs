//! Replay benchmark (`cargo bench -p reproj-replay`): the 150-frame marble session at 256×256,
//! replayed for the original shader and for two cached variants at Δn = 32, side by side in one run.
//! Reports wall time per replay, mean frame time (GPU timestamps; frame 0, which compiles the
//! shaders, excluded) and each variant's speedup as a ratio of mean frame times.
//!
//! Options (after `--`): `--shader PATH --session PATH --delta-n N --repeat R`.

use std::path::PathBuf;
use std::time::Instant;

use reproj_front::{enumerate, load_file, normalize};
use reproj_instance::{InstanceOptions, NodeSelector, instance};
use reproj_replay::{RenderOptions, Renderer, RendererOptions, VariantInput};
use reproj_scene::Session;

fn main() {
    let root = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../..");
    let mut shader_path = root.join("shaders/marble.wgsl");
    let mut session_path = root.join("sessions/marble.json");
    let mut delta_n = 32u32;
    let mut repeat = 3usize;
    let args: Vec<String> = std::env::args().skip(1).collect();
    let mut i = 0;
    while i < args.len() {
        let next = |i: usize| args.get(i + 1).cloned().unwrap_or_default();
        match args[i].as_str() {
            "--shader" => shader_path = PathBuf::from(next(i)),
            "--session" => session_path = PathBuf::from(next(i)),
            "--delta-n" => delta_n = next(i).parse().expect("--delta-n N"),
            "--repeat" => repeat = next(i).parse().expect("--repeat R"),
            _ => {
                i += 1;
                continue;
            }
        }
        i += 2;
    }
    let shader = load_file(&shader_path).unwrap_or_else(|e| panic!("{e}"));
    let session = Session::load(&session_path).unwrap_or_else(|e| panic!("{e}"));
    let renderer = Renderer::new(&RendererOptions::default()).unwrap_or_else(|e| panic!("{e}"));
    let norm = normalize(&shader, &Default::default()).unwrap();
    let table = enumerate(&shader, &norm);
    let opts = RenderOptions {
        png_dir: None,
        max_frames: None,
        first_frame: 0,
        timing_only: false,
        classify: false,
        raw_frames: false,
        perceptual_stride: None,
    };
    println!(
        "replay benchmark: {} over {} ({} frames, {}x{})",
        shader_path.display(),
        session_path.display(),
        session.frames,
        session.resolution[0],
        session.resolution[1]
    );
    println!(
        "adapter: {} [{:?}]; cores: {}; LP_NUM_THREADS={}",
        renderer.adapter().name,
        renderer.timing_method(),
        std::thread::available_parallelism().map_or(1, |n| n.get()),
        std::env::var("LP_NUM_THREADS").unwrap_or_else(|_| "unset".into())
    );
    // An inner node (marble: the turbulence sum `s3 + n4`; another shader: the cacheable node saving
    // the most while costing clearly less than the whole shader) and the root.
    let inner = table
        .cacheable()
        .find(|n| n.text == "s3 + n4")
        .or_else(|| {
            table
                .cacheable()
                .filter(|n| !n.root && n.cost <= 0.97 * table.total_cost)
                .max_by(|a, b| (a.cost - a.overlap).total_cmp(&(b.cost - b.overlap)))
        })
        .unwrap_or_else(|| table.root());
    let variants: Vec<(String, VariantInput)> = [
        (
            format!("node {} `{}`", inner.id, inner.text),
            NodeSelector::Id(inner.id),
        ),
        ("root".to_string(), NodeSelector::Root),
    ]
    .into_iter()
    .map(|(label, sel)| {
        let v = instance(&shader, &norm, &table, sel, &InstanceOptions::default()).unwrap();
        let input = VariantInput::new(
            v.passes.iter().map(|p| p.wgsl.clone()).collect(),
            v.manifest.clone(),
            delta_n,
        );
        (label, input)
    })
    .collect();
    println!(
        "{:<6} {:<40} {:>10} {:>12} {:>9} {:>9} {:>8}",
        "round", "replay", "wall s", "frame ms", "error", "hit rate", "speedup"
    );
    for round in 0..repeat {
        let t = Instant::now();
        let reference = renderer
            .render_original(
                &shader,
                shader.fragment_entry(None).unwrap(),
                &session,
                &opts,
            )
            .unwrap();
        let wall = t.elapsed().as_secs_f64();
        let base = reference.report.frame_ms;
        println!(
            "{round:<6} {:<40} {wall:>10.2} {base:>12.3} {:>9} {:>9} {:>8}",
            "original", "-", "-", "1.00x"
        );
        for (label, input) in &variants {
            let t = Instant::now();
            let r = renderer
                .render_variant(&shader, &session, input, &reference, &opts)
                .unwrap();
            let wall = t.elapsed().as_secs_f64();
            println!(
                "{round:<6} {:<40} {wall:>10.2} {:>12.3} {:>9.5} {:>9.3} {:>7.2}x",
                format!("{label} at Δn={delta_n}")
                    .chars()
                    .take(40)
                    .collect::<String>(),
                r.frame_ms,
                r.error,
                r.hit_rate,
                base / r.frame_ms
            );
        }
    }
}
