//! `reproj compare`: reprojection against reduced-resolution rendering and code simplification at
//! equal frame time (the paper's Fig. 10); a table or `compare.json` on stdout, files in `--out`.

use std::io::Write;
use std::path::{Path, PathBuf};

use reproj_compare::{CompareInput, CompareOptions, CompareReport, Target, compare, write_outputs};
use reproj_emit::load_profile;
use reproj_replay::{Renderer, RendererOptions};
use reproj_scene::Session;

use super::UserError;
use super::analyze::{Bar, bar};
use crate::CompareArgs;

/// `reproj compare`: the target, the shader and session, the comparison and its files, the table.
pub fn run(args: &CompareArgs) -> anyhow::Result<()> {
    let target = target(args)?;
    let profile = match &args.profile {
        Some(p) => Some((load_profile(p)?, p.clone())),
        None => None,
    };
    // Node ids are those of the profile's node table: the loops it unrolled are unrolled here.
    let unroll = crate::UnrollArg {
        unroll: profile.as_ref().map_or(0, |(p, _)| p.unroll),
    };
    // And the shader is read as the profile's was, unless told otherwise here.
    let input = match &profile {
        Some((p, path)) if args.input.is_empty() => reproj_emit::profile_shader_input(p, path)?,
        _ => args.input.to_input(),
    };
    let mut loaded = super::load_shader(
        &args.shader,
        args.entry.as_deref(),
        args.lang_in,
        &unroll,
        &input,
    )?;
    // The replay renders WGSL: a GLSL or SPIR-V shader is compared as naga's WGSL of it.
    loaded.shader = loaded.shader.to_wgsl()?;
    let session = Session::load(&args.session)?;
    let stem = args
        .shader
        .file_stem()
        .map_or_else(|| "shader".into(), |s| s.to_string_lossy().into_owned());
    let out = args
        .out
        .clone()
        .unwrap_or_else(|| PathBuf::from("out").join(format!("compare-{stem}")));
    let renderer = Renderer::new(&RendererOptions {
        backend: args.backend.clone(),
        cpu_timing: false,
        ..Default::default()
    })?;
    crate::ui::note(format_args!(
        "comparing {} over {} on {} ({} cores, LP_NUM_THREADS={}) at {}",
        args.shader.display(),
        args.session.display(),
        renderer.adapter().name,
        std::thread::available_parallelism().map_or(1, |n| n.get()),
        std::env::var("LP_NUM_THREADS").unwrap_or_else(|_| "unset".into()),
        match target {
            Target::Speedup(x) => format!("{x}×"),
            Target::Budget(e) => format!("reproj's predicted speedup under error {e}"),
        }
    ));
    let input = CompareInput {
        loaded: &loaded,
        entry: args.entry.as_deref(),
        session: &session,
        profile: profile.as_ref().map(|(p, path)| (p, path.as_path())),
    };
    let opts = CompareOptions {
        target,
        max_frames: args.max_frames,
        resize: reproj_compare::resize::ResizeOptions {
            tries: args.resize_tries,
            ..Default::default()
        },
        simplify: reproj_compare::simplify::SimplifyOptions {
            candidates: args.candidates,
            max_steps: args.max_steps,
        },
        max_delta_n: args.max_delta_n,
        reproj_tries: args.reproj_tries,
        supersample: args.supersample,
        temporal: !args.no_temporal,
        ..Default::default()
    };
    let mut result = compare(&renderer, &input, &opts, &Bar(bar()))?;
    for w in write_outputs(&mut result, &out)? {
        crate::ui::warn(w);
    }
    for w in &result.report.timing_warnings {
        crate::ui::warn(w);
    }
    print_table(&result.report, &out, args.json)
}

/// What every method aims at: `--speedup` (checked here, a number above 1) or reproj's own
/// selection under `--max-error` (a [`reproj_emit::Budget`], checked by clap).
fn target(args: &CompareArgs) -> Result<Target, UserError> {
    match (args.speedup, args.max_error) {
        (Some(x), _) if !(x.is_finite() && x > 1.0) => Err(UserError(format!(
            "--speedup must be a number above 1, got {x}"
        ))),
        (Some(x), _) => Ok(Target::Speedup(x)),
        (None, Some(e)) => Ok(Target::Budget(e)),
        (None, None) => Err(UserError("give --speedup or --max-error".into())),
    }
}

/// The comparison on stdout: `compare.json` with `--json`, else the table of methods.
fn print_table(r: &CompareReport, out: &Path, json: bool) -> anyhow::Result<()> {
    let mut stdout = super::stdout::stdout();
    if json {
        writeln!(stdout, "{}", serde_json::to_string_pretty(r)?)?;
        return Ok(());
    }
    writeln!(
        stdout,
        "{}: {} frames at {}×{} on {}; original {:.3} ms/frame; target {:.2}×{}",
        r.shader,
        r.frames,
        r.resolution[0],
        r.resolution[1],
        r.adapter,
        r.original_ms,
        r.target_speedup,
        r.max_error.map_or_else(String::new, |e| format!(
            " (reproj's predicted speedup under error {e})"
        ))
    )?;
    if let Some(on) = &r.measured_on {
        writeln!(stdout, "speeds timed interleaved on {on}")?;
    }
    let ss = if r.supersample > 0 {
        format!("vs {} spp", r.supersample)
    } else {
        String::new()
    };
    writeln!(
        stdout,
        "{:<9} {:>8} {:<14} {:>10} {:>9} {:>7} {:>13} {:>13}  setting",
        "method", "speedup", "[95 % CI]", "L2", "PSNR dB", "ꟻLIP", "still/moving", ss
    )?;
    let split = |s: Option<reproj_compare::Split>| {
        s.map_or("-".into(), |s| {
            format!("{:.1}/{:.1}", s.still_psnr, s.moving_psnr)
        })
    };
    let against = |a: Option<&reproj_compare::Against>| {
        a.map_or(String::new(), |a| {
            format!(
                "{:.1} dB {}",
                a.psnr,
                a.flip.map_or("-".into(), |f| format!("{f:.3}"))
            )
        })
    };
    if let Some(o) = &r.original_vs_supersampled {
        writeln!(
            stdout,
            "{:<9} {:>8} {:<14} {:>10} {:>9} {:>7} {:>13} {:>13}  the one-sample original: every method's floor against the supersampled reference",
            "original",
            "1.00×",
            "",
            "",
            "",
            "",
            "",
            against(Some(o))
        )?;
    }
    for m in &r.methods {
        writeln!(
            stdout,
            "{:<9} {:>7.2}{} {:<14} {:>10.5} {:>9.2} {:>7} {:>13} {:>13}  {}",
            m.method,
            m.speedup,
            if m.reached_target { "×" } else { "!" },
            m.speedup_ci95
                .map_or_else(String::new, |[lo, hi]| format!("[{lo:.2}, {hi:.2}]")),
            m.scores.error,
            m.scores.psnr,
            m.scores.flip.map_or("-".into(), |f| format!("{f:.4}")),
            split(m.scores.split),
            against(m.scores.supersampled.as_ref()),
            m.setting
        )?;
    }
    for n in &r.notes {
        writeln!(stdout, "note: {n}")?;
    }
    if r.reproj.is_none() {
        writeln!(stdout, "(no --profile: reproj's own choice not compared)")?;
    }
    if let Some(m) = r.reproj.as_ref().and_then(|d| d.rematch.as_ref()) {
        let what = if m.moved {
            "written above, every method timed again"
        } else {
            "the period written above already"
        };
        writeln!(
            stdout,
            "equal time: the first timing put reproj at {:.2}× against resizing's {:.2}×; its node's period for {:.2}× (its models scaled by that timing): {what}",
            m.from_speedup, m.to_speedup, m.to_speedup
        )?;
    }
    writeln!(
        stdout,
        "! = target speedup not reached; files in {}",
        out.display()
    )?;
    Ok(())
}
