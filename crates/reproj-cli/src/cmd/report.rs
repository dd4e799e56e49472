//! `reproj report`: one self-contained HTML page of a profile (`reproj-report`).

use std::io::Write;

use reproj_emit::load_profile;
use reproj_replay::{Renderer, RendererOptions};
use reproj_report::{ReportOptions, report};

use crate::ReportArgs;

/// An existing page at `--out` must be one reproj wrote (its title says so).
const REPORT_PAGE: reproj_io::Owner = reproj_io::Owner::Marker("<title>reproj report");

pub fn run(args: &ReportArgs) -> anyhow::Result<()> {
    let mut stdout = super::stdout::stdout();
    // Check where the page goes before rendering anything: only a page reproj wrote is replaced.
    reproj_io::check_target(&args.out, REPORT_PAGE)?;
    let profile = load_profile(&args.profile)?;
    let renderer = Renderer::new(&RendererOptions {
        backend: args.backend.clone(),
        cpu_timing: false,
        ..Default::default()
    })?;
    let opts = ReportOptions {
        session: args.session.clone(),
        shader: args.shader.clone(),
        max_rendered: args.max_rendered,
        timing: reproj_bench::BenchOptions {
            stop: reproj_models::speedup::StopRule {
                max_seconds: args.max_time,
                min_rounds: args.min_rounds,
                ..Default::default()
            },
            ..Default::default()
        },
        compare: args.compare.clone(),
    };
    let start = std::time::Instant::now();
    let mut progress = |line: &str| {
        crate::ui::note(format_args!(
            "[{:6.1}s] {line}",
            start.elapsed().as_secs_f64()
        ));
    };
    let html = report(&profile, &args.profile, &opts, &renderer, &mut progress)?;
    reproj_io::write_owned_file(&args.out, html.as_bytes(), REPORT_PAGE)?;
    if args.json {
        let out = serde_json::json!({
            "schema": "reproj.report-run",
            "version": 1,
            "out": args.out.display().to_string(),
            "bytes": html.len(),
            "profile": args.profile.display().to_string(),
        });
        writeln!(stdout, "{}", serde_json::to_string_pretty(&out)?)?;
        return Ok(());
    }
    writeln!(
        stdout,
        "wrote {} ({} KiB)",
        args.out.display(),
        html.len().div_ceil(1024)
    )?;
    Ok(())
}
