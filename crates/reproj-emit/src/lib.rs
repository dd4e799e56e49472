//! reproj's deciding stage, GPU-free: `emit` selects the fastest (node or set of nodes, Δn) under an
//! error budget from a profile and writes its passes. Built and tested without wgpu: the light
//! build CI uses to run `emit` is this crate and the CLI. reproj-analyze's `verify` re-renders the
//! selection to check the prediction.
//!
//! In phases: read the profile(s) and check the shader is the one profiled (`profile.rs`), select
//! across the sessions and motion (`choose.rs`, [`motion`]), spell the choice as a typed
//! [`VariantSpec`] (`spec.rs`, the one place a profile's strings become a variant's options),
//! write it (`write.rs`). [`contenders`] lists what a runoff times (`runoff.rs`).

use std::path::{Path, PathBuf};

use reproj_front::{LoadOptions, UnrollOptions, load};
use reproj_instance::{
    CacheFormatChoice, InstanceOptions, Reconstruct, Strategy, VARIANT_FILES, Variant,
    backends::Outputs,
};
use reproj_io::Replace;
use reproj_metrics::MetricSummary;
use reproj_models::Metric;
use reproj_models::{Profile, content_hash};
use reproj_select::{NodeRecord, ScenePrediction, SelectOptions, Selection, SetRecord};
use serde::{Deserialize, Serialize};

mod choose;
mod error;
pub mod motion;
mod profile;
mod runoff;
mod spec;
mod write;

pub use error::EmitError;

use choose::{Records, choose};
pub use profile::{
    is_profiled_shader, latest_profile, load_profile, load_profiled, profile_shader,
    profile_shader_input, profile_variant_settings, resolve, selector_records,
};
use profile::{records_of, same_shader, same_variant};
pub use runoff::{Contender, Runoff, RunoffEntry, contenders};
pub use spec::{Profiled, VariantSpec};
use write::Writer;

/// Options of [`emit`].
#[derive(Debug, Clone)]
pub struct EmitOptions {
    /// Error budget, in the unit of `metric`.
    pub max_error: Budget,
    /// Which measured error the budget bounds (the error model fitted to it predicts it).
    pub metric: Metric,
    pub min_delta_n: u32,
    pub max_delta_n: u32,
    /// Directory for the passes and the report.
    pub out: PathBuf,
    /// The cache format of the written passes (`None`: the profile's).
    pub cache_format: Option<CacheFormatChoice>,
    /// Only consider nodes profiled in this strategy (`None`: any).
    pub strategy: Option<Strategy>,
    /// Only consider this node (`None`: any; sets are then left out).
    pub node: Option<NodeChoice>,
    /// Where the written passes fit in a host: its `group`, `frame_load`, `depth_load` and
    /// `reprojection` are used (the rest
    /// comes from the selection and the profile).
    pub integration: InstanceOptions,
    /// The shader to instance (`None`: the profile's, relative to the profile file). Either way
    /// it must be the shader that was profiled, up to comments and formatting.
    pub shader: Option<PathBuf>,
    /// Languages to write the passes in besides WGSL, and the values of the override constants.
    pub outputs: Outputs,
    /// Profiles of the same shader over other sessions (path, profile): the selection holds the
    /// budget on every session, the first profile's included ([`reproj_select::select_worst_case`]).
    pub also: Vec<(PathBuf, Profile)>,
    /// The session the variant is for, when it may be none of the profiled ones (`--verify
    /// --session NEW`): the profile nearest in motion is carried to its motion
    /// ([`crate::motion::carry`]) and the budget must hold there too.
    pub target: Option<crate::motion::TargetSession>,
    /// One Δn for every frame, or Δn per frame from the manifest's schedule chosen for the
    /// target's (or the profiled sessions') motion frame by frame (`--adaptive`).
    pub period: crate::motion::PeriodChoice,
}

/// A node `emit` is restricted to (`--node`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum NodeChoice {
    Root,
    Id(u32),
}

impl NodeChoice {
    fn admits(self, n: &reproj_models::profile::NodeProfile) -> bool {
        match self {
            NodeChoice::Root => n.root,
            NodeChoice::Id(id) => n.id == id,
        }
    }
}

/// Schema name of an [`EmitReport`] (`report.json`).
pub const EMIT_REPORT_SCHEMA: &str = "reproj.report";
/// Version of the [`EmitReport`] schema. Bump on any incompatible change.
/// Version 2: `metric` (what `max_error` and `predicted_error` are), `measured_flip`,
/// `measured_ssim`.
/// Version 3: the choice may be a set of nodes cached together: `node` is then the member ids
/// joined by `+` (`"22+39"`), `node_text` their texts joined by ` + `, `line`/`col` the first
/// member's.
/// Version 4: `motion`, the sessions' motions, the motion exponent, and the prediction carried to
/// a session of other motion.
/// Version 5: `adaptive`, what `emit --adaptive` predicted over the frames' motion (`delta_n` is
/// then the schedule's Δn at the median motion, `predicted_error` the worst frame's), and
/// `reconstruct`, the written variant's reconstruction filter (the node's own, profile version 9).
/// Version 6: `runoff`, the contenders `emit --verify` timed together before writing the fastest
/// measured (absent when nothing raced).
pub const EMIT_REPORT_VERSION: u32 = 6;

fn emit_report_schema() -> String {
    EMIT_REPORT_SCHEMA.into()
}

fn first_version() -> u32 {
    1
}

/// What `emit` chose and wrote (`report.json`). With `--json` this is printed as is.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct EmitReport {
    /// Always [`EMIT_REPORT_SCHEMA`] (absent before version 1: read as version 1).
    #[serde(default = "emit_report_schema")]
    pub schema: String,
    #[serde(default = "first_version")]
    pub version: u32,
    pub profile: String,
    pub shader: String,
    /// The metric `max_error` bounds and `predicted_error` predicts (`l2` before version 2).
    #[serde(default)]
    pub metric: Metric,
    pub max_error: f64,
    /// Node id, `"root"`, a set's member ids joined by `+` (`"22+39"`, version 3), or `null` when
    /// the original shader is kept.
    pub node: Option<String>,
    pub node_text: Option<String>,
    /// Variant strategy of the choice (`3pass`, `2pass`, `fused`).
    #[serde(default)]
    pub strategy: Option<String>,
    /// The written variant's reconstruction filter (`bilinear`, `nearest`, `catmull-rom`; version
    /// 5), as its manifest says.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub reconstruct: Option<String>,
    pub line: Option<u32>,
    pub col: Option<u32>,
    pub delta_n: Option<u32>,
    pub predicted_error: Option<f64>,
    /// PSNR of the MSE measured at the profiled Δn, interpolated between neighbouring periods
    /// (`None` beyond the longest profiled Δn or for a profile that recorded no MSE).
    pub predicted_psnr: Option<f64>,
    pub predicted_ms: Option<f64>,
    pub original_ms: f64,
    pub predicted_speedup: Option<f64>,
    /// Its 95 % interval, where `analyze` timed the node interleaved with the original (profile
    /// version 7 on): the timing model's shape over Δn scaled to that measurement.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub predicted_speedup_ci95: Option<[f64; 2]>,
    /// Why the original shader was kept.
    pub reason: Option<String>,
    pub files: Vec<String>,
    pub measured_error: Option<f64>,
    /// Pixels, over the verified session, where the variant renders a NaN or an infinity and the
    /// original does not (any fails the verification), and where the original itself does (left
    /// out of the error). Absent when 0.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub measured_nonfinite_pixels: Option<u64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub measured_nonfinite_reference_pixels: Option<u64>,
    /// The re-rendered session's PSNR, as `reproj render` reports it.
    pub measured_psnr: Option<f64>,
    /// The re-rendered session's ꟻLIP and SSIM (mean and worst frame), on the profile's
    /// perceptual stride.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub measured_flip: Option<MetricSummary>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub measured_ssim: Option<MetricSummary>,
    /// Median ms per frame of the variant and of the original, timed interleaved in one run
    /// (`reproj-bench`).
    pub measured_ms: Option<f64>,
    pub measured_original_ms: Option<f64>,
    /// Original time over variant time, Hodges–Lehmann over the rounds of the interleaved
    /// timing, and its 95 % interval; `--min-speedup` gates on the interval's lower end.
    pub measured_speedup: Option<f64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub measured_speedup_ci95: Option<[f64; 2]>,
    /// Rounds of the interleaved timing.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub measured_rounds: Option<u32>,
    /// The machine the measured speed comes from (adapter, LP_NUM_THREADS, cores; a CPU
    /// rasterizer says so).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub measured_on: Option<String>,
    /// What the timing saw of the machine (load, drift, a wide interval); empty when clean.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub timing_warnings: Vec<String>,
    pub adapter: String,
    /// With several profiles (`--profile A --profile B`, one per session): each session's
    /// prediction for the choice, which holds the budget on every one. Absent with one profile.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub sessions: Vec<ScenePrediction>,
    /// The sessions' motions and what emit did with them (version 4; absent before).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub motion: Option<crate::motion::MotionReport>,
    /// With `--adaptive` (version 5): the per-frame prediction of the chosen schedule and the
    /// fastest fixed choice beside it.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub adaptive: Option<crate::motion::AdaptiveReport>,
    /// With `--verify` (version 6): the nodes predicted too close to the choice to tell apart,
    /// timed together interleaved with the original; the written variant is the fastest measured.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub runoff: Option<Runoff>,
}

impl EmitReport {
    /// The report of an emit before its choice is written: what the profile and options say.
    fn empty(
        profile: &Profile,
        profile_path: &Path,
        shader_path: &Path,
        opts: &EmitOptions,
    ) -> EmitReport {
        EmitReport {
            schema: EMIT_REPORT_SCHEMA.into(),
            version: EMIT_REPORT_VERSION,
            profile: profile_path.display().to_string(),
            shader: shader_path.display().to_string(),
            metric: opts.metric,
            max_error: opts.max_error.get(),
            node: None,
            node_text: None,
            strategy: None,
            reconstruct: None,
            line: None,
            col: None,
            delta_n: None,
            predicted_error: None,
            predicted_psnr: None,
            predicted_ms: None,
            original_ms: profile.original.frame_ms,
            predicted_speedup: None,
            predicted_speedup_ci95: None,
            reason: None,
            files: Vec::new(),
            measured_error: None,
            measured_nonfinite_pixels: None,
            measured_nonfinite_reference_pixels: None,
            measured_psnr: None,
            measured_flip: None,
            measured_ssim: None,
            measured_ms: None,
            measured_original_ms: None,
            measured_speedup: None,
            measured_speedup_ci95: None,
            measured_rounds: None,
            measured_on: None,
            timing_warnings: Vec::new(),
            adapter: profile.machine.adapter.clone(),
            sessions: Vec::new(),
            motion: None,
            adaptive: None,
            runoff: None,
        }
    }
}

/// Write the original shader into `opts.out` in place of what [`emit`] wrote there, with
/// `reason` (a verified variant slower than the original beyond doubt, say); plus
/// `report.json`, which keeps `measured`'s sessions, motion, runoff and timing warnings. The
/// shader is copied as it is: [`emit`] checked it was the one profiled.
pub fn keep_original(
    profile: &Profile,
    profile_path: &Path,
    opts: &EmitOptions,
    reason: &str,
    measured: &EmitReport,
) -> Result<EmitReport, EmitError> {
    let shader_path = profile::shader_path_of(profile, profile_path, opts.shader.as_deref())?;
    let mut report = EmitReport::empty(profile, profile_path, &shader_path, opts);
    (report.sessions, report.motion, report.runoff) = (
        measured.sessions.clone(),
        measured.motion.clone(),
        measured.runoff.clone(),
    );
    report.timing_warnings.clone_from(&measured.timing_warnings);
    let staging = reproj_io::StagedDir::new(&opts.out, Replace::OwnFiles(VARIANT_FILES))?;
    write::original(&staging, &opts.out, &shader_path, reason, &mut report)?;
    finish(&mut report, opts, staging)?;
    Ok(report)
}

/// Add `report.json` to the staged output folder and put the folder in place.
fn finish(
    report: &mut EmitReport,
    opts: &EmitOptions,
    staging: reproj_io::StagedDir,
) -> Result<(), EmitError> {
    report
        .files
        .push(opts.out.join("report.json").display().to_string());
    write_report(report, staging.path())?;
    staging.commit()?;
    Ok(())
}

/// Select under the budget and write the result into `opts.out`: the three passes and the
/// manifest, or the original shader unchanged when nothing fits; plus `report.json`.
pub fn emit(
    profile: &Profile,
    profile_path: &Path,
    opts: &EmitOptions,
) -> Result<(EmitReport, Option<Variant>), EmitError> {
    let (shader_path, loaded, shader) =
        load_profiled(profile, profile_path, opts.shader.as_deref())?;
    // `--node N` for a node the shader does not have: the same answer as `instance` and `render`.
    if let Some(NodeChoice::Id(id)) = opts.node
        && loaded.table.get(id).is_none()
    {
        let table = &loaded.table;
        return Err(reproj_instance::InstanceError::UnknownNode {
            id,
            shader: table.shader.clone(),
            min: table.nodes.first().map_or(0, |n| n.id),
            max: table.nodes.last().map_or(0, |n| n.id),
        }
        .into());
    }
    let all = gather(profile, profile_path, opts)?;
    // The cache format (each node's own filter is read by its spec).
    // The profile's filter and cache format name what reproj writes, checked before anything is
    // (each variant's spec reads them again).
    profile_variant_settings(profile, None, profile_path)?;
    let select_opts = select_options(opts);
    let names: Vec<String> = all.iter().map(|(p, _, _)| p.session.path.clone()).collect();
    let chosen = choose(&all, &names, opts, &select_opts);
    // The run-time Δn schedule of the choice (manifest `params.schedule`): at bands of motion
    // around the profiled ones, each from the profile nearest in motion.
    let beta = chosen.motion.as_ref().map_or(1.0, |m| m.exponent.beta);
    let schedule_of = |find: &dyn Fn(&Records) -> Option<NodeRecord>| {
        crate::motion::manifest_schedule(
            all.iter()
                .map(|r| (r.0.motion.as_ref().map(|m| m.pixels_per_frame), find(r))),
            beta,
            &select_opts,
        )
    };
    let mut report = EmitReport::empty(profile, profile_path, &shader_path, opts);
    (report.sessions, report.motion, report.adaptive) =
        (chosen.sessions, chosen.motion, chosen.adaptive);
    let selection = chosen.selection;
    let staging = reproj_io::StagedDir::new(&opts.out, Replace::OwnFiles(VARIANT_FILES))?;
    let w = Writer {
        profile,
        profile_path,
        opts,
        shader_path: &shader_path,
        shader: &shader,
        loaded: &loaded,
        staging: &staging,
    };
    let variant = match selection {
        Selection::Node(choice) => {
            let profiled = Profiled::of_choice(profile, &choice)
                .expect("the selection comes from the profile's nodes and sets");
            let schedule = match profiled {
                Profiled::Set(set) => schedule_of(&|(_, _, sets)| {
                    sets.iter()
                        .find(|r| r.members == set.members && r.strategy == set.strategy)
                        .map(SetRecord::as_node)
                }),
                Profiled::Node(node) => schedule_of(&|(_, nodes, _)| {
                    nodes
                        .iter()
                        .find(|r| r.id == node.id && r.strategy == node.strategy)
                        .cloned()
                }),
            };
            Some(w.variant(&choice, profiled, schedule, &mut report)?)
        }
        Selection::Original { reason } => {
            // A profile that stopped at its ceiling says why better than "no usable node".
            let why = match &profile.ceiling {
                Some(c) if !c.pays && profile.nodes.is_empty() => c.to_string(),
                _ => reason.to_string(),
            };
            w.original(&why, &mut report)?;
            None
        }
    };
    finish(&mut report, opts, staging)?;
    Ok((report, variant))
}

pub use reproj_instance::ir_hash;
/// The error budget and the default refresh periods, as the CLI checks them at its edge.
pub use reproj_select::{Budget, DELTA_N_RANGE, EXTENDED_MAX_DELTA_N};

/// The selector's options of `opts`.
fn select_options(opts: &EmitOptions) -> SelectOptions {
    SelectOptions {
        max_error: opts.max_error,
        min_delta_n: opts.min_delta_n,
        max_delta_n: opts.max_delta_n,
    }
}

/// The selector's records of `profile` and of every `--also` profile (checked to be the same
/// shader), under `opts`' filters: what [`emit`] chooses across.
fn gather<'p>(
    profile: &'p Profile,
    profile_path: &Path,
    opts: &'p EmitOptions,
) -> Result<Vec<Records<'p>>, EmitError> {
    let (records, set_records) = records_of(profile, profile_path, opts)?;
    // Other sessions' profiles of the same shader: the budget must hold on each (worst case).
    let mut all: Vec<Records> = vec![(profile, records, set_records)];
    for (path, other) in &opts.also {
        same_shader(profile, profile_path, other, path)?;
        let (mut nodes, sets) = records_of(other, path, opts)?;
        // A node measured as another variant there (another refresh block or filter, kept by
        // that session's race) is another candidate: it cannot hold the budget for this one.
        nodes.retain(|n| same_variant(profile, other, n.id));
        all.push((other, nodes, sets));
    }
    Ok(all)
}

/// Write `out/report.json`.
pub fn write_report(report: &EmitReport, out: &Path) -> Result<(), EmitError> {
    let mut json = serde_json::to_vec_pretty(report).expect("report serializes");
    json.push(b'\n');
    Ok(reproj_io::write_file(&out.join("report.json"), &json)?)
}
