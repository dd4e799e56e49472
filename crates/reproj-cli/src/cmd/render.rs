//! `reproj render`: replay a session for the original shader or one variant.

use std::io::Write;

use reproj_front::{Loaded, load_file_as};
use reproj_instance::{NodeSelector, instance};
use reproj_replay::{RenderOptions, Renderer, RendererOptions, Session, VariantInput};

use super::{UserError, front_error, instance_error, replay_error};
use crate::RenderArgs;

pub fn run(args: &RenderArgs) -> anyhow::Result<()> {
    let mut stdout = std::io::stdout().lock();
    let input = load_file_as(&args.shader, super::lang_in(args.lang_in)).map_err(front_error)?;
    // The replay renders WGSL: a GLSL shader is rendered as naga's WGSL of it.
    let shader = input.to_wgsl().map_err(front_error)?;
    let entry = shader
        .fragment_entry(args.entry.as_deref())
        .map_err(front_error)?;
    let session = Session::load(&args.session).map_err(|e| replay_error(e.into()))?;
    let renderer = Renderer::new(&RendererOptions {
        backend: args.backend.clone(),
        cpu_timing: false,
    })
    .map_err(replay_error)?;
    let opts = RenderOptions {
        png_dir: args.frames.clone(),
        max_frames: args.max_frames,
        classify: true,
        raw_frames: args.raw_frames,
    };
    let reference = renderer
        .render_original(
            &shader,
            entry,
            &session,
            &RenderOptions {
                classify: false,
                ..opts.clone()
            },
        )
        .map_err(replay_error)?;
    let variant_input = match (&args.node, &args.variant) {
        (None, None) => None,
        (Some(node), _) => {
            let sel: NodeSelector = node.parse().map_err(UserError)?;
            let loaded = Loaded::new(input, args.entry.as_deref()).map_err(front_error)?;
            let variant = instance(
                &loaded.shader,
                &loaded.norm,
                &loaded.table,
                sel,
                &super::instance_options(args.cache, args.delta_n.unwrap_or(8)),
            )
            .map_err(instance_error)?;
            Some(VariantInput::new(
                variant.passes.iter().map(|p| p.wgsl.clone()).collect(),
                variant.manifest.clone(),
                args.delta_n.unwrap_or(8),
            ))
        }
        (None, Some(dir)) => {
            let mut input = VariantInput::from_dir(dir, 1).map_err(replay_error)?;
            input.delta_n = args.delta_n.unwrap_or(input.manifest.params.delta_n);
            Some(input)
        }
    };
    let report = match &variant_input {
        None => reference.report,
        Some(input) => {
            let r = renderer
                .render_variant(&shader, &session, input, &reference, &opts)
                .map_err(replay_error)?;
            // Speedup against the original measured in this same run.
            eprintln!(
                "original: {:.3} ms/frame; variant: {:.3} ms/frame; speedup {:.2}x",
                reference.report.frame_ms,
                r.frame_ms,
                if r.frame_ms > 0.0 {
                    reference.report.frame_ms / r.frame_ms
                } else {
                    0.0
                }
            );
            r
        }
    };
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
        writeln!(stdout, "  PSNR      {:.2} dB", report.psnr)?;
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
