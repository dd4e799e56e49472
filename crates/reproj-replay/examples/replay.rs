//! Render a shader over a session (and optionally a variant directory) and print the report.
//!
//! `cargo run -p reproj-replay --example replay -- SHADER SESSION [--png DIR] [--variant DIR --delta-n N] [--frames N] [--eps E]`
use std::path::PathBuf;

use reproj_replay::{RenderOptions, Renderer, RendererOptions, VariantInput};
use reproj_scene::Session;

fn main() {
    if let Err(e) = run() {
        eprintln!("error: {e}");
        std::process::exit(1);
    }
}

fn run() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let (mut pos, mut png, mut variant, mut dn, mut frames, mut eps) =
        (Vec::new(), None, None, 8u32, None, None);
    let mut i = 0;
    while i < args.len() {
        match args[i].as_str() {
            "--png" => {
                i += 1;
                png = Some(PathBuf::from(&args[i]));
            }
            "--variant" => {
                i += 1;
                variant = Some(PathBuf::from(&args[i]));
            }
            "--delta-n" => {
                i += 1;
                dn = args[i].parse()?;
            }
            "--frames" => {
                i += 1;
                frames = Some(args[i].parse()?);
            }
            "--eps" => {
                i += 1;
                eps = Some(args[i].parse::<f32>()?);
            }
            a => pos.push(a.to_owned()),
        }
        i += 1;
    }
    if pos.len() != 2 {
        return Err(
            "usage: replay SHADER SESSION [--png DIR] [--variant DIR --delta-n N] [--frames N]"
                .into(),
        );
    }
    let shader = reproj_front::load_file(pos[0].as_ref())?;
    let entry = shader.fragment_entry(None)?;
    let session = Session::load(&pos[1])?;
    let r = Renderer::new(&RendererOptions::default())?;
    let mut opts = RenderOptions {
        max_frames: frames,
        ..Default::default()
    };
    if variant.is_none() {
        opts.png_dir = png.clone();
    }
    let t = std::time::Instant::now();
    let reference = r.render_original(&shader, entry, &session, &opts)?;
    let rep = &reference.report;
    eprintln!(
        "original: {} frames in {:.2} s wall; mean frame {:.3} ms ({:?}), cpu {:.3} ms, adapter {}",
        rep.frames.len(),
        t.elapsed().as_secs_f64(),
        rep.frame_ms,
        rep.timing,
        rep.cpu_ms,
        rep.adapter.name
    );
    if let Some(dir) = variant {
        let mut v = VariantInput::from_dir(&dir, dn)?;
        if let Some(e) = eps {
            v.depth_epsilon = e;
        }
        opts.png_dir = png;
        let t = std::time::Instant::now();
        let report = r.render_variant(&shader, &session, &v, &reference, &opts)?;
        eprintln!("variant: {:.2} s wall", t.elapsed().as_secs_f64());
        println!("{}", serde_json::to_string_pretty(&report)?);
    } else {
        println!("{}", serde_json::to_string_pretty(rep)?);
    }
    Ok(())
}
