//! `reproj render`: replay a session for the original shader or one variant.
//!
//! A long session renders for minutes: progress goes to stderr per frame, as `analyze`'s does
//! per replay ([`FrameBar`]), and never with `--json`, whose stdout a program reads.

use std::cell::Cell;
use std::io::Write;
use std::time::{Duration, Instant};

use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use reproj_front::Loaded;
use reproj_instance::{NodeSelector, instance};
use reproj_replay::{FrameProgress, RenderOptions, Renderer, RendererOptions, VariantInput};
use reproj_scene::Session;

use super::UserError;
use crate::RenderArgs;

/// What `render --frames DIR` writes (and so what DIR may hold for it to be replaced).
const FRAME_FILES: &[&str] = &["png", "f32"];

/// `reproj render`: the shader and the variant, the reference replay, the variant's replay and
/// its timing on request, the frames committed, the warnings, then the report.
pub fn run(args: &RenderArgs) -> anyhow::Result<()> {
    let mut stdout = super::stdout::stdout();
    let input = super::read_shader(&args.shader, args.lang_in, &args.input)?;
    // The replay renders WGSL: a GLSL shader is rendered as naga's WGSL of it.
    let shader = input.to_wgsl()?;
    let entry = shader.fragment_entry(args.entry.as_deref())?;
    let session = Session::load(&args.session)?;
    let variant_input = variant_input(args, input, &session)?;
    let renderer = Renderer::new(&RendererOptions {
        backend: args.backend.clone(),
        cpu_timing: false,
        ..Default::default()
    })?;
    // `--frames DIR` is written aside and replaces DIR whole at the end: a failed or
    // interrupted render leaves the previous frames as they were.
    let frames = args
        .frames
        .as_deref()
        .map(|dir| reproj_io::StagedDir::new(dir, reproj_io::Replace::OwnFiles(FRAME_FILES)))
        .transpose()?;
    let opts = RenderOptions {
        png_dir: frames.as_ref().map(|f| f.path().to_owned()),
        max_frames: args.max_frames,
        first_frame: 0,
        timing_only: false,
        classify: true,
        raw_frames: args.raw_frames,
        perceptual_stride: Some(args.metric_stride),
    };
    let has_variant = args.node.is_some() || args.variant.is_some();
    // With a variant, the original's frames go beside the variant's as `ref_NNN.png`.
    let progress = |phase| -> Box<dyn FrameProgress> {
        if args.json || crate::ui::quiet() {
            Box::new(())
        } else {
            Box::new(FrameBar::new(phase))
        }
    };
    let reference = renderer.render_original_with(
        &shader,
        entry,
        &session,
        &RenderOptions {
            classify: false,
            png_dir: opts.png_dir.clone().filter(|_| !has_variant),
            raw_frames: opts.raw_frames && !has_variant,
            ..opts.clone()
        },
        progress("original").as_ref(),
    )?;
    if let Some(dir) = opts.png_dir.as_ref().filter(|_| has_variant) {
        for (i, frame) in reference.frames.iter().enumerate() {
            reproj_metrics::output::write_reference_frame(
                dir,
                i as u32,
                reference.width,
                reference.height,
                frame,
            )?;
        }
    }
    let report = match &variant_input {
        None => reference.report.clone(),
        Some(input) => renderer.render_variant_with(
            &shader,
            &session,
            input,
            &reference,
            &opts,
            progress("variant").as_ref(),
        )?,
    };
    // Two single replays taken one after the other are no speed measurement: the speedup comes
    // from the timing engine (`reproj bench`: interleaved, with its 95 % interval), on request.
    let speedup = match (&variant_input, args.speedup) {
        (Some(input), true) => Some(time_against_original(
            &renderer, &shader, entry, &session, &reference, input, args,
        )?),
        _ => None,
    };
    let original_ms = variant_input.as_ref().map(|_| reference.report.frame_ms);
    if let Some(original_ms) = original_ms.filter(|_| speedup.is_none() && !args.json) {
        note_single_replays(args, original_ms, report.frame_ms);
    }
    if let Some(frames) = frames {
        frames.commit()?;
    }
    warn_nonfinite(&report);
    if let Some(s) = &speedup {
        for w in &s.warnings {
            crate::ui::warn(w);
        }
    }
    let out = RenderOutput {
        report: &report,
        original_frame_ms: original_ms,
        speedup: speedup.as_ref(),
    };
    if args.json {
        writeln!(stdout, "{}", serde_json::to_string_pretty(&out)?)?;
    } else {
        print_report(&mut stdout, &out, args)?;
    }
    Ok(())
}

/// A variant's and the original's frame times from one replay each are no speed comparison:
/// said as such, with how to get the speedup.
fn note_single_replays(args: &RenderArgs, original_ms: f64, variant_ms: f64) {
    crate::ui::note(format!(
        "original: {:.3} ms/frame; variant: {:.3} ms/frame (one replay each; for the speedup with its 95 % interval: --speedup, or reproj bench {} --session {} {})",
        original_ms,
        variant_ms,
        args.shader.display(),
        args.session.display(),
        args.variant
            .as_ref()
            .map_or_else(|| "VARIANT_DIR".into(), |v| v.display().to_string()),
    ));
}

/// The variant to render, if any: `--node` instanced here, or `--variant DIR` read (checked to be
/// of this shader, its Δn from the flag, the manifest or `--adaptive`). Done before the reference
/// is rendered, so a wrong node or another shader's variant is refused first.
fn variant_input(
    args: &RenderArgs,
    input: reproj_front::Shader,
    session: &Session,
) -> anyhow::Result<Option<VariantInput>> {
    let mut variant = variant_of(args, input, session)?;
    if let Some(v) = &mut variant {
        v.pass_times = args.pass_times;
    }
    Ok(variant)
}

/// The variant `--node` instances or `--variant` names, if any.
fn variant_of(
    args: &RenderArgs,
    input: reproj_front::Shader,
    session: &Session,
) -> anyhow::Result<Option<VariantInput>> {
    Ok(match (&args.node, &args.variant) {
        (None, None) => None,
        (Some(node), _) => {
            let sel: NodeSelector = node.parse().map_err(UserError)?;
            let loaded = Loaded::new(input, args.entry.as_deref())?;
            let variant = instance(
                &loaded.shader,
                &loaded.norm,
                &loaded.table,
                sel,
                &super::instance_options(args.cache, args.delta_n.unwrap_or(8))?,
            )?;
            Some(VariantInput::new(
                variant.passes.iter().map(|p| p.wgsl.clone()).collect(),
                variant.manifest.clone(),
                args.delta_n.unwrap_or(8),
            ))
        }
        (None, Some(dir)) => {
            let mut variant = VariantInput::from_dir(dir, 1)?;
            super::check_variant_shader(&input, &args.shader, &variant.manifest, dir)?;
            variant.delta_n = args.delta_n.unwrap_or(variant.manifest.params.delta_n);
            if args.adaptive {
                let (lo, hi) = super::adapt(&mut variant, session)?;
                crate::ui::note(format!("adaptive: Δn {lo}..={hi} by each frame's motion"));
            }
            Some(variant)
        }
    })
}

/// Never a silent NaN: the non-finite pixels of the render and of the original, said on stderr
/// whatever the output format.
fn warn_nonfinite(report: &reproj_metrics::RenderReport) {
    let is_variant = report.node.is_some();
    if report.nonfinite_pixels > 0 {
        crate::ui::warn(format_args!(
            "{} renders {} pixels that are NaN or infinite over the session{}",
            if is_variant {
                "the variant"
            } else {
                "the shader"
            },
            report.nonfinite_pixels,
            if is_variant {
                " where the original is finite: its error is not a number"
            } else {
                ""
            }
        ));
    }
    if report.nonfinite_reference_pixels > 0 {
        crate::ui::warn(format_args!(
            "the original renders {} pixels that are NaN or infinite over the session; they are left out of the error",
            report.nonfinite_reference_pixels
        ));
    }
}

/// The report as text: what was rendered, its errors, hit rate and frame time, the original's
/// own replay time beside a variant's, the timing engine's speedup on request.
fn print_report(
    stdout: &mut impl Write,
    out: &RenderOutput,
    args: &RenderArgs,
) -> std::io::Result<()> {
    let report = out.report;
    writeln!(
        stdout,
        "{} over {} ({} frames, {}x{}) on {} [{:?}]",
        report.node.as_deref().map_or_else(
            || "original".to_string(),
            |n| format!("node {n} at Δn = {}", report.delta_n.unwrap_or(1))
        ),
        args.session.display(),
        report.frames.len(),
        report.resolution[0],
        report.resolution[1],
        report.adapter.name,
        report.timing,
    )?;
    writeln!(
        stdout,
        "  error     {:.6} (mean per-pixel L2, linear RGB)",
        report.error
    )?;
    if let Some(w) = report.error_worst.filter(|_| report.node.is_some()) {
        writeln!(stdout, "  worst     {:.6} (frame {})", w.value, w.frame)?;
    }
    writeln!(stdout, "  PSNR      {:.2} dB", report.psnr)?;
    if let Some(f) = report.flip {
        writeln!(
            stdout,
            "  ꟻLIP      {:.6} mean, worst {:.6} (frame {}) (covered pixels, {} of {} frames)",
            f.mean,
            f.worst.value,
            f.worst.frame,
            f.frames,
            report.frames.len()
        )?;
    }
    if let Some(s) = report.ssim {
        writeln!(
            stdout,
            "  SSIM      {:.6} mean, worst {:.6} (frame {})",
            s.mean, s.worst.value, s.worst.frame
        )?;
    }
    writeln!(stdout, "  hit rate  {:.3}", report.hit_rate)?;
    writeln!(
        stdout,
        "  frame     {:.3} ms (mean over frames 1..; frame 0 compiles shaders)",
        report.frame_ms
    )?;
    if let Some(original_ms) = out.original_frame_ms {
        writeln!(stdout, "  original  {original_ms:.3} ms (its own replay)")?;
    }
    if let Some(s) = out.speedup {
        writeln!(
            stdout,
            "  speedup   {} (timing engine: {} rounds interleaved with the original, {:.1} s; original {:.3} ms/frame)",
            match (s.speedup, s.speedup_ci95) {
                (Some(x), Some([lo, hi])) => format!("{x:.2}x [{lo:.2}, {hi:.2}]"),
                (Some(x), None) => format!("{x:.2}x"),
                _ => "no usable timing".into(),
            },
            s.rounds,
            s.seconds,
            s.original_median_ms,
        )?;
    }
    if let Some(dir) = &args.frames {
        writeln!(stdout, "  PNGs in   {}", dir.display())?;
    }
    Ok(())
}

/// `render --json`: the replay's report (`reproj.render`, its `schema` and `version` first), then
/// the original's own replay time beside a variant's and, with `--speedup`, the timing engine's
/// figure (docs/SCHEMAS.md).
#[derive(serde::Serialize)]
struct RenderOutput<'a> {
    #[serde(flatten)]
    report: &'a reproj_metrics::RenderReport,
    /// The original's mean ms/frame in its own replay (a variant's render only): one replay, not
    /// a speed comparison.
    #[serde(skip_serializing_if = "Option::is_none")]
    original_frame_ms: Option<f64>,
    /// `--speedup`: the variant timed against the original by the timing engine.
    #[serde(skip_serializing_if = "Option::is_none")]
    speedup: Option<&'a Speedup>,
}

/// The timing engine's answer for one variant against the original (`reproj bench`'s figure).
#[derive(Debug, serde::Serialize)]
struct Speedup {
    /// Original time over variant time (above 1: faster), Hodges–Lehmann over the rounds.
    speedup: Option<f64>,
    speedup_ci95: Option<[f64; 2]>,
    /// Median ms/frame of the interleaved blocks.
    original_median_ms: f64,
    variant_median_ms: Option<f64>,
    rounds: u32,
    seconds: f64,
    warnings: Vec<String>,
}

/// `--speedup`: time the variant against the original through the timing engine, interleaved,
/// as `reproj bench` does with its defaults.
fn time_against_original(
    renderer: &Renderer,
    shader: &reproj_front::Shader,
    entry: usize,
    session: &Session,
    reference: &reproj_replay::Reference,
    variant: &VariantInput,
    args: &RenderArgs,
) -> anyhow::Result<Speedup> {
    use reproj_bench::{Baseline, BenchOptions, Candidate, Subject, bench};
    crate::ui::note("timing the variant against the original (interleaved)");
    let report = bench(
        renderer,
        Baseline {
            shader,
            entry,
            reference,
        },
        session,
        &[Candidate {
            name: "variant".into(),
            subject: Subject::Variant(variant.clone()),
        }],
        &BenchOptions {
            max_frames: args.max_frames,
            ..BenchOptions::default()
        },
        &mut |_| {},
    )?;
    let c = &report.candidates[0];
    Ok(Speedup {
        speedup: c.speedup,
        speedup_ci95: c.speedup_ci95,
        original_median_ms: report.baseline.median_ms,
        variant_median_ms: c.median_ms,
        rounds: report.rounds,
        seconds: report.seconds,
        warnings: report.warnings.clone(),
    })
}

/// How often a progress line is printed when stderr is no terminal; the first comes only once a
/// replay has run this long, so short renders print none.
const LINE_EVERY: Duration = Duration::from_secs(2);

/// The per-frame progress of one replay (`original` or `variant`) on stderr: on a terminal a bar
/// with an ETA, redrawn at most 4 times a second; otherwise (CI, a log file) a line like
/// `analyze`'s, `[done/total] phase frames: … s elapsed, ETA … s`, at most every [`LINE_EVERY`]
/// (`REPROJ_PROGRESS_EVERY_MS` overrides it; the tests set 0 for a line per frame). Cleared when
/// dropped.
struct FrameBar {
    bar: ProgressBar,
    phase: &'static str,
    start: Instant,
    every: Duration,
    last_line: Cell<Instant>,
}

impl FrameBar {
    fn new(phase: &'static str) -> FrameBar {
        let bar = ProgressBar::with_draw_target(None, ProgressDrawTarget::stderr_with_hz(4))
            .with_style(
                ProgressStyle::with_template(
                    "{spinner} [{elapsed_precise}] {bar:30} {pos}/{len} frames, ETA {eta} {msg}",
                )
                .expect("valid template"),
            )
            .with_message(phase);
        let every = std::env::var("REPROJ_PROGRESS_EVERY_MS")
            .ok()
            .and_then(|ms| ms.parse().ok())
            .map_or(LINE_EVERY, Duration::from_millis);
        let start = Instant::now();
        FrameBar {
            bar,
            phase,
            start,
            every,
            last_line: Cell::new(start),
        }
    }
}

impl FrameProgress for FrameBar {
    fn frame(&self, done: u32, total: u32) {
        if !self.bar.is_hidden() {
            self.bar.set_length(total.into());
            self.bar.set_position(done.into());
            return;
        }
        let now = Instant::now();
        if now - self.last_line.get() < self.every {
            return;
        }
        self.last_line.set(now);
        let elapsed = (now - self.start).as_secs_f64();
        let eta = elapsed / f64::from(done.max(1)) * f64::from(total.saturating_sub(done));
        crate::ui::note(format_args!(
            "[{done}/{total}] {} frames: {elapsed:.1} s elapsed, ETA {eta:.0} s",
            self.phase
        ));
    }
}

impl Drop for FrameBar {
    fn drop(&mut self) {
        self.bar.finish_and_clear();
    }
}
