//! `reproj-host`: a small wgpu program that runs reproj's output the way an engine would.
//!
//! ```text
//! reproj-host --variant DIR --shader shaders/marble.wgsl --session sessions/marble.json \
//!             --frames 30 --out OUTDIR [--delta-n N] [--raw]
//! reproj-host --original --shader shaders/marble.wgsl --session sessions/marble.json --out OUTDIR
//! ```
//!
//! - `engine/` is the engine: the recorded scene (geometry, camera and object transforms, the
//!   original shader's own uniforms, storage buffers, textures and samplers), its vertex stage and
//!   frame target (`mod.rs`), its depth passes (`depth.rs`) and its own pass of the original
//!   shader (`original.rs`).
//! - `variant.rs` runs a variant through `reproj-runtime`, which reads `manifest.json` alone and
//!   owns what reproj added (textures, samplers, params, its bind group, the passes' pipelines,
//!   the per-frame params and ping-pong, passes in order with their load operations); the engine
//!   gives it its vertex stage, bind groups, frame and depth targets and draw calls.
//! - This file opens the device, runs the frames and writes `frame_NNN.png` (sRGB-encoded, as
//!   `reproj render --frames` writes them), with `--raw` `frame_NNN.f32` (the frame's exact
//!   linear RGBA: width × height × 4 little-endian f32, top row first, no header), and
//!   `summary.json` (per-frame milliseconds); with `--capture FILE` it records the frames it drew
//!   as a session (`capture.rs`).

mod capture;
mod engine;
mod gpu;
mod motion;
mod variant;

use std::collections::BTreeSet;
use std::path::{Path, PathBuf};
use std::time::Instant;

use anyhow::Context;
use clap::Parser;
use serde::Serialize;

use engine::{Engine, Original};
use gpu::{Gpu, Timer};
use reproj_runtime::{SessionCapture, Variant};
use variant::HostVariant;

/// Run a reproj variant (or the original shader) over a recorded session with wgpu, following
/// the variant's manifest.json alone; write the frames and their times.
#[derive(Debug, Parser)]
#[command(name = "reproj-host", version)]
struct Args {
    /// Directory written by `reproj instance` or `reproj emit` (manifest.json and the pass files).
    #[arg(
        long,
        required_unless_present = "original",
        conflicts_with = "original"
    )]
    variant: Option<PathBuf>,
    /// Render the original shader instead of a variant (the engine before reproj).
    #[arg(long)]
    original: bool,
    /// The original WGSL shader (the engine's own: its uniforms, textures and inputs).
    #[arg(long)]
    shader: PathBuf,
    /// The session: the scene, its animation and the shader's uniform values.
    #[arg(long)]
    session: PathBuf,
    /// Frames to render (default: the session's).
    #[arg(long)]
    frames: Option<u32>,
    /// Output directory.
    #[arg(long)]
    out: PathBuf,
    /// Refresh period Δn: the `steady` value of the manifest's `delta_n` parameter (default: the
    /// manifest's).
    #[arg(long, conflicts_with = "adaptive")]
    delta_n: Option<u32>,
    /// Run-time adaptation: each frame, measure the frame's on-screen motion from the camera and
    /// the objects' transforms (`motion.rs`) and set Δn from the manifest's schedule
    /// (`params.schedule`, written by `reproj emit`).
    #[arg(long)]
    adaptive: bool,
    /// Fragment entry point of the original shader (default: the manifest's, else the only one).
    #[arg(long)]
    entry: Option<String>,
    /// Also write each frame's exact linear RGBA as frame_NNN.f32.
    #[arg(long)]
    raw: bool,
    /// Time frames with CPU submit + wait even if the adapter has timestamp queries.
    #[arg(long)]
    cpu_timing: bool,
    /// Record the frames drawn as a session file (`reproj-runtime`'s `SessionCapture`: the
    /// camera, the objects' model matrices, the light and the uniform values of every frame, on
    /// top of `--session`), which `reproj render` replays to the same frames.
    #[arg(long, value_name = "FILE")]
    capture: Option<PathBuf>,
}

/// `summary.json`.
#[derive(Debug, Serialize)]
struct Summary {
    /// `variant` or `original`.
    mode: &'static str,
    variant: Option<String>,
    strategy: Option<String>,
    delta_n: Option<u32>,
    shader: String,
    session: String,
    resolution: [u32; 2],
    adapter: String,
    backend: String,
    /// `gpu-timestamps` (first pass's begin to last pass's end) or `cpu-submit-wait`.
    timing: &'static str,
    /// Mean `ms` over frames 1.. (frame 0 pays pipeline compilation on some drivers).
    mean_ms: f64,
    frames: Vec<FrameRecord>,
}

#[derive(Debug, Serialize)]
struct FrameRecord {
    frame: u32,
    /// The frame time by the summary's `timing`.
    ms: f64,
    /// Wall time of submit + wait for the frame's commands.
    cpu_ms: f64,
    /// GPU time per render pass (empty without timestamps; a variant's passes that share their
    /// targets share one).
    pass_ms: Vec<f64>,
    /// With `--adaptive`: the frame's measured motion (pixels per frame) and the Δn it set.
    #[serde(skip_serializing_if = "Option::is_none")]
    motion_px: Option<f64>,
    #[serde(skip_serializing_if = "Option::is_none")]
    delta_n: Option<u32>,
}

/// What the frame loop draws.
enum Mode {
    Variant(Box<HostVariant>),
    Original(Original),
}

fn main() {
    let args = Args::parse();
    if let Err(e) = run(&args) {
        // One prefix, as `reproj` prints its errors (a cause that says `error:` itself keeps
        // only the first).
        let message = format!("{e:#}");
        eprintln!(
            "error: {}",
            message.strip_prefix("error: ").unwrap_or(&message)
        );
        std::process::exit(1);
    }
}

fn run(args: &Args) -> anyhow::Result<()> {
    // The manifest first: its version, features and bind groups decide how the device and the
    // engine are set up.
    let variant = match &args.variant {
        Some(dir) => Some(Variant::load(dir)?),
        None => None,
    };
    let required = variant
        .as_ref()
        .map_or(wgpu::Features::empty(), Variant::required_features);
    let gpu = Gpu::new(required, args.cpu_timing)?;
    let reserved: BTreeSet<u32> = variant
        .as_ref()
        .map(Variant::reserved_groups)
        .unwrap_or_default();
    let entry = args
        .entry
        .as_deref()
        .or(variant.as_ref().map(|v| v.manifest().entry.as_str()));
    let engine = Engine::new(&gpu, &args.session, &args.shader, entry, &reserved)?;
    if let Some(m) = variant.as_ref().map(Variant::manifest) {
        let file = args.shader.file_name().and_then(|f| f.to_str());
        if file != Some(m.shader.as_str()) {
            eprintln!(
                "note: the manifest was written for {}, the engine's shader is {}",
                m.shader,
                args.shader.display()
            );
        }
    }
    let mode = match variant {
        Some(v) => Mode::Variant(Box::new(HostVariant::new(&gpu, &engine, v)?)),
        None => Mode::Original(Original::new(&gpu, &engine)?),
    };
    // The refresh period: `--delta-n`, else the manifest's; `--adaptive` sets it every frame.
    let mut delta_n = args.delta_n.map(|n| n.max(1));
    let timer = Timer::new(
        &gpu,
        match &mode {
            Mode::Variant(v) => v.variant.render_pass_count() as u32,
            Mode::Original(_) => 1,
        },
    );
    std::fs::create_dir_all(&args.out)
        .with_context(|| format!("creating {}", args.out.display()))?;

    let frames = args
        .frames
        .unwrap_or(engine.session.frames)
        .clamp(1, engine.session.frames);
    let mut records = Vec::new();
    let probe = args
        .adaptive
        .then(|| motion::MotionProbe::new(&engine.session));
    let mut mode = mode;
    if let (true, Mode::Variant(v)) = (args.adaptive, &mode)
        && v.variant.manifest().params.schedule.is_empty()
    {
        anyhow::bail!(
            "--adaptive: the manifest has no run-time schedule (params.schedule; `reproj emit` writes one from a profile that records motion)"
        );
    }
    let mut capture = match &args.capture {
        Some(_) => Some(SessionCapture::from_file(&args.session)?),
        None => None,
    };
    for f in 0..frames {
        // The engine's per-frame updates, then the variant's.
        engine.write_frame(&gpu, f);
        if let Some(c) = &mut capture {
            c.frame(capture::frame(&engine.session, f))?;
        }
        let mut enc = gpu.device.create_command_encoder(&Default::default());
        engine.encode_depth_passes(&mut enc);
        let mut adapted = (None, None);
        if let (Some(probe), Mode::Variant(v)) = (&probe, &mode) {
            // This frame's motion from the previous frame's transforms to this one's.
            let now = engine.session.frame_state(f);
            let prev = engine.session.frame_state(f.saturating_sub(1));
            let px = if f == 0 {
                0.0
            } else {
                probe.pixels(&prev, &now)
            };
            if let Some(dn) = v.variant.scheduled_delta_n(px) {
                delta_n = Some(dn.max(1));
                adapted = (Some(px), Some(dn));
            }
        }
        match &mut mode {
            Mode::Variant(v) => {
                if v.variant.loads_frame_first() {
                    // `--frame-load load`: the passes draw over what the engine drew before; here
                    // that is its background.
                    enc.begin_render_pass(&wgpu::RenderPassDescriptor {
                        label: Some("engine background"),
                        color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                            view: &engine.frame_view,
                            depth_slice: None,
                            resolve_target: None,
                            ops: wgpu::Operations {
                                load: wgpu::LoadOp::Clear(engine.clear),
                                store: wgpu::StoreOp::Store,
                            },
                        })],
                        ..Default::default()
                    });
                }
                v.encode_frame(&gpu, &mut enc, &engine, delta_n, &timer)?;
            }
            Mode::Original(o) => o.encode(&mut enc, &engine, &timer),
        }
        timer.resolve(&mut enc);
        let t0 = Instant::now();
        gpu.queue.submit([enc.finish()]);
        gpu.wait()?;
        let cpu_ms = t0.elapsed().as_secs_f64() * 1e3;
        gpu.check(&format!("frame {f}"))?;
        let times = timer.read(&gpu)?;
        let pixels = gpu.read_rgba32f(&engine.frame)?;
        write_frame(&args.out, f, engine.width, engine.height, &pixels, args.raw)?;
        records.push(FrameRecord {
            frame: f,
            ms: times.span_ms.unwrap_or(cpu_ms),
            cpu_ms,
            pass_ms: times.pass_ms,
            motion_px: adapted.0,
            delta_n: adapted.1,
        });
    }

    if let (Some(c), Some(path)) = (&capture, &args.capture) {
        c.write(path)?;
        eprintln!("session recorded: {} ({frames} frames)", path.display());
    }
    let steady: Vec<f64> = records.iter().skip(1).map(|r| r.ms).collect();
    let mean_ms = if steady.is_empty() {
        records[0].ms
    } else {
        steady.iter().sum::<f64>() / steady.len() as f64
    };
    let (variant, strategy, delta_n) = match &mode {
        Mode::Variant(v) => (
            args.variant.as_ref().map(|d| d.display().to_string()),
            Some(v.variant.manifest().strategy.clone()),
            delta_n.or(v.variant.delta_n()),
        ),
        Mode::Original(_) => (None, None, None),
    };
    let summary = Summary {
        mode: if variant.is_some() {
            "variant"
        } else {
            "original"
        },
        variant,
        strategy,
        delta_n,
        shader: args.shader.display().to_string(),
        session: args.session.display().to_string(),
        resolution: [engine.width, engine.height],
        adapter: gpu.adapter.clone(),
        backend: gpu.backend.clone(),
        timing: if gpu.timestamps {
            "gpu-timestamps"
        } else {
            "cpu-submit-wait"
        },
        mean_ms,
        frames: records,
    };
    let path = args.out.join("summary.json");
    std::fs::write(&path, serde_json::to_string_pretty(&summary)?)
        .with_context(|| format!("writing {}", path.display()))?;
    println!(
        "{} on {} [{}]: {} frames, {:.3} ms/frame (mean over frames 1..); frames and summary.json in {}",
        summary.variant.as_deref().unwrap_or("original"),
        summary.adapter,
        summary.timing,
        frames,
        summary.mean_ms,
        args.out.display()
    );
    Ok(())
}

/// `frame_NNN.png` (sRGB-encoded like `reproj render`'s) and, with `raw`, `frame_NNN.f32`.
fn write_frame(
    dir: &Path,
    index: u32,
    width: u32,
    height: u32,
    rgba: &[f32],
    raw: bool,
) -> anyhow::Result<()> {
    let png = dir.join(format!("frame_{index:03}.png"));
    let rgba8 = reproj_metrics::srgb::frame_to_rgba8(rgba);
    image::save_buffer(&png, &rgba8, width, height, image::ExtendedColorType::Rgba8)
        .with_context(|| format!("writing {}", png.display()))?;
    if raw {
        let path = dir.join(format!("frame_{index:03}.f32"));
        let bytes: Vec<u8> = rgba.iter().flat_map(|x| x.to_le_bytes()).collect();
        std::fs::write(&path, bytes).with_context(|| format!("writing {}", path.display()))?;
    }
    Ok(())
}
