//! `reproj bench`: time candidates against the original shader, interleaved in one run
//! (`reproj-bench`), and print each one's median frame time and speedup with its 95 % interval.

use std::io::Write;
use std::path::Path;
use std::time::Duration;

use indicatif::{ProgressBar, ProgressStyle};
use reproj_bench::{Baseline, BenchOptions, BenchReport, Candidate, Subject, bench};
use reproj_models::speedup::StopRule;
use reproj_replay::{RenderOptions, Renderer, RendererOptions, VariantInput};
use reproj_scene::Session;

use super::UserError;
use crate::BenchArgs;

pub fn run(args: &BenchArgs) -> anyhow::Result<()> {
    if args.min_rounds > args.rounds {
        return Err(UserError(format!(
            "--min-rounds {} is more than --rounds {}",
            args.min_rounds, args.rounds
        ))
        .into());
    }
    let input = super::read_shader(&args.shader, args.lang_in, &args.input)?;
    let shader = input.to_wgsl()?;
    let entry = shader.fragment_entry(args.entry.as_deref())?;
    let session = Session::load(&args.session)?;
    let mut candidates = Vec::new();
    for path in &args.candidates {
        candidates.push(candidate(path, &input, &session, args)?);
    }
    let renderer = Renderer::new(&RendererOptions {
        backend: args.backend.clone(),
        cpu_timing: false,
        ..Default::default()
    })?;
    let bar = ProgressBar::new_spinner().with_style(
        ProgressStyle::with_template("{spinner} [{elapsed_precise}] {msg}").expect("template"),
    );
    bar.enable_steady_tick(Duration::from_millis(250));
    bar.set_message("rendering the reference frames");
    let reference = renderer.render_original(
        &shader,
        entry,
        &session,
        &RenderOptions {
            max_frames: args.max_frames,
            classify: false,
            ..Default::default()
        },
    )?;
    let opts = BenchOptions {
        block_frames: args.block,
        stop: StopRule {
            min_rounds: args.min_rounds,
            max_rounds: args.rounds,
            target_half_width: args.target,
            max_seconds: args.max_time,
        },
        max_frames: args.max_frames,
        settle: Some(reproj_bench::DEFAULT_SETTLE),
    };
    let report = bench(
        &renderer,
        Baseline {
            shader: &shader,
            entry,
            reference: &reference,
        },
        &session,
        &candidates,
        &opts,
        &mut |p| {
            let figures: Vec<String> = p
                .estimates
                .iter()
                .map(|e| e.map_or_else(|| "–".into(), |e| e.display()))
                .collect();
            bar.set_message(format!(
                "round {}, {:.1} s: {}",
                p.rounds,
                p.seconds,
                figures.join(", ")
            ));
        },
    )?;
    bar.finish_and_clear();
    let mut out = super::stdout::stdout();
    if args.json {
        writeln!(out, "{}", serde_json::to_string_pretty(&report)?)?;
    } else {
        write_table(&mut out, &report, args)?;
    }
    for w in &report.warnings {
        crate::ui::warn(with_limit_flag(w));
    }
    Ok(())
}

/// A warning of the timing engine, with the flag of this command that raises the limit it names
/// (the engine's text names no flag: `analyze` and `compare` have none).
fn with_limit_flag(warning: &str) -> String {
    match reproj_bench::limit_of(warning) {
        Some(reproj_bench::Limit::Rounds) => format!("{warning} (--rounds)"),
        Some(reproj_bench::Limit::Time) => format!("{warning} (--max-time)"),
        None => warning.to_owned(),
    }
}

/// A candidate from the command line: a variant directory or a shader file.
fn candidate(
    path: &Path,
    original: &reproj_front::Shader,
    session: &reproj_scene::Session,
    args: &BenchArgs,
) -> anyhow::Result<Candidate> {
    let name = path.display().to_string();
    if path.is_dir() {
        if !path.join("manifest.json").is_file() {
            return Err(UserError(format!(
                "{name}: not a variant directory (no manifest.json; `emit` that kept the original writes none)"
            ))
            .into());
        }
        let mut v = VariantInput::from_dir(path, 1)?;
        super::check_variant_shader(original, &args.shader, &v.manifest, path)?;
        v.delta_n = args
            .delta_n
            .or_else(|| emitted_delta_n(path))
            .unwrap_or(v.manifest.params.delta_n);
        // Only variants with a schedule adapt: others in the same run keep their fixed Δn (to
        // time an adaptive variant against fixed periods interleaved).
        if args.adaptive && !v.manifest.params.schedule.is_empty() {
            let (lo, hi) = super::adapt(&mut v, session)?;
            return Ok(Candidate {
                name: format!("{name} (adaptive Δn {lo}..={hi})"),
                subject: Subject::Variant(v),
            });
        }
        return Ok(Candidate {
            name: format!("{name} (Δn {})", v.delta_n),
            subject: Subject::Variant(v),
        });
    }
    if !path.exists() {
        return Err(UserError(format!("{name}: no such file or directory")).into());
    }
    let shader = super::read_shader(path, args.lang_in, &args.input)?.to_wgsl()?;
    let entry = shader.fragment_entry(args.entry.as_deref())?;
    Ok(Candidate {
        name,
        subject: Subject::Shader {
            shader: Box::new(shader),
            entry,
            session: None,
        },
    })
}

/// The Δn `emit` chose for the variant in `dir`, from its report.json.
fn emitted_delta_n(dir: &Path) -> Option<u32> {
    let text =
        reproj_io::read_input_string(&dir.join("report.json"), reproj_io::InputKind::Json).ok()?;
    let v: serde_json::Value = serde_json::from_str(&text).ok()?;
    u32::try_from(v.get("delta_n")?.as_u64()?).ok()
}

fn write_table(out: &mut impl Write, r: &BenchReport, args: &BenchArgs) -> anyhow::Result<()> {
    writeln!(
        out,
        "{} over {}: {} rounds of {} timed frames, {:.1} s",
        args.shader.display(),
        args.session.display(),
        r.rounds,
        r.block_frames,
        r.seconds
    )?;
    writeln!(out, "on {}", r.machine.describe())?;
    if let Some(s) = &r.settling {
        let blocks: Vec<String> = s.blocks_ms.iter().map(|b| format!("{b:.3}")).collect();
        let moved = s.drift().map_or_else(String::new, |d| {
            format!("; {:+.0} % first to last", 100.0 * (d - 1.0))
        });
        writeln!(
            out,
            "clock {} after {} blocks of the original in {:.1} s (ms/frame: {}{moved})",
            if s.settled { "settled" } else { "not settled" },
            s.blocks_ms.len(),
            s.seconds,
            blocks.join(", ")
        )?;
    }
    let width = r
        .candidates
        .iter()
        .map(|c| c.name.chars().count())
        .max()
        .unwrap_or(0)
        .max("original (baseline)".len());
    writeln!(
        out,
        "  {:<width$}  {:>10}  {:<24}  {:>6}  {:>8}",
        "", "ms/frame", "speedup [95 % CI]", "rounds", "outliers"
    )?;
    writeln!(
        out,
        "  {:<width$}  {:>10.3}",
        "original (baseline)", r.baseline.median_ms
    )?;
    for (i, c) in r.candidates.iter().enumerate() {
        let ms = c
            .median_ms
            .map_or_else(|| "–".into(), |m| format!("{m:.3}"));
        let s = r
            .estimate(i)
            .map_or_else(|| "no usable timing".into(), |e| e.display());
        writeln!(
            out,
            "  {:<width$}  {:>10}  {:<24}  {:>6}  {:>8}",
            c.name, ms, s, c.rounds, c.outliers
        )?;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    #[test]
    fn a_limit_warning_names_the_flag_that_raises_it() {
        let w =
            super::with_limit_flag("the interval is wider than ±3 % after the last of 48 rounds");
        assert!(w.ends_with("rounds (--rounds)"), "{w}");
        let w = super::with_limit_flag("the interval is wider than ±3 % after 30 s");
        assert!(w.ends_with("30 s (--max-time)"), "{w}");
        let w = super::with_limit_flag("the machine was busy: a 1.20× [1.00, 1.40]");
        assert!(!w.contains("(--"), "{w}");
    }
}
