//! `reproj report`: one self-contained HTML page of a profile (`reproj-report`).

use std::io::Write;
use std::path::Path;

use reproj_analyze::load_profile;
use reproj_replay::{Renderer, RendererOptions};
use reproj_report::{ReportOptions, report};

use super::UserError;
use crate::ReportArgs;

pub fn run(args: &ReportArgs) -> anyhow::Result<()> {
    let mut stdout = std::io::stdout().lock();
    // Check where the page goes before rendering anything.
    let dir = args
        .out
        .parent()
        .filter(|d| !d.as_os_str().is_empty())
        .unwrap_or(Path::new("."));
    if !dir.is_dir() {
        return Err(UserError(format!(
            "cannot write {}: {} is not a directory",
            args.out.display(),
            dir.display()
        ))
        .into());
    }
    if args.out.is_dir() {
        return Err(UserError(format!(
            "cannot write {}: it is a directory",
            args.out.display()
        ))
        .into());
    }
    let profile = load_profile(&args.profile)?;
    let renderer = Renderer::new(&RendererOptions {
        backend: args.backend.clone(),
        cpu_timing: false,
    })?;
    let opts = ReportOptions {
        session: args.session.clone(),
        shader: args.shader.clone(),
        max_rendered: args.max_rendered,
        timing: Default::default(),
    };
    let start = std::time::Instant::now();
    let mut progress = |line: &str| {
        eprintln!("[{:6.1}s] {line}", start.elapsed().as_secs_f64());
    };
    let html = report(&profile, &args.profile, &opts, &renderer, &mut progress)?;
    reproj_io::write_file(&args.out, html.as_bytes())?;
    writeln!(
        stdout,
        "wrote {} ({} KiB)",
        args.out.display(),
        html.len().div_ceil(1024)
    )?;
    Ok(())
}
