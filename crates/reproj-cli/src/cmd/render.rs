//! `reproj render`: replay a session for the original shader or one variant.

use std::io::Write;

use reproj_front::{Loaded, load_file_as};
use reproj_instance::{NodeSelector, instance};
use reproj_replay::{RenderOptions, Renderer, RendererOptions, Session, VariantInput};

use super::UserError;
use crate::RenderArgs;

/// What `render --frames DIR` writes (and so what DIR may hold for it to be replaced).
const FRAME_FILES: &[&str] = &["png", "f32"];

pub fn run(args: &RenderArgs) -> anyhow::Result<()> {
    let mut stdout = std::io::stdout().lock();
    let input = load_file_as(&args.shader, super::lang_in(args.lang_in))?;
    // The replay renders WGSL: a GLSL shader is rendered as naga's WGSL of it.
    let shader = input.to_wgsl()?;
    let entry = shader.fragment_entry(args.entry.as_deref())?;
    let session = Session::load(&args.session)?;
    // The variant first: a wrong node or a variant of another shader is refused before the
    // reference frames are rendered.
    let variant_input = match (&args.node, &args.variant) {
        (None, None) => None,
        (Some(node), _) => {
            let sel: NodeSelector = node.parse().map_err(UserError)?;
            let loaded = Loaded::new(input, args.entry.as_deref())?;
            let variant = instance(
                &loaded.shader,
                &loaded.norm,
                &loaded.table,
                sel,
                &super::instance_options(args.cache, args.delta_n.unwrap_or(8)),
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
                let (lo, hi) = super::adapt(&mut variant, &session)?;
                eprintln!("adaptive: Δn {lo}..={hi} by each frame's motion");
            }
            Some(variant)
        }
    };
    let renderer = Renderer::new(&RendererOptions {
        backend: args.backend.clone(),
        cpu_timing: false,
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
    let reference = renderer.render_original(
        &shader,
        entry,
        &session,
        &RenderOptions {
            classify: false,
            png_dir: opts.png_dir.clone().filter(|_| !has_variant),
            raw_frames: opts.raw_frames && !has_variant,
            ..opts.clone()
        },
    )?;
    if let Some(dir) = opts.png_dir.as_ref().filter(|_| has_variant) {
        for (i, frame) in reference.frames.iter().enumerate() {
            reproj_replay::output::write_reference_frame(
                dir,
                i as u32,
                reference.width,
                reference.height,
                frame,
            )?;
        }
    }
    let report = match &variant_input {
        None => reference.report,
        Some(input) => {
            let r = renderer.render_variant(&shader, &session, input, &reference, &opts)?;
            // Two single replays taken one after the other are no speed measurement: the
            // timing engine (`reproj bench`) measures the speedup, interleaved, with its interval.
            eprintln!(
                "original: {:.3} ms/frame; variant: {:.3} ms/frame (one replay each; for the speedup with its 95 % interval: reproj bench {} --session {} {})",
                reference.report.frame_ms,
                r.frame_ms,
                args.shader.display(),
                args.session.display(),
                args.variant
                    .as_ref()
                    .map_or_else(|| "VARIANT_DIR".into(), |v| v.display().to_string()),
            );
            r
        }
    };
    if let Some(frames) = frames {
        frames.commit()?;
    }
    // Never a silent NaN: said on stderr whatever the output format.
    let is_variant = report.node.is_some();
    if report.nonfinite_pixels > 0 {
        eprintln!(
            "warning: {} renders {} pixels that are NaN or infinite over the session{}",
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
        );
    }
    if report.nonfinite_reference_pixels > 0 {
        eprintln!(
            "warning: the original renders {} pixels that are NaN or infinite over the session; they are left out of the error",
            report.nonfinite_reference_pixels
        );
    }
    if args.json {
        writeln!(stdout, "{}", serde_json::to_string_pretty(&report)?)?;
    } else {
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
        if let Some(dir) = &args.frames {
            writeln!(stdout, "  PNGs in   {}", dir.display())?;
        }
    }
    Ok(())
}
