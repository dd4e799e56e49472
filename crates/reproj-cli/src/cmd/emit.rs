//! `reproj emit`: pick the fastest node and Δn under an error budget and write the passes.

use std::io::Write;
use std::path::PathBuf;

use reproj_emit::{DELTA_N_RANGE, EmitOptions, EmitReport, emit, latest_profile, load_profile};
use reproj_models::Profile;
use reproj_scene::Session;

use super::{UserError, cache_format};
use crate::EmitArgs;

/// `reproj emit`: the inputs, the selection and its passes, `--verify`, the bars, the report.
pub fn run(args: &EmitArgs) -> anyhow::Result<()> {
    let mut stdout = super::stdout::stdout();
    let Inputs {
        profile_path,
        profile,
        session,
        opts,
    } = inputs(args)?;
    let (mut report, mut variant) = emit(&profile, &profile_path, &opts)?;
    for w in report.motion.iter().flat_map(|m| &m.warnings) {
        crate::ui::warn(w);
    }
    if args.verify {
        let (session, _, _) = session
            .as_ref()
            .expect("clap requires --session with --verify");
        verify_selection(
            &mut report,
            &mut variant,
            (&profile, &profile_path),
            &opts,
            session,
            args,
        )?;
    }
    for w in &report.timing_warnings {
        crate::ui::warn(w);
    }
    let unmet = gate(&report, args);
    if args.json {
        writeln!(stdout, "{}", serde_json::to_string_pretty(&report)?)?;
        return unmet.map_or(Ok(()), Err);
    }
    print_choice(&mut stdout, &report, &profile)?;
    print_runoff(&mut stdout, &report)?;
    print_measured(&mut stdout, &report)?;
    writeln!(stdout, "wrote    {}", report.files.join(", "))?;
    unmet.map_or(Ok(()), Err)
}

/// What `emit` works from: the profiles, the session the variant is for (with its motion and
/// hash) and the library's options.
struct Inputs {
    profile_path: PathBuf,
    profile: Profile,
    session: Option<(Session, Option<reproj_models::motion::Motion>, String)>,
    opts: EmitOptions,
}

/// Read the profiles (the newest one here without `--profile`) and the session, and turn the
/// arguments into [`EmitOptions`]; nothing is written yet.
fn inputs(args: &EmitArgs) -> anyhow::Result<Inputs> {
    let profile_path = match args.profile.first() {
        Some(p) => p.clone(),
        None => {
            let p = latest_profile(&PathBuf::from("."))?;
            crate::ui::note(format!("using the newest profile here: {}", p.display()));
            p
        }
    };
    let profile = load_profile(&profile_path)?;
    let mut also = Vec::new();
    for p in args.profile.iter().skip(1) {
        also.push((p.clone(), load_profile(p)?));
    }
    let stem = std::path::Path::new(&profile.shader.path)
        .file_stem()
        .map_or_else(
            || "shader".to_string(),
            |s| s.to_string_lossy().into_owned(),
        );
    let out = args
        .out
        .clone()
        .unwrap_or_else(|| PathBuf::from("out").join(&stem));
    // The session the variant is for: loaded before anything is written, its motion measured.
    let session = match &args.session {
        Some(path) => {
            let session = Session::load(path)?;
            let bytes = reproj_io::read_input(path, reproj_io::InputKind::Json)?;
            let motion = reproj_emit::motion::measure(&session, None);
            Some((session, motion, reproj_models::content_hash(&bytes)))
        }
        None => None,
    };
    let target = match (&session, &args.session) {
        (Some((_, Some(motion), hash)), Some(path)) if args.motion == crate::MotionUse::Carry => {
            Some(reproj_emit::motion::TargetSession {
                name: path.display().to_string(),
                hash: hash.clone(),
                motion: motion.clone(),
            })
        }
        _ => None,
    };
    let opts = EmitOptions {
        max_error: args.max_error,
        metric: args.metric,
        min_delta_n: *DELTA_N_RANGE.start(),
        max_delta_n: args.max_delta_n,
        out,
        cache_format: args.cache_format.map(cache_format),
        strategy: args.strategy.map(super::strategy),
        node: match args.node.as_deref() {
            None => None,
            Some("root") => Some(reproj_emit::NodeChoice::Root),
            Some(id) => Some(reproj_emit::NodeChoice::Id(id.parse().map_err(|_| {
                UserError(format!("--node {id}: a node id (a number) or `root`"))
            })?)),
        },
        integration: super::integrate(Default::default(), &args.integration),
        shader: args.shader.clone(),
        outputs: super::outputs(&args.lang, &args.overrides),
        also,
        target,
        period: if args.adaptive {
            reproj_emit::motion::PeriodChoice::Adaptive
        } else {
            reproj_emit::motion::PeriodChoice::Fixed
        },
    };
    Ok(Inputs {
        profile_path,
        profile,
        session,
        opts,
    })
}

/// The table's first part: the profile, the budget and what was selected (or why the original
/// is kept), with the predictions per session or the adaptive schedule.
fn print_choice(
    stdout: &mut impl Write,
    report: &EmitReport,
    profile: &Profile,
) -> std::io::Result<()> {
    writeln!(
        stdout,
        "profile  {} ({} on {})",
        report.profile, report.shader, report.adapter
    )?;
    writeln!(
        stdout,
        "budget   {} ≤ {}",
        metric_label(report.metric),
        report.max_error
    )?;
    let (Some(node), Some(dn)) = (&report.node, report.delta_n) else {
        return writeln!(
            stdout,
            "kept the original shader: {}",
            report
                .reason
                .as_deref()
                .unwrap_or("no node fits the budget")
        );
    };
    writeln!(
        stdout,
        "selected node {node} `{}` (line {}:{}) at Δn = {dn}, strategy {}",
        report.node_text.as_deref().unwrap_or(""),
        report.line.unwrap_or(0),
        report.col.unwrap_or(0),
        report.strategy.as_deref().unwrap_or("3pass")
    )?;
    writeln!(
        stdout,
        "predicted {} {:.5}{}, {:.3} ms/frame vs {:.3} ms original: {:.2}x{}",
        metric_label(report.metric),
        report.predicted_error.unwrap_or(0.0),
        report
            .predicted_psnr
            .map_or_else(String::new, |p| format!(" (PSNR {p:.2} dB)")),
        report.predicted_ms.unwrap_or(0.0),
        report.original_ms,
        report.predicted_speedup.unwrap_or(0.0),
        report
            .predicted_speedup_ci95
            .map_or_else(String::new, |[lo, hi]| format!(" [{lo:.2}, {hi:.2}]")),
    )?;
    if let Some(a) = &report.adaptive {
        writeln!(
            stdout,
            "adaptive  Δn {}–{} by motion over the {} frames of {} (worst frame predicted {:.5}, mean {:.5}){}",
            a.delta_n_min,
            a.delta_n_max,
            a.frames,
            a.trace,
            a.predicted_worst_error,
            a.predicted_mean_error,
            match (&a.fixed_node, a.fixed_delta_n, a.fixed_predicted_speedup) {
                (Some(n), Some(dn), Some(s)) => {
                    format!("; the fastest fixed choice: node {n} at Δn {dn}, {s:.2}x")
                }
                _ => String::new(),
            }
        )?;
    } else {
        for sp in &report.sessions {
            writeln!(
                stdout,
                "  on {}: {} {:.5}, {:.3} ms/frame vs {:.3} ms original: {:.2}x",
                sp.session,
                metric_label(report.metric),
                sp.predicted_error,
                sp.predicted_ms,
                sp.original_ms,
                sp.predicted_speedup
            )?;
        }
    }
    if profile.machine.cpu_rasterizer {
        writeln!(
            stdout,
            "          (profiled on {}, a CPU rasterizer: GPU figures differ)",
            profile.machine.adapter
        )?;
    }
    Ok(())
}

/// The runoff, where one ran: each contender's predicted and measured speedup, the written one
/// marked.
fn print_runoff(stdout: &mut impl Write, report: &EmitReport) -> std::io::Result<()> {
    let Some(r) = &report.runoff else {
        return Ok(());
    };
    writeln!(
        stdout,
        "runoff    {} nodes predicted too close to tell apart, timed together ({} rounds){}:",
        r.entries.len(),
        r.rounds,
        if r.changed {
            "; the fastest measured replaces the prediction's choice"
        } else {
            ""
        }
    )?;
    for e in &r.entries {
        let ci = |c: Option<[f64; 2]>| {
            c.map_or_else(String::new, |[lo, hi]| format!(" [{lo:.2}, {hi:.2}]"))
        };
        writeln!(
            stdout,
            "  {} node {} ({}, Δn {}, predicted error {:.5}): predicted {:.2}x{}, measured {}{}",
            if e.written { "→" } else { " " },
            e.node,
            e.strategy,
            e.delta_n,
            e.predicted_error,
            e.predicted_speedup,
            ci(e.predicted_speedup_ci95),
            e.measured_speedup
                .map_or_else(|| "nothing".to_string(), |s| format!("{s:.2}x")),
            ci(e.measured_speedup_ci95),
        )?;
    }
    Ok(())
}

/// The table's second part, after `--verify`: the measured error and speedup, the worst band of
/// an adaptive schedule, the motion carried to the session, and the perceptual metrics.
fn print_measured(stdout: &mut impl Write, report: &EmitReport) -> std::io::Result<()> {
    if report.node.is_none() && report.measured_error.is_some() {
        writeln!(
            stdout,
            "measured  the original shader is kept: nothing to time against it ({:.3} ms/frame on this session, one render)",
            report.measured_original_ms.unwrap_or(0.0),
        )?;
        if let Some(on) = &report.measured_on {
            writeln!(stdout, "measured on {on}")?;
        }
        return Ok(());
    }
    if let (Some(e), Some(s)) = (report.measured_error, report.measured_speedup) {
        let ci = report
            .measured_speedup_ci95
            .map_or_else(String::new, |[lo, hi]| format!(" [{lo:.2}, {hi:.2}]"));
        writeln!(
            stdout,
            "measured  error {e:.5}{}, {:.3} ms/frame vs {:.3} ms original: {s:.2}x{ci}{}",
            report
                .measured_psnr
                .map_or_else(String::new, |p| format!(" (PSNR {p:.2} dB)")),
            report.measured_ms.unwrap_or(0.0),
            report.measured_original_ms.unwrap_or(0.0),
            report
                .measured_rounds
                .map_or_else(String::new, |r| format!(" (interleaved, {r} rounds)")),
        )?;
        if let Some(on) = &report.measured_on {
            writeln!(stdout, "measured on {on}")?;
        }
        if let Some(b) = report.adaptive.as_ref().and_then(|a| a.measured_worst_band)
            && report.metric == reproj_models::Metric::L2
        {
            writeln!(
                stdout,
                "measured  worst band: error {:.5} over the {} frames at Δn {}",
                b.error, b.frames, b.delta_n
            )?;
        }
        print_motion(stdout, report, e)?;
        if let Some(n) = report.measured_nonfinite_reference_pixels {
            crate::ui::warn(format_args!(
                "the original shader renders {n} pixels that are NaN or infinite on this session; they are left out of the measured error"
            ));
        }
    }
    if let (Some(f), Some(s)) = (report.measured_flip, report.measured_ssim) {
        writeln!(
            stdout,
            "measured  ꟻLIP {:.5} (worst {:.5}, frame {}), SSIM {:.5} (worst {:.5}, frame {})",
            f.mean, f.worst.value, f.worst.frame, s.mean, s.worst.value, s.worst.frame
        )?;
    }
    Ok(())
}

/// The motion line: the error predicted on the verified session (carried from a profiled one)
/// against the measured `e`.
fn print_motion(stdout: &mut impl Write, report: &EmitReport, e: f64) -> std::io::Result<()> {
    if let (Some(m), Some(p), Some(t)) = (
        &report.motion,
        report
            .motion
            .as_ref()
            .and_then(|m| m.target_predicted_error),
        report.motion.as_ref().and_then(|m| m.target.as_ref()),
    ) && report.metric == reproj_models::Metric::L2
    {
        writeln!(
            stdout,
            "motion    {} px/frame on this session; predicted here {p:.5} before rendering (carried from {}, r = {:.2}, β = {:.1} {}): measured {}",
            format_args!("{:.2}", t.pixels_per_frame),
            m.carried_from.as_deref().unwrap_or("?"),
            m.period_scale.unwrap_or(1.0),
            m.exponent.beta,
            match m.exponent.source {
                reproj_models::motion::ExponentSource::Fitted => "fitted",
                reproj_models::motion::ExponentSource::Assumed => "assumed",
            },
            // A ratio of two errors far under the budget says nothing about the promise.
            if p.max(e) < report.max_error * 0.1 {
                "both under a tenth of the budget".to_string()
            } else {
                format!("{:+.0} %", (e / p - 1.0) * 100.0)
            }
        )?;
    }
    Ok(())
}

/// `--verify`: the runoff first (the nodes predicted too close to the choice, timed together;
/// the fastest measured is written in its place), then re-render the written selection and time
/// it against the original (the timing engine).
#[cfg(feature = "gpu")]
fn verify_selection(
    report: &mut reproj_emit::EmitReport,
    variant: &mut Option<reproj_instance::Variant>,
    (profile, profile_path): (&reproj_models::Profile, &std::path::Path),
    opts: &EmitOptions,
    session: &Session,
    args: &EmitArgs,
) -> anyhow::Result<()> {
    use reproj_replay::{Renderer, RendererOptions};
    let renderer = Renderer::new(&RendererOptions {
        backend: args.backend.clone(),
        cpu_timing: false,
        ..Default::default()
    })?;
    let timing = reproj_bench::BenchOptions::default();
    let contenders =
        reproj_emit::contenders(profile, profile_path, opts, report, args.runoff as usize)?;
    if !contenders.is_empty() {
        let bar = if args.json || crate::ui::quiet() {
            indicatif::ProgressBar::hidden()
        } else {
            indicatif::ProgressBar::new_spinner().with_style(
                indicatif::ProgressStyle::with_template("{spinner} [{elapsed_precise}] {msg}")
                    .expect("valid template"),
            )
        };
        bar.enable_steady_tick(std::time::Duration::from_millis(250));
        let what = format!(
            "runoff: {} nodes predicted too close to tell apart, timed together",
            contenders.len()
        );
        bar.set_message(what.clone());
        let (runoff, winner) = reproj_analyze::runoff(
            &contenders,
            report,
            (profile, profile_path),
            session,
            &renderer,
            &timing,
            &mut |p| bar.set_message(format!("{what}: round {}", p.rounds)),
        )?;
        bar.finish_and_clear();
        if runoff.changed {
            let forced = contenders[winner].emit_options(opts);
            (*report, *variant) = emit(profile, profile_path, &forced)?;
        }
        report.runoff = Some(runoff);
    }
    reproj_analyze::verify(
        report,
        &opts.out,
        variant.as_ref(),
        (profile, profile_path),
        session,
        &renderer,
        &timing,
    )?;
    // Never a shader slower than the one it replaces: the original is written instead.
    if let Some(reason) = slower_beyond_doubt(report).filter(|_| variant.is_some()) {
        *report = reproj_emit::keep_original(profile, profile_path, opts, &reason, report)?;
        *variant = None;
    }
    Ok(())
}

/// Why a verified choice is not written: its measured speedup's whole 95 % interval below 1×
/// (slower than the original beyond doubt; noise alone never rejects it).
#[cfg(any(feature = "gpu", test))]
fn slower_beyond_doubt(report: &reproj_emit::EmitReport) -> Option<String> {
    let (s, [lo, hi]) = (report.measured_speedup?, report.measured_speedup_ci95?);
    (hi < 1.0).then(|| {
        format!(
            "the choice ({} {} at Δn {}) verified slower than the original beyond doubt: {s:.2}x [{lo:.2}, {hi:.2}] over {} rounds; the original is kept",
            report.node.as_deref().map_or_else(|| "node ?".into(), |n| format!("node {n}")),
            report.strategy.as_deref().unwrap_or("?"),
            report.delta_n.unwrap_or(0),
            report.measured_rounds.unwrap_or(0),
        )
    })
}

/// `--verify` renders: a build without the `gpu` feature says so (exit 2).
#[cfg(not(feature = "gpu"))]
fn verify_selection(
    _: &mut reproj_emit::EmitReport,
    _: &mut Option<reproj_instance::Variant>,
    _: (&reproj_models::Profile, &std::path::Path),
    _: &EmitOptions,
    _: &Session,
    _: &EmitArgs,
) -> anyhow::Result<()> {
    Err(super::needs_gpu("emit --verify"))
}

/// The bars a run must pass, in order: a verified error within the budget (exit 4 otherwise, with
/// a warning naming a tighter budget: the budget is a promise), then `--min-speedup` — on the
/// lower end of the measured speedup's 95 % interval with `--verify` (noise never passes a bar),
/// on the prediction without (exit 3).
fn gate(report: &reproj_emit::EmitReport, args: &EmitArgs) -> Option<anyhow::Error> {
    let measured = match report.metric {
        // Adaptive: every band of the schedule promises the budget, the worst one included.
        reproj_models::Metric::L2 => report.measured_error.map(|e| {
            report
                .adaptive
                .as_ref()
                .and_then(|a| a.measured_worst_band)
                .map_or(e, |b| e.max(b.error))
        }),
        reproj_models::Metric::Flip => report.measured_flip.map(|f| f.mean),
    };
    if let Some(n) = report.measured_nonfinite_pixels {
        let o = super::OverBudget(format!(
            "the variant renders {n} pixels that are NaN or infinite where the original is finite: no budget holds; emit a tighter budget or fix the node's math"
        ));
        crate::ui::warn(&o);
        return Some(o.into());
    }
    if let Some(e) = measured.filter(|e| !e.is_finite() || *e > report.max_error) {
        let session = args
            .session
            .as_ref()
            .map_or_else(|| "the session".into(), |p| p.display().to_string());
        let what = metric_label(report.metric);
        let o = if e.is_finite() {
            let safer = report.max_error * (report.max_error / e) * 0.95;
            super::OverBudget(format!(
                "verified {what} {e:.5} is over the budget {} on {session}: the choice does not hold there; the next safe choice: `reproj emit --max-error {safer:.3e}` (or profile this session too)",
                report.max_error
            ))
        } else {
            super::OverBudget(format!(
                "verified {what} is not a number on {session}: the variant produces non-finite pixels there; no budget holds"
            ))
        };
        crate::ui::warn(&o);
        return Some(o.into());
    }
    let min = args.min_speedup?;
    let (speedup, how) = match (
        report.measured_speedup,
        report.measured_speedup_ci95,
        report.predicted_speedup,
    ) {
        (Some(s), Some([lo, hi]), _) => (
            lo,
            format!("measured speedup {s:.2}x [{lo:.2}, {hi:.2}]: its lower bound"),
        ),
        (Some(s), None, _) => (s, format!("measured speedup {s:.2}x")),
        (None, _, Some(s)) => (s, format!("predicted speedup {s:.2}x")),
        (None, _, None) => (1.0, "kept the original: speedup 1.00x".to_string()),
    };
    (speedup < min).then(|| {
        super::Unmet(format!(
            "{how} is below --min-speedup {min} at error ≤ {}",
            report.max_error
        ))
        .into()
    })
}

fn metric_label(metric: reproj_models::Metric) -> &'static str {
    match metric {
        reproj_models::Metric::L2 => "error",
        reproj_models::Metric::Flip => "ꟻLIP",
    }
}

#[cfg(test)]
mod tests;
