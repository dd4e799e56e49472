//! `reproj compare`: is reprojection the right tool for this shader at all? The paper's Fig. 10
//! compares, at equal speed, three ways to shade fewer operations per frame:
//!
//! - **resize** ([`resize`]): the original rendered at a reduced resolution, upsampled bilinearly
//!   to full size; the scale is searched by measurement until the frame time meets the target;
//! - **easu** ([`easu`]): resize's frames upsampled edge-adaptively (FSR 1 EASU's way) instead
//!   of bilinearly, at resize's speed;
//! - **temporal** ([`temporal`]): what engines ship, temporal upsampling — the original at a
//!   reduced resolution with a sub-pixel jitter, resolved each frame into a reprojected
//!   full-resolution history; its scale searched like resize's;
//! - **simplify** ([`simplify`]): Pellacini-style code simplification — greedily replace the node
//!   whose removal costs the least error per saved time by its session mean, until the target;
//! - **reproj** ([`reproj`]): reproj's own choice from a profile at the target speedup, rendered.
//!
//! Each is rendered with the replay (one renderer, no second one) and scored against the
//! full-resolution original with the replay's metrics (L2, PSNR, ꟻLIP), and against a
//! supersampled reference (the original at `CompareOptions::supersample` jittered samples per
//! pixel, averaged: what a temporal method converges toward; [`supersample`]), each split into
//! still and moving frames where the session has both. Every speed — the
//! searches' tries as well as the table's — is timed against the original interleaved
//! ([`Ctx::race`], `reproj-bench`), never read off a replay's own mean. [`write_outputs`] writes
//! the JSON report (schema `reproj.compare`, `docs/SCHEMAS.md`), the chart and side-by-side crops.

pub mod crops;
mod ctx;
pub mod easu;
mod equal_time;
mod output;
mod report;
pub mod reproj;
pub mod resize;
pub mod simplify;
pub mod supersample;
pub mod temporal;
mod timing;

use std::cell::{Cell, RefCell};
use std::path::{Path, PathBuf};

use reproj_analyze::Progress;
use reproj_front::Loaded;
use reproj_models::Profile;
use reproj_replay::{RenderOptions, Renderer};
use reproj_scene::Session;

pub(crate) use ctx::Ctx;
pub use output::write_outputs;
pub use report::{Against, CompareReport, MethodResult, Scores, Split};
use timing::{apply_timing, time_final};

/// Schema name of a [`CompareReport`] (`compare.json`).
pub const COMPARE_SCHEMA: &str = "reproj.compare";
/// Version of the [`CompareReport`] schema. Bump on any incompatible change.
pub const COMPARE_VERSION: u32 = 6;

/// What can go wrong in `compare`.
#[derive(Debug, thiserror::Error)]
pub enum CompareError {
    #[error(transparent)]
    Front(#[from] reproj_front::FrontError),
    #[error(transparent)]
    Instance(#[from] reproj_instance::InstanceError),
    #[error(transparent)]
    Replay(#[from] reproj_replay::ReplayError),
    #[error(transparent)]
    Analyze(#[from] reproj_analyze::AnalyzeError),
    /// The profile (read as `emit` reads it) or the variant it names.
    #[error(transparent)]
    Emit(#[from] reproj_emit::EmitError),
    #[error(transparent)]
    Write(#[from] reproj_io::WriteError),
    #[error(transparent)]
    Chart(#[from] reproj_charts::ChartError),
    /// An option out of range (the target speedup, a count).
    #[error("{0}")]
    Options(String),
    /// The shader has no node code simplification could replace.
    #[error("{shader}: no cacheable f32 or vecN<f32> node to simplify")]
    NothingToSimplify { shader: String },
    /// Under the error budget given as the target, reproj keeps the original shader: there is no
    /// speedup to compare at.
    #[error(
        "{path}: under the error budget {max_error}, reproj keeps the original shader ({reason}); give --speedup instead"
    )]
    KeepsOriginal {
        path: PathBuf,
        max_error: f64,
        reason: String,
    },
    /// The profile has no usable (node, Δn) to render.
    #[error("{path}: the profile has no node with usable fits; reproj has nothing to compare")]
    NoSelection { path: PathBuf },
    /// A bug or the machine: a temporary file, an image that would not encode.
    #[error("{what}: {message}")]
    Internal { what: String, message: String },
}

impl CompareError {
    /// True when the error comes from the user's input (exit code 2), false for a bug, a GPU
    /// failure or the machine.
    pub fn is_user_error(&self) -> bool {
        match self {
            CompareError::Front(e) => e.is_user_error(),
            CompareError::Instance(e) => e.is_user_error(),
            CompareError::Replay(e) => e.is_user_error(),
            CompareError::Analyze(e) => e.is_user_error(),
            CompareError::Emit(e) => e.is_user_error(),
            CompareError::Chart(_) | CompareError::Internal { .. } => false,
            _ => true,
        }
    }

    /// The source diagnostic of a front-end error about a place in the shader.
    pub fn diagnostic(&self) -> Option<&reproj_front::SourceDiagnostic> {
        match self {
            CompareError::Front(e) => e.diagnostic(),
            CompareError::Instance(e) => e.diagnostic(),
            CompareError::Analyze(e) => e.diagnostic(),
            CompareError::Emit(e) => e.diagnostic(),
            _ => None,
        }
    }
}

/// What [`compare`] works on.
#[derive(Debug)]
pub struct CompareInput<'a> {
    /// The shader as loaded (normalized, its nodes enumerated); WGSL (GLSL and SPIR-V are written
    /// as WGSL by the caller, as `analyze` does).
    pub loaded: &'a Loaded,
    /// Its fragment entry point's name (`None`: the only one).
    pub entry: Option<&'a str>,
    pub session: &'a Session,
    /// The profile from `analyze` and its path, for reproj's own choice; `None`: compare resize
    /// and simplification only.
    pub profile: Option<(&'a Profile, &'a Path)>,
}

/// What every method aims at.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Target {
    /// This speedup over the original (> 1).
    Speedup(f64),
    /// The speedup reproj's own selection under this error budget (mean per-pixel L2, as
    /// `emit --max-error`) is predicted to reach; needs a profile.
    Budget(reproj_select::Budget),
}

/// Options of [`compare`].
#[derive(Debug, Clone, PartialEq)]
pub struct CompareOptions {
    /// What every method aims at.
    pub target: Target,
    /// Render only the first N frames of the session.
    pub max_frames: Option<u32>,
    pub resize: resize::ResizeOptions,
    pub simplify: simplify::SimplifyOptions,
    /// Longest refresh period reproj may choose.
    pub max_delta_n: u32,
    /// reproj at a target speedup: most points raced while steering to it (`reproj::steer`).
    pub reproj_tries: usize,
    /// At a target speedup, reproj and resizing further apart than this fraction in the final
    /// interleaved run, the faster one with the larger error, leave the comparison undecided:
    /// reproj is moved to resizing's speed and every method timed again (`rematch`).
    pub equal_time: f64,
    /// ꟻLIP is computed on frames `f` with `f % stride == 0`.
    pub perceptual_stride: u32,
    /// How the methods' final speeds are timed against the original (interleaved,
    /// `reproj-bench`).
    pub timing: reproj_bench::BenchOptions,
    /// How the searches time their tries against the original (each resize scale, each
    /// simplification step's candidates together): interleaved too, shorter
    /// ([`reproj_analyze::DEFAULT_RACE`] by default).
    pub search_timing: reproj_bench::BenchOptions,
    /// Compare temporal upsampling too ([`temporal`]).
    pub temporal: bool,
    /// Jittered samples per pixel of the supersampled reference (0: none; 1 is refused).
    pub supersample: u32,
}

impl Default for CompareOptions {
    fn default() -> Self {
        CompareOptions {
            target: Target::Speedup(2.0),
            max_frames: None,
            resize: Default::default(),
            simplify: Default::default(),
            max_delta_n: reproj_select::EXTENDED_MAX_DELTA_N,
            reproj_tries: 4,
            equal_time: 0.03,
            perceptual_stride: reproj_analyze::DEFAULT_PERCEPTUAL_STRIDE,
            timing: reproj_bench::BenchOptions::default(),
            search_timing: reproj_analyze::DEFAULT_RACE,
            temporal: true,
            supersample: 16,
        }
    }
}

/// A finished comparison: the report and what the output files are made from.
#[derive(Debug, Clone)]
pub struct Comparison {
    pub report: CompareReport,
    /// The crop frame of each method (reference first), RGBA f32 at full resolution.
    pub crop_frames: Vec<(String, Vec<f32>)>,
    /// The crop frame's reference depth (covered pixels).
    pub crop_depth: Vec<f32>,
    /// WGSL of the final simplified shader.
    pub simplified_wgsl: String,
}

/// Render the original, then each method at the target speedup; score each against the
/// original. Phases: the target (reproj's plan from the profile), the reference, the methods'
/// searches, their final interleaved timing, then the report.
pub fn compare(
    renderer: &Renderer,
    input: &CompareInput,
    opts: &CompareOptions,
    progress: &dyn Progress,
) -> Result<Comparison, CompareError> {
    let (planned, target, max_error) = plan_target(input, opts)?;
    if opts.perceptual_stride == 0 {
        return Err(CompareError::Options(
            "the perceptual stride must be at least 1".into(),
        ));
    }
    let shader = &input.loaded.shader;
    let entry = shader.fragment_entry(input.entry)?;
    let render_opts = RenderOptions {
        png_dir: None,
        max_frames: opts.max_frames,
        first_frame: 0,
        timing_only: false,
        classify: false,
        raw_frames: false,
        perceptual_stride: None,
    };
    // The simplification's length is not known ahead (it stops when the target is reached): the
    // total assumes two steps and is re-estimated as each method ends.
    let counted = Counted {
        inner: progress,
        done: Cell::new(0),
    };
    let progress = &counted;
    let steps = Steps {
        per_simplify_step: (opts.simplify.candidates + opts.simplify.candidates.div_ceil(2)) as u64,
        reproj: match (input.profile, opts.target) {
            (None, _) => 0,
            (Some(_), Target::Speedup(_)) => 1 + opts.reproj_tries as u64,
            (Some(_), Target::Budget(_)) => 1,
        },
    };
    // The temporal upsampler's search, and reproj's variant inside it where there is one.
    let temporal_tries = if opts.temporal {
        opts.resize.tries as u64 * (1 + u64::from(input.profile.is_some()))
    } else {
        0
    };
    progress.remaining(
        4 + opts.resize.tries as u64 + temporal_tries + 2 * steps.per_simplify_step + steps.reproj,
    );
    let reference = renderer.render_original(shader, entry, input.session, &render_opts)?;
    progress.step("original");
    let frames = reference.frames.len() as u32;
    let mid = (frames / 2) as usize;
    let moving = supersample::moving_frames(input.session, frames);
    let mut notes = Vec::new();
    let supersampled = supersample::reference(
        renderer,
        shader,
        entry,
        input.session,
        (&render_opts, frames),
        opts.supersample,
        &mut notes,
    )?;
    if opts.supersample > 1 {
        progress.step("supersampled reference");
    }
    let ctx = Ctx {
        renderer,
        baseline: reproj_bench::Baseline {
            shader,
            entry,
            reference: &reference,
        },
        search_timing: &opts.search_timing,
        timing_warnings: RefCell::new(Vec::new()),
        session: input.session,
        reference: &reference,
        supersampled: supersampled.as_deref(),
        moving: &moving,
        render_opts: &render_opts,
        stride: opts.perceptual_stride,
        target,
        progress,
    };
    let mut m = run_methods(&ctx, &counted, input, opts, planned.as_ref(), mid, steps)?;
    let mut timed = time_final(&ctx, input, opts, &mut m)?;
    progress.step("timing, interleaved");
    if let (Some(profile), Some(apart)) =
        (input.profile, equal_time::apart(&timed, &m.results, opts))
    {
        counted.remaining(2);
        if equal_time::rematch(&ctx, input, opts, profile, &mut m, apart, mid)? {
            timed = time_final(&ctx, input, opts, &mut m)?;
            progress.step("timing again, interleaved");
        }
    }
    apply_timing(&mut m.results, &timed, target);
    let original_ms = timed.baseline.median_ms;
    progress.finish();
    let [w, h] = input.session.resolution;
    let crop_depth = reference.depth[mid].clone();
    let region = crops::region(w, h, &crop_depth, mid as u32);
    let report = CompareReport {
        schema: COMPARE_SCHEMA.into(),
        version: COMPARE_VERSION,
        shader: shader.path.display().to_string(),
        entry: shader.module.entry_points[entry].name.clone(),
        session: input.session.display_name(),
        resolution: [w, h],
        frames,
        adapter: reference.report.adapter.name.clone(),
        timing: format!("{:?}", reference.report.timing).to_lowercase(),
        target_speedup: target,
        max_error,
        original_ms,
        measured_on: Some(reproj_bench::Machine::of(renderer).describe()),
        timing_warnings: merged_warnings(timed.warnings, ctx.timing_warnings.take()),
        methods: m.results,
        supersample: if supersampled.is_some() {
            opts.supersample
        } else {
            0
        },
        original_vs_supersampled: ctx.original_vs_supersampled()?,
        moving_frames: moving.iter().filter(|&&m| m).count() as u32,
        notes: {
            notes.extend(supersample::notes(&moving, opts.temporal));
            notes
        },
        resize: m.resize,
        temporal: m.temporal,
        simplify: m.simplified.detail,
        reproj: m.reproj,
        crops: region,
        files: Vec::new(),
    };
    Ok(Comparison {
        report,
        crop_frames: m.crop_frames,
        crop_depth,
        simplified_wgsl: m.simplified.wgsl,
    })
}

/// reproj's plan from the profile (when there is one), the speedup every method aims at (the
/// target's, or what the plan predicts under the budget) and the budget.
fn plan_target<'p>(
    input: &CompareInput<'p>,
    opts: &CompareOptions,
) -> Result<(Option<reproj::Planned<'p>>, f64, Option<f64>), CompareError> {
    let planned = match input.profile {
        Some((profile, path)) => Some(reproj::plan(
            input.loaded,
            profile,
            path,
            opts.target,
            opts.max_delta_n,
        )?),
        None => None,
    };
    let (target, max_error) = match (opts.target, &planned) {
        (Target::Speedup(x), _) => (x, None),
        (Target::Budget(e), Some(p)) => (p.predicted_speedup, Some(e.get())),
        (Target::Budget(_), None) => {
            return Err(CompareError::Options(
                "an error budget as the target needs a profile: reproj's selection under it sets the speedup".into(),
            ));
        }
    };
    if !(target.is_finite() && target > 1.0) {
        return Err(CompareError::Options(format!(
            "the target speedup must be a number above 1, got {target}"
        )));
    }
    Ok((planned, target, max_error))
}

/// The progress steps a method is expected to take: each simplification step's, and reproj's
/// (1 with a profile).
#[derive(Clone, Copy)]
struct Steps {
    per_simplify_step: u64,
    reproj: u64,
}

/// What the methods' searches found, in order (resize, simplify, reproj where planned): their
/// results, the crop frames (the reference's first), and what the timing and the report need.
struct Methods {
    results: Vec<MethodResult>,
    crop_frames: Vec<(String, Vec<f32>)>,
    resize: resize::ResizeDetail,
    temporal: Option<resize::ResizeDetail>,
    /// reproj's variant inside the temporal upsampler ([`temporal::composed`]).
    composed: Option<resize::ResizeDetail>,
    simplified: simplify::Simplification,
    reproj: Option<reproj::ReprojDetail>,
    /// reproj's variant, for the final timing.
    reproj_input: Option<reproj_replay::VariantInput>,
}

/// Run each method's search at the target: resizing, simplification, then reproj's planned
/// choice; `mid` is the frame the crops are taken from.
fn run_methods(
    ctx: &Ctx,
    progress: &Counted,
    input: &CompareInput,
    opts: &CompareOptions,
    planned: Option<&reproj::Planned>,
    mid: usize,
    steps: Steps,
) -> Result<Methods, CompareError> {
    let shader = &input.loaded.shader;
    let entry = ctx.baseline.entry;
    let mut results = Vec::new();
    let mut crop_frames = vec![("reference".to_string(), ctx.reference.frames[mid].clone())];
    let (resize_detail, resize_frames, resize_result) =
        resize::resize(ctx, shader, entry, &opts.resize)?;
    results.push(resize_result);
    crop_frames.push(("resize".into(), resize_frames[mid].clone()));
    drop(resize_frames);
    let (easu_frames, easu) =
        resize::edge_adaptive(ctx, shader, entry, &resize_detail, &results[0])?;
    results.push(easu);
    crop_frames.push(("easu".into(), easu_frames[mid].clone()));
    drop(easu_frames);
    let temporal = if opts.temporal {
        let (detail, frames, result) = temporal::temporal(ctx, shader, entry, &opts.resize)?;
        results.push(result);
        crop_frames.push(("temporal".into(), frames[mid].clone()));
        Some(detail)
    } else {
        None
    };
    progress.remaining(1 + 2 * steps.per_simplify_step + steps.reproj);
    let simplified = simplify::simplify(ctx, input.loaded, &opts.simplify)?;
    progress.remaining(1 + steps.reproj);
    results.push(simplified.result.clone());
    crop_frames.push(("simplify".into(), simplified.frames[mid].clone()));
    let mut reproj_input = None;
    let reproj_detail = match (input.profile, planned) {
        (Some((profile, path)), Some(planned)) => {
            // At a target speedup the models' point is steered by measurement, as resizing's
            // scale is; under a budget it is `emit`'s choice as it stands.
            let (planned, tries) = match opts.target {
                Target::Speedup(_) => reproj::steer(
                    ctx,
                    input.loaded,
                    profile,
                    path,
                    *planned,
                    opts.max_delta_n,
                    opts.reproj_tries,
                    opts.resize.tolerance,
                )?,
                Target::Budget(_) => (*planned, Vec::new()),
            };
            let r = reproj::reproj(
                ctx,
                input.loaded,
                (profile, path),
                &planned,
                tries,
                mid as u32,
            )?;
            results.push(r.result);
            crop_frames.push(("reproj".into(), r.crop_frame));
            reproj_input = Some(r.input);
            Some(r.detail)
        }
        _ => None,
    };
    // reproj's variant inside the temporal upsampler, where both are compared.
    let composed = match (&reproj_input, &reproj_detail) {
        (Some(v), Some(d)) if opts.temporal => {
            // reproj's speed as raced (the final interleaved run sets its result's later), else
            // as predicted.
            let alone = d
                .tries
                .iter()
                .find(|t| t.node == d.node && t.delta_n == d.delta_n && t.speedup > 0.0)
                .map_or(d.predicted_speedup, |t| t.speedup);
            let (detail, frames, result) = temporal::composed(ctx, shader, v, alone, &opts.resize)?;
            results.push(result);
            crop_frames.push((temporal::COMPOSED.into(), frames[mid].clone()));
            Some(detail)
        }
        _ => None,
    };
    Ok(Methods {
        results,
        crop_frames,
        resize: resize_detail,
        temporal,
        composed,
        simplified,
        reproj: reproj_detail,
        reproj_input,
    })
}

/// The final run's timing warnings, then the searches' (each once, marked `search:`).
fn merged_warnings(mut warnings: Vec<String>, search: Vec<String>) -> Vec<String> {
    for s in search {
        let s = format!("search: {s}");
        if !warnings.contains(&s) {
            warnings.push(s);
        }
    }
    warnings
}

/// A [`Progress`] that counts finished steps, so the total can be re-estimated mid-way.
struct Counted<'a> {
    inner: &'a dyn Progress,
    done: Cell<u64>,
}

impl Counted<'_> {
    /// `n` more steps are expected after those done.
    fn remaining(&self, n: u64) {
        self.inner.start(self.done.get() + n);
    }
}

impl Progress for Counted<'_> {
    fn start(&self, total: u64) {
        self.inner.start(total);
    }
    fn step(&self, what: &str) {
        self.done.set(self.done.get() + 1);
        self.inner.step(what);
    }
    fn note(&self, line: &str) {
        self.inner.note(line);
    }
    fn finish(&self) {
        self.inner.finish();
    }
}
