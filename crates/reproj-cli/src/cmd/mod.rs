//! Command implementations and the error policy: user errors exit 2, internal errors exit 1.

use std::process::ExitCode;

// The commands that render or time need the `gpu` feature (the default); without it the light
// build has nodes, instance, emit and completions, and the others answer `needs_gpu`.
#[cfg(feature = "gpu")]
pub mod analyze;
#[cfg(feature = "gpu")]
pub mod bench;
#[cfg(feature = "gpu")]
pub mod charts;
#[cfg(feature = "gpu")]
pub mod compare;
pub mod completions;
pub mod emit;
pub mod instance;
#[cfg(feature = "gpu")]
pub mod merge;
pub mod nodes;
#[cfg(feature = "gpu")]
pub mod render;
#[cfg(feature = "gpu")]
pub mod report;
pub mod session;
pub mod stdout;

/// The error of a command (or option) this build was made without: exit 2, saying how to get it.
#[cfg(not(feature = "gpu"))]
pub fn needs_gpu(what: &str) -> anyhow::Error {
    UserError(format!(
        "`reproj {what}` renders with the GPU, and this reproj was built without the `gpu` feature (the light build for CI: nodes, instance, emit); install the full one: cargo install --locked --path crates/reproj-cli"
    ))
    .into()
}

/// An error caused by the user's input (bad file, bad flag value, ...): exit code 2.
#[derive(Debug)]
pub struct UserError(pub String);

impl std::fmt::Display for UserError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.0)
    }
}

impl std::error::Error for UserError {}

/// The command worked but its result misses a bar the user set (`emit --min-speedup`): exit 3.
#[derive(Debug)]
pub struct Unmet(pub String);

impl std::fmt::Display for Unmet {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.0)
    }
}

impl std::error::Error for Unmet {}

/// `emit --verify` measured an error over the budget: the promise does not hold on the session
/// verified. Exit 4.
#[derive(Debug)]
pub struct OverBudget(pub String);

impl std::fmt::Display for OverBudget {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.0)
    }
}

impl std::error::Error for OverBudget {}

/// On SIGINT or SIGTERM: remove the temporary files, staged directories and locks being
/// written (the previous outputs are untouched: nothing was renamed over them yet), say so, and
/// exit 130. A journal (`analyze`) stays: the next run resumes from it. The exit skips the
/// process's exit handlers (`_exit`): the renderer's threads are still running, and tearing down
/// the driver under them could kill the process by a signal after the cleanup (seen with
/// lavapipe: a status of no code instead of 130).
///
/// On a memory fault (SIGSEGV, SIGBUS): say what happened instead of the shell's bare
/// "Segmentation fault", and exit 1 (a bug: ours, or, while rendering, most often the Vulkan
/// driver's on that shader — lavapipe 22.3 faults on a few engine shaders). Nothing is cleaned up
/// there (a lock may be held by the faulting thread): what was being written is left for the next
/// run's sweep of stale temporaries, and the previous outputs are untouched.
#[allow(unsafe_code)]
pub fn clean_up_on_signals() {
    let _ = ctrlc::set_handler(|| {
        reproj_io::remove_registered();
        crate::ui::error("interrupted; partial output removed, previous outputs kept");
        // SAFETY: `_exit` ends the process at once; nothing of this process runs after it.
        unsafe { libc::_exit(130) }
    });
    extern "C" fn on_fault(_: libc::c_int) {
        const MESSAGE: &[u8] = b"error: reproj stopped on a memory fault (SIGSEGV or SIGBUS). While rendering this is most often the Vulkan driver failing on the shader (lavapipe 22.3 does on a few): try a newer Mesa or a GPU. Previous outputs are kept; what was being written is swept by the next run. Please report it with the shader and session.\n";
        // SAFETY: `write` and `_exit` are async-signal-safe; the message is a static buffer.
        unsafe {
            libc::write(2, MESSAGE.as_ptr().cast(), MESSAGE.len());
            libc::_exit(1);
        }
    }
    // SAFETY: a handler that only calls async-signal-safe functions, installed once at start-up;
    // SA_ONSTACK runs it on the thread's alternate stack where Rust set one (a stack overflow).
    unsafe {
        let mut action: libc::sigaction = std::mem::zeroed();
        action.sa_sigaction = on_fault as extern "C" fn(libc::c_int) as libc::sighandler_t;
        action.sa_flags = libc::SA_ONSTACK | libc::SA_RESETHAND;
        libc::sigemptyset(&mut action.sa_mask);
        for signal in [libc::SIGSEGV, libc::SIGBUS] {
            libc::sigaction(signal, &action, std::ptr::null_mut());
        }
    }
}

/// What an existing profile path must hold for analyze or merge to replace it.
#[cfg(feature = "gpu")]
pub const PROFILE_FILE: reproj_io::Owner = reproj_io::Owner::Json(&["reproj.profile"]);

#[cfg(feature = "gpu")]
/// Run-time adaptation for a replay (`render --adaptive`, `bench --adaptive`): each frame's Δn
/// from `variant`'s manifest schedule at that frame's on-screen motion in `session`, as a host
/// applies it. Returns the per-frame periods' range, for messages.
pub fn adapt(
    variant: &mut reproj_replay::VariantInput,
    session: &reproj_scene::Session,
) -> anyhow::Result<(u32, u32)> {
    let params = &variant.manifest.params;
    if params.schedule.is_empty() {
        return Err(UserError(format!(
            "{}: the manifest has no run-time schedule (`params.schedule`): `reproj emit` writes one from a profile that records motion (profile version 8)",
            variant.label
        ))
        .into());
    }
    let per_frame = reproj_emit::motion::adaptive_periods(params, session).ok_or_else(|| {
        UserError(
            "the session's motion cannot be measured (no object's mesh could be built)".into(),
        )
    })?;
    let range = (
        per_frame.iter().copied().min().unwrap_or(1),
        per_frame.iter().copied().max().unwrap_or(1),
    );
    variant.delta_n_per_frame = Some(per_frame);
    Ok(range)
}

/// A variant directory is only rendered or timed with the shader it was made from: its manifest's
/// IR hash must be `shader`'s (comments and formatting aside). Manifests written before the hash
/// was recorded are taken as they are.
#[cfg(feature = "gpu")]
pub fn check_variant_shader(
    shader: &reproj_front::Shader,
    shader_path: &std::path::Path,
    manifest: &reproj_instance::Manifest,
    dir: &std::path::Path,
) -> Result<(), UserError> {
    let Some(want) = &manifest.shader_ir_hash else {
        return Ok(());
    };
    let have = reproj_instance::ir_hash(shader);
    if &have == want {
        return Ok(());
    }
    Err(UserError(format!(
        "{} is a variant of {} (IR hash {want}), not of {} (IR hash {have}): give the shader it was made from, or instance this one",
        dir.display(),
        manifest.shader,
        shader_path.display()
    )))
}

/// The front end's language for `--lang-in` (`None`: by extension).
pub fn lang_in(l: Option<crate::LangInArg>) -> Option<reproj_front::Lang> {
    l.map(|l| match l {
        crate::LangInArg::Wgsl => reproj_front::Lang::Wgsl,
        crate::LangInArg::Glsl => reproj_front::Lang::Glsl,
        crate::LangInArg::Spv => reproj_front::Lang::SpirV,
    })
}

/// Load, normalize and enumerate a shader file (see [`reproj_front::load`]), read as `input`
/// says; its warnings printed.
pub fn load_shader(
    path: &std::path::Path,
    entry: Option<&str>,
    lang: Option<crate::LangInArg>,
    unroll: &crate::UnrollArg,
    input: &reproj_front::ShaderInput,
) -> anyhow::Result<reproj_front::Loaded> {
    let options = reproj_front::LoadOptions {
        lang: lang_in(lang),
        unroll: reproj_front::UnrollOptions {
            max_trip: unroll.unroll,
        },
        input: input.clone(),
    };
    let start = std::time::Instant::now();
    let loaded = reproj_front::load(path, entry, &options)?;
    warn_input(&loaded.shader);
    crate::ui::detail(format_args!(
        "{}: entry `{}`, {} nodes ({} cacheable), read and normalized in {:.1} ms",
        path.display(),
        loaded.table.entry,
        loaded.table.nodes.len(),
        loaded.table.cacheable().count(),
        start.elapsed().as_secs_f64() * 1e3
    ));
    Ok(loaded)
}

/// Read a shader file as `input` says (no normalization: `render`, `bench`, `session init`);
/// its warnings printed.
pub fn read_shader(
    path: &std::path::Path,
    lang: Option<crate::LangInArg>,
    input: &crate::ShaderInputArgs,
) -> anyhow::Result<reproj_front::Shader> {
    let shader = reproj_front::load_file_with(path, lang_in(lang), &input.to_input())?;
    warn_input(&shader);
    Ok(shader)
}

/// The warnings of reading a shader (a def nobody reads) on stderr.
pub fn warn_input(shader: &reproj_front::Shader) {
    for w in &shader.warnings {
        crate::ui::warn(w);
    }
}

/// What `--lang` and `--override` ask for (WGSL is always written).
pub fn outputs(
    langs: &[crate::LangArg],
    overrides: &[(String, f64)],
) -> reproj_instance::backends::Outputs {
    reproj_instance::backends::Outputs {
        langs: output_langs(langs),
        overrides: overrides.iter().cloned().collect(),
    }
}

/// The backends `--lang` asks for (WGSL is always written).
fn output_langs(langs: &[crate::LangArg]) -> Vec<reproj_instance::backends::OutputLang> {
    use reproj_instance::backends::OutputLang as O;
    let mut out = Vec::new();
    for l in langs {
        let o = match l {
            crate::LangArg::Wgsl => continue,
            crate::LangArg::Glsl => O::Glsl,
            crate::LangArg::Hlsl => O::Hlsl,
            crate::LangArg::Msl => O::Msl,
            crate::LangArg::Spv => O::SpirV,
        };
        if !out.contains(&o) {
            out.push(o);
        }
    }
    out
}

/// Why a shader has no cacheable node, one line per culling reason with its count, then a hint
/// (`None` when some node is cacheable).
pub fn no_cacheable_lines(table: &reproj_front::NodeTable) -> Option<Vec<String>> {
    if table.cacheable().next().is_some() {
        return None;
    }
    let summary = table.cull_summary();
    let mut lines = vec![format!(
        "{}: no cacheable node among {} nodes:",
        table.shader,
        table.nodes.len()
    )];
    for (reason, count) in &summary.counts {
        lines.push(format!("  {reason}: {count}"));
    }
    lines.push(format!("hint: {}", summary.hint));
    Some(lines)
}

/// How an error ends the process: its exit code (2: the user's input or files, 1: a bug or the
/// machine, 3: a bar the user set was not met, 4: `emit --verify` measured an error over the
/// budget) and, for an error about a place in a shader, the
/// source diagnostic to show. The one place that decides, for every error type reproj has.
fn classify(e: &anyhow::Error) -> (u8, Option<&reproj_front::SourceDiagnostic>) {
    let user = |yes: bool| if yes { 2 } else { 1 };
    for c in e.chain() {
        if c.downcast_ref::<Unmet>().is_some() {
            return (3, None);
        }
        if c.downcast_ref::<OverBudget>().is_some() {
            return (4, None);
        }
        if c.downcast_ref::<UserError>().is_some()
            || c.downcast_ref::<reproj_io::ReadError>().is_some()
            || c.downcast_ref::<reproj_io::InputError>().is_some()
            || c.downcast_ref::<reproj_io::WriteError>().is_some()
            || c.downcast_ref::<reproj_scene::SessionError>().is_some()
            || c.downcast_ref::<reproj_scene::reflect::Unsupported>()
                .is_some()
        {
            return (2, None);
        }
        if let Some(f) = c.downcast_ref::<reproj_front::FrontError>() {
            return (user(f.is_user_error()), f.diagnostic());
        }
        if let Some(i) = c.downcast_ref::<reproj_instance::InstanceError>() {
            return (user(i.is_user_error()), i.diagnostic());
        }
        if let Some(e) = c.downcast_ref::<reproj_emit::EmitError>() {
            return (user(e.is_user_error()), e.diagnostic());
        }
        #[cfg(feature = "gpu")]
        if let Some(found) = classify_gpu(c) {
            return found;
        }
    }
    (1, None)
}

/// [`classify`] for the error types of the crates only the `gpu` feature builds.
#[cfg(feature = "gpu")]
fn classify_gpu<'e>(
    c: &'e (dyn std::error::Error + 'static),
) -> Option<(u8, Option<&'e reproj_front::SourceDiagnostic>)> {
    let user = |yes: bool| if yes { 2 } else { 1 };
    if c.downcast_ref::<reproj_metrics::output::OutputError>()
        .is_some()
    {
        return Some((2, None));
    }
    if let Some(r) = c.downcast_ref::<reproj_replay::ReplayError>() {
        return Some((user(r.is_user_error()), None));
    }
    if let Some(a) = c.downcast_ref::<reproj_analyze::AnalyzeError>() {
        return Some((user(a.is_user_error()), a.diagnostic()));
    }
    if let Some(r) = c.downcast_ref::<reproj_compare::CompareError>() {
        return Some((user(r.is_user_error()), r.diagnostic()));
    }
    if let Some(r) = c.downcast_ref::<reproj_report::ReportError>() {
        return Some((user(r.is_user_error()), r.diagnostic()));
    }
    if let Some(r) = c.downcast_ref::<reproj_charts::ChartError>() {
        return Some((user(matches!(r, reproj_charts::ChartError::Write(_))), None));
    }
    None
}

/// Instancer options from the CLI's cache flags and a default Δn (3pass unless one is named).
/// `--reconstruct auto` and `--block auto` are refused: one variant has one filter and one block
/// size (`analyze` handles `auto` itself).
pub fn instance_options(
    c: crate::CacheArgs,
    delta_n: u32,
) -> Result<reproj_instance::InstanceOptions, UserError> {
    let strategy = c
        .strategy
        .map_or(reproj_instance::Strategy::ThreePass, strategy);
    let reconstruct = reconstruct(c.reconstruct).ok_or_else(|| {
        UserError(
            "--reconstruct auto is for `analyze`, which races the filters per node; name one filter (bilinear, nearest, catmull-rom)".into(),
        )
    })?;
    let block = match c.block {
        None => strategy.default_block(),
        Some(crate::values::BlockArg::Size(k)) => k,
        Some(crate::values::BlockArg::Auto) => {
            return Err(UserError(
                "--block auto is for `analyze`, which races the block sizes per node; name one size (1 or an even number in 2..=256)".into(),
            ));
        }
    };
    Ok(reproj_instance::InstanceOptions {
        strategy,
        reconstruct,
        cache_format: cache_format(c.cache_format),
        delta_n,
        block,
        depth_epsilon: c.depth_epsilon,
        ..Default::default()
    })
}

/// Apply the integration flags to instancing options.
pub fn integrate(
    opts: reproj_instance::InstanceOptions,
    i: &crate::IntegrationArgs,
) -> reproj_instance::InstanceOptions {
    reproj_instance::InstanceOptions {
        group: i.group,
        frame_load: if i.loads_frame() {
            reproj_instance::FrameLoad::Load
        } else {
            reproj_instance::FrameLoad::Clear
        },
        depth_load: if i.loads_depth() {
            reproj_instance::DepthLoad::Load
        } else {
            reproj_instance::DepthLoad::Clear
        },
        reprojection: match i.reproject {
            crate::ReprojectArg::Vertex => reproj_instance::Reprojection::Vertex,
            crate::ReprojectArg::MotionVectors => reproj_instance::Reprojection::MotionVectors,
        },
        ..opts
    }
}

/// The instancer's strategy for the CLI flag.
pub fn strategy(s: crate::StrategyArg) -> reproj_instance::Strategy {
    match s {
        crate::StrategyArg::ThreePass => reproj_instance::Strategy::ThreePass,
        crate::StrategyArg::TwoPass => reproj_instance::Strategy::TwoPass,
        crate::StrategyArg::Fused => reproj_instance::Strategy::Fused,
    }
}

/// The instancer's reconstruction for the CLI flag (`None`: `auto`, chosen by `analyze`).
pub fn reconstruct(r: crate::ReconstructArg) -> Option<reproj_instance::Reconstruct> {
    match r {
        crate::ReconstructArg::Bilinear => Some(reproj_instance::Reconstruct::Bilinear),
        crate::ReconstructArg::Nearest => Some(reproj_instance::Reconstruct::Nearest),
        crate::ReconstructArg::CatmullRom => Some(reproj_instance::Reconstruct::CatmullRom),
        crate::ReconstructArg::Auto => None,
    }
}

/// The instancer's cache format choice for the CLI flag.
pub fn cache_format(f: crate::CacheFormatArg) -> reproj_instance::CacheFormatChoice {
    use reproj_instance::{CacheFormat as F, CacheFormatChoice as C};
    match f {
        crate::CacheFormatArg::F32 => C::Narrowest32,
        crate::CacheFormatArg::F16 => C::Narrowest16,
        crate::CacheFormatArg::Rgba32float => C::Exact(F::Rgba32float),
        crate::CacheFormatArg::Rg32float => C::Exact(F::Rg32float),
        crate::CacheFormatArg::R32float => C::Exact(F::R32float),
        crate::CacheFormatArg::Rgba16float => C::Exact(F::Rgba16float),
        crate::CacheFormatArg::Rg16float => C::Exact(F::Rg16float),
        crate::CacheFormatArg::R16float => C::Exact(F::R16float),
    }
}

/// `path` relative to `dir` (both taken from the working directory), with forward slashes;
/// absolute when they share no root.
#[cfg(feature = "gpu")]
pub fn relative_to(dir: &std::path::Path, path: &std::path::Path) -> String {
    let abs = |p: &std::path::Path| {
        let p = if p.as_os_str().is_empty() {
            std::path::Path::new(".")
        } else {
            p
        };
        std::fs::canonicalize(p).unwrap_or_else(|_| p.to_owned())
    };
    let (dir, path) = (abs(dir), abs(path));
    let d: Vec<_> = dir.components().collect();
    let p: Vec<_> = path.components().collect();
    let common = d.iter().zip(&p).take_while(|(a, b)| a == b).count();
    if common == 0 {
        return path.display().to_string();
    }
    let mut parts: Vec<String> = vec!["..".into(); d.len() - common];
    parts.extend(
        p[common..]
            .iter()
            .map(|c| c.as_os_str().to_string_lossy().into_owned()),
    );
    parts.join("/")
}

/// Print the error (if any) and choose the exit code.
pub fn finish(result: anyhow::Result<()>) -> ExitCode {
    use std::io::Write as _;
    // Output still buffered is written now, so that its failure is seen.
    let flushed = stdout::stdout().flush();
    let e = match (result, flushed) {
        (Err(e), _) => e,
        (Ok(()), Err(e)) => e.into(),
        (Ok(()), Ok(())) => return ExitCode::SUCCESS,
    };
    // A signal's cleanup has run (writes are refused from then on, which is likely this error):
    // the handler says so and exits 130; leave it the last word.
    if reproj_io::cleanup_started() {
        std::thread::sleep(std::time::Duration::from_secs(5));
        return ExitCode::from(130);
    }
    // `reproj nodes x.wgsl | head` closes the pipe early: not an error.
    if is_broken_pipe(&e) {
        return ExitCode::SUCCESS;
    }
    // Our own output could not be written (a full disk, a closed stdout): its own exit code.
    if let Some(why) = stdout::failure() {
        crate::ui::error(format!("could not write the output to stdout: {why}"));
        crate::ui::detail(format!("exit code {}", stdout::EXIT_STDOUT));
        return ExitCode::from(stdout::EXIT_STDOUT);
    }
    let (code, diagnostic) = classify(&e);
    match (code, diagnostic) {
        (_, Some(d)) => crate::ui::diagnostic(&d.render()),
        // A user error's own message says what to fix; `-v` adds the causes under it.
        (2..=4, None) if !crate::ui::verbose(1) => {
            let msg = e.to_string();
            let msg = msg.trim_end();
            crate::ui::error(msg.strip_prefix("error: ").unwrap_or(msg));
        }
        _ => crate::ui::error(format!("{e:#}")),
    }
    crate::ui::detail(format!("exit code {code}"));
    ExitCode::from(code)
}

/// Did writing to stdout fail because its reader went away? Commands print through a locked
/// stdout handle with `writeln!` (never `println!`, which panics on a closed pipe), so the error
/// comes back here, directly or inside a `serde_json` error.
fn is_broken_pipe(e: &anyhow::Error) -> bool {
    use std::io::ErrorKind::BrokenPipe;
    e.chain().any(|c| {
        c.downcast_ref::<std::io::Error>()
            .is_some_and(|io| io.kind() == BrokenPipe)
            || c.downcast_ref::<serde_json::Error>()
                .is_some_and(|j| j.io_error_kind() == Some(BrokenPipe))
    })
}
