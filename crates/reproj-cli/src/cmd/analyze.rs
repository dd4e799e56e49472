//! `reproj analyze`: profile the nodes over a session and save the profile and its charts.

use std::io::Write;
use std::path::PathBuf;
use std::time::Duration;

use indicatif::{ProgressBar, ProgressStyle};
use reproj_analyze::{AnalyzeInput, AnalyzeOptions, Progress, PruneOptions, analyze};
use reproj_replay::{Renderer, RendererOptions};
use reproj_scene::Session;

use crate::AnalyzeArgs;

/// A progress bar with ETA on stderr; without a terminal, one line per step instead.
pub(crate) struct Bar(pub(crate) ProgressBar);

impl Progress for Bar {
    fn start(&self, total: u64) {
        self.0.set_length(total);
        self.0.enable_steady_tick(Duration::from_millis(250));
    }
    fn step(&self, what: &str) {
        self.0.set_message(what.to_string());
        self.0.inc(1);
        if self.0.is_hidden() {
            // No terminal (CI, a log file): one line per finished replay.
            let (pos, len) = (self.0.position(), self.0.length().unwrap_or(0));
            let elapsed = self.0.elapsed().as_secs_f64();
            let eta = if pos > 0 {
                elapsed / pos as f64 * len.saturating_sub(pos) as f64
            } else {
                0.0
            };
            crate::ui::note(format_args!(
                "[{pos}/{len}] {what}: {elapsed:.1} s elapsed, ETA {eta:.0} s"
            ));
        }
    }
    fn note(&self, line: &str) {
        if self.0.is_hidden() {
            crate::ui::note(line);
        } else {
            self.0.println(line);
        }
    }
    fn extend(&self, more: u64) {
        self.0.inc_length(more);
    }
    fn finish(&self) {
        self.0.finish_and_clear();
    }
}

/// The progress bar of a command that replays (analyze, compare).
pub(crate) fn bar() -> ProgressBar {
    if crate::ui::quiet() {
        return ProgressBar::hidden();
    }
    ProgressBar::new(0).with_style(
        ProgressStyle::with_template(
            "{spinner} [{elapsed_precise}] {bar:30} {pos}/{len} replays, ETA {eta} {msg}",
        )
        .expect("valid template"),
    )
}

pub fn run(args: &AnalyzeArgs) -> anyhow::Result<()> {
    let mut stdout = super::stdout::stdout();
    let loaded = super::load_shader(
        &args.shader,
        args.entry.as_deref(),
        args.lang_in,
        &args.unroll,
        &args.input.to_input(),
    )?;
    if let Some(lines) = super::no_cacheable_lines(&loaded.table) {
        // Nothing to profile: an honest answer, exit 0 without a profile.
        if args.json {
            let out = AnalyzeOutput {
                schema: ANALYZE_SCHEMA,
                version: ANALYZE_VERSION,
                profiles: Vec::new(),
                no_cacheable: lines,
            };
            writeln!(stdout, "{}", serde_json::to_string_pretty(&out)?)?;
            return Ok(());
        }
        for line in lines {
            writeln!(stdout, "{line}")?;
        }
        writeln!(
            stdout,
            "no profile written: keep the original shader (`emit` has nothing to choose from)"
        )?;
        return Ok(());
    }
    let stem = args.shader.file_stem().map_or_else(
        || "shader".to_string(),
        |s| s.to_string_lossy().into_owned(),
    );
    let out = args
        .out
        .clone()
        .unwrap_or_else(|| PathBuf::from(format!("{stem}.profile.json")));
    // One profile per session: the first at `out`, each further one beside it, named after its
    // session (`marble.profile.json`, `marble.marble_fast.profile.json`).
    let outs: Vec<PathBuf> = args
        .session
        .iter()
        .enumerate()
        .map(|(i, s)| {
            if i == 0 {
                out.clone()
            } else {
                session_profile(&out, s)
            }
        })
        .collect();
    let mut locks = Vec::new();
    for out in &outs {
        // Before minutes of rendering: the profile (and its charts) can be written, replacing
        // only reproj's own files.
        reproj_io::check_target(out, super::PROFILE_FILE)?;
        // One analysis per profile at a time: a second one would skew this one's timings and
        // race for the journal and the file. Held until the profile is written.
        locks.push(reproj_io::OutputLock::acquire(out)?);
        if !args.no_charts {
            super::charts::check_targets(out)?;
        }
    }
    // The replay renders WGSL: a GLSL shader is analyzed as naga's WGSL of it.
    let shader = loaded.shader.to_wgsl()?;
    let mut profiles = Vec::new();
    for (session_path, out) in args.session.iter().zip(&outs) {
        let written = analyze_session(args, &loaded, &shader, session_path, out)?;
        if !args.json {
            print_summary(&mut stdout, &written)?;
        }
        profiles.push(written);
    }
    drop(locks);
    if args.json {
        let out = AnalyzeOutput {
            schema: ANALYZE_SCHEMA,
            version: ANALYZE_VERSION,
            profiles,
            no_cacheable: Vec::new(),
        };
        writeln!(stdout, "{}", serde_json::to_string_pretty(&out)?)?;
        return Ok(());
    }
    let profiles: Vec<String> = outs
        .iter()
        .map(|o| format!("--profile {}", o.display()))
        .collect();
    writeln!(
        stdout,
        "next: reproj emit --max-error 0.01 {}",
        profiles.join(" ")
    )?;
    Ok(())
}

/// `analyze --json`'s schema name and version (docs/SCHEMAS.md).
const ANALYZE_SCHEMA: &str = "reproj.analyze";
const ANALYZE_VERSION: u32 = 1;

/// `analyze --json`: what was written, one entry per session (the profiles hold the rest).
#[derive(serde::Serialize)]
struct AnalyzeOutput {
    schema: &'static str,
    version: u32,
    profiles: Vec<Written>,
    /// Why nothing was profiled, when the shader has no cacheable node (then `profiles` is empty).
    #[serde(skip_serializing_if = "Vec::is_empty")]
    no_cacheable: Vec<String>,
}

/// One profile written.
#[derive(serde::Serialize)]
struct Written {
    profile: String,
    session: String,
    nodes: usize,
    usable: usize,
    sets: usize,
    delta_n_train: Vec<u32>,
    delta_n_holdout: Vec<u32>,
    frames: u32,
    resolution: [u32; 2],
    original_frame_ms: f64,
    hit_rate_mu: Option<f64>,
    seconds: f64,
    charts: Vec<String>,
    /// The most caching can give on this device (profile `ceiling`); where `pays` is false no
    /// node was profiled.
    #[serde(skip_serializing_if = "Option::is_none")]
    ceiling: Option<reproj_models::profile::Ceiling>,
    #[serde(skip)]
    time: reproj_models::profile::AnalysisTime,
}

/// The text summary of one profile written.
fn print_summary(stdout: &mut impl Write, w: &Written) -> anyhow::Result<()> {
    if let Some(c) = &w.ceiling {
        writeln!(stdout, "ceiling  {c}")?;
        if !c.pays {
            writeln!(
                stdout,
                "no node profiled: `reproj emit` keeps the original shader, with this reason (time {:.1} s)",
                w.seconds
            )?;
            writeln!(stdout, "wrote {}", w.profile)?;
            return Ok(());
        }
    }
    writeln!(
        stdout,
        "profiled {} nodes ({} usable) at Δn {:?} (+ held out {:?}) over {} frames at {}x{}",
        w.nodes,
        w.usable,
        w.delta_n_train,
        w.delta_n_holdout,
        w.frames,
        w.resolution[0],
        w.resolution[1]
    )?;
    writeln!(
        stdout,
        "original {:.3} ms/frame; hit-rate model µ = {}",
        w.original_frame_ms,
        w.hit_rate_mu
            .map_or_else(|| "n/a".into(), |m| format!("{m:.3}"))
    )?;
    let t = &w.time;
    writeln!(
        stdout,
        "time {:.1} s: reference {:.1} s, rendering {:.1} s, readback+error+compile {:.1} s, fitting {:.2} s, instancing {:.2} s",
        t.total_s,
        t.reference_s,
        t.rendering_s,
        t.readback_and_error_s,
        t.fitting_s,
        t.instancing_s
    )?;
    writeln!(stdout, "wrote {}", w.profile)?;
    if !w.charts.is_empty() {
        writeln!(stdout, "charts {}", w.charts.join(", "))?;
    }
    Ok(())
}

/// Where the profile of a further session goes: beside `out`, named after the session.
fn session_profile(out: &std::path::Path, session: &std::path::Path) -> PathBuf {
    let name = out
        .file_name()
        .map_or_else(String::new, |n| n.to_string_lossy().into_owned());
    let stem = name
        .strip_suffix(".profile.json")
        .or_else(|| name.strip_suffix(".json"))
        .unwrap_or(&name);
    let session = session
        .file_stem()
        .map_or_else(|| "session".into(), |s| s.to_string_lossy().into_owned());
    out.with_file_name(format!("{stem}.{session}.profile.json"))
}

/// Profile the shader over one session and write its profile (and charts) at `out`.
fn analyze_session(
    args: &AnalyzeArgs,
    loaded: &reproj_front::Loaded,
    shader: &reproj_front::Shader,
    session_path: &std::path::Path,
    out: &std::path::Path,
) -> anyhow::Result<Written> {
    let (norm, table) = (&loaded.norm, &loaded.table);
    let session_bytes = reproj_io::read_input(session_path, reproj_io::InputKind::Json)?;
    let session = Session::load(session_path)?;
    let renderer = Renderer::new(&RendererOptions {
        backend: args.backend.clone(),
        cpu_timing: false,
        ..Default::default()
    })?;
    // `auto`: each strategy's default block is the base, and a larger one races it per node.
    let (block, race_blocks) = match args.cache.block {
        Some(crate::values::BlockArg::Size(k)) => (Some(k), false),
        Some(crate::values::BlockArg::Auto) => (None, true),
        None => (None, false),
    };
    let opts = AnalyzeOptions {
        delta_n_train: args.delta_n.clone(),
        delta_n_holdout: args.holdout.clone(),
        prune: if args.all_nodes {
            PruneOptions {
                max_nodes: usize::MAX,
                min_saving: 0.0,
                merge_within: 0.0,
            }
        } else {
            PruneOptions {
                max_nodes: args.max_nodes.max(1),
                min_saving: args.min_saving,
                ..PruneOptions::default()
            }
        },
        nodes: args.nodes.clone(),
        // `auto`: bilinear is the base filter, and Catmull-Rom races it per node.
        instance: super::instance_options(
            crate::CacheArgs {
                reconstruct: match args.cache.reconstruct {
                    crate::ReconstructArg::Auto => crate::ReconstructArg::Bilinear,
                    r => r,
                },
                block: block.map(crate::values::BlockArg::Size),
                ..args.cache
            },
            8,
        )?,
        race_filters: args.cache.reconstruct == crate::ReconstructArg::Auto,
        strategies: match args.cache.strategy {
            Some(s) => vec![super::strategy(s)],
            None => reproj_instance::Strategy::ALL.to_vec(),
        },
        block,
        race_blocks,
        max_frames: args.max_frames,
        probe_frames: (args.probe_frames > 0).then_some(args.probe_frames),
        race: reproj_analyze::DEFAULT_RACE,
        perceptual_stride: args.metric_stride,
        // Beside the profile: NAME.profile.journal. Removed once the profile is written.
        journal: Some(reproj_analyze::JournalOptions {
            path: out.with_extension("journal"),
            fresh: args.fresh,
        }),
        shard: args.shard,
        sets: (!args.no_sets).then_some(reproj_analyze::SetSearchOptions {
            top: args.set_top as usize,
            replays: args.set_replays as usize,
            max_nodes: args.set_max_nodes as usize,
        }),
        sampling: match args.sampling {
            crate::SamplingArg::Adaptive => reproj_analyze::Sampling::default(),
            crate::SamplingArg::Every => reproj_analyze::Sampling::Every,
        },
        extension: reproj_analyze::Extension {
            max_delta_n: args.max_delta_n,
            ..reproj_analyze::Extension::default()
        },
        // `REPROJ_NO_CEILING` is `--no-ceiling` for harnesses (the CLI tests' tiny shaders cost
        // less than a variant's own passes, and their profiles need nodes).
        ceiling: !args.no_ceiling && std::env::var_os("REPROJ_NO_CEILING").is_none(),
    };
    crate::ui::note(format_args!(
        "analyzing {} over {} on {} ({} cores, LP_NUM_THREADS={})",
        args.shader.display(),
        session_path.display(),
        reproj_models::profile::device_name(
            &renderer.adapter().name,
            Some(&reproj_bench::driver_of(renderer.adapter()))
        ),
        std::thread::available_parallelism().map_or(1, |n| n.get()),
        std::env::var("LP_NUM_THREADS").unwrap_or_else(|_| "unset".into())
    ));
    let bar = bar();
    let input = AnalyzeInput {
        shader,
        norm,
        table,
        session_path,
        session_bytes: &session_bytes,
        session: &session,
    };
    let mut profile = analyze(&input, &renderer, &opts, &Bar(bar))?;
    // Paths relative to the profile's directory: the profile and the files it names can be
    // committed together and used from any working directory.
    let dir = out.parent().unwrap_or(std::path::Path::new(""));
    profile.shader.path = super::relative_to(dir, &args.shader);
    profile.session.path = super::relative_to(dir, session_path);
    profile.shader_input = input_record(&args.input, dir);
    let mut json = serde_json::to_vec_pretty(&profile)?;
    json.push(b'\n');
    reproj_io::write_owned_file(out, &json, super::PROFILE_FILE)?;
    if let Some(j) = &opts.journal {
        let _ = std::fs::remove_file(&j.path);
    }
    let usable = profile
        .nodes
        .iter()
        .filter(|n| n.status == reproj_models::profile::NodeStatus::Ok)
        .count();
    let charts = if args.no_charts {
        Vec::new()
    } else {
        super::charts::write(&profile, out)?
    };
    Ok(Written {
        profile: out.display().to_string(),
        session: session_path.display().to_string(),
        nodes: profile.nodes.len(),
        usable,
        sets: profile.sets.len(),
        delta_n_train: profile.delta_n_train.clone(),
        delta_n_holdout: profile.delta_n_holdout.clone(),
        frames: profile.frames,
        resolution: profile.resolution,
        original_frame_ms: profile.original.frame_ms,
        hit_rate_mu: profile.hit_rate.mu,
        seconds: profile.time.total_s,
        charts,
        ceiling: profile.ceiling.clone(),
        time: profile.time.clone(),
    })
}

/// The profile's record of how the shader was read, its folders relative to `dir` (the
/// profile's) as the shader's path is.
fn input_record(
    input: &crate::ShaderInputArgs,
    dir: &std::path::Path,
) -> reproj_models::profile::ShaderInputRecord {
    let input = input.to_input();
    let dirs =
        |list: &[std::path::PathBuf]| list.iter().map(|d| super::relative_to(dir, d)).collect();
    reproj_models::profile::ShaderInputRecord {
        defs: input
            .defs
            .iter()
            .map(|(n, v)| (n.clone(), v.to_string()))
            .collect(),
        defs_preset: input.preset.map(|p| p.as_str().to_owned()),
        import_paths: dirs(&input.import_paths),
        include_dirs: dirs(&input.include_dirs),
    }
}

#[cfg(test)]
mod tests {
    use clap::Parser;

    /// `--delta-n`'s default is the library's training periods, spread over the Δn range.
    #[test]
    fn the_default_training_periods_are_the_library_s() {
        let cli = crate::Cli::parse_from(["reproj", "analyze", "s.wgsl", "--session", "s.json"]);
        let crate::Command::Analyze(args) = cli.command else {
            unreachable!()
        };
        assert_eq!(args.delta_n, reproj_analyze::analyze::DEFAULT_TRAIN);
    }
}
