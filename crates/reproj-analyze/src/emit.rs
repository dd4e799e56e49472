//! `emit`: select the fastest (node or set of nodes, Δn) under an error budget from a profile and
//! write its passes.
//! Needs no GPU; [`crate::verify`] re-renders the selection to check the prediction.

use std::path::{Path, PathBuf};

use reproj_front::{LoadOptions, UnrollOptions, load};
use reproj_instance::{
    CacheFormatChoice, InstanceOptions, NodeSelector, Reconstruct, Strategy, VARIANT_FILES,
    Variant, backends::Outputs, instance, instance_nodes, variant_files,
};
use reproj_io::Replace;
use reproj_models::Metric;
use reproj_models::profile::NodeStatus;
use reproj_models::{Profile, content_hash};
use reproj_replay::metrics::{MetricSummary, psnr};
use reproj_select::{
    NodeRecord, Scene, ScenePrediction, SelectOptions, Selection, SetRecord, select_with_sets,
    select_worst_case,
};
use serde::{Deserialize, Serialize};

use crate::AnalyzeError;

/// Options of [`emit`].
#[derive(Debug, Clone)]
pub struct EmitOptions {
    /// Error budget, in the unit of `metric`.
    pub max_error: f64,
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
    /// Where the written passes fit in a host: its `group` and `frame_load` are used (the rest
    /// comes from the selection and the profile).
    pub integration: InstanceOptions,
    /// The shader to instance (`None`: the profile's, relative to the profile file). Either way
    /// it must be the shader that was profiled, up to comments and formatting.
    pub shader: Option<PathBuf>,
    /// Languages to write the passes in besides WGSL, and the values of the override constants.
    pub outputs: Outputs,
    /// Profiles of the same shader over other sessions (path, profile): the selection holds the
    /// budget on every session, the first profile's included ([`select_worst_case`]).
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
pub const EMIT_REPORT_VERSION: u32 = 5;

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
}

/// Read a profile, naming the field when it is malformed.
pub fn load_profile(path: &Path) -> Result<Profile, AnalyzeError> {
    let profile: Profile = reproj_io::read_json(path, &reproj_models::PROFILE_KIND)?;
    profile
        .check()
        .map_err(|(field, message)| reproj_io::ReadError::Field {
            path: path.to_owned(),
            field,
            message,
        })?;
    Ok(profile)
}

/// The most recently modified `*.profile.json` in `dir`.
pub fn latest_profile(dir: &Path) -> Result<PathBuf, AnalyzeError> {
    let entries = std::fs::read_dir(dir).map_err(|source| AnalyzeError::Io {
        path: dir.to_owned(),
        source,
    })?;
    entries
        .filter_map(Result::ok)
        .filter(|e| e.file_name().to_string_lossy().ends_with(".profile.json"))
        .filter_map(|e| Some((e.metadata().ok()?.modified().ok()?, e.path())))
        .max()
        .map(|(_, p)| p)
        .ok_or_else(|| AnalyzeError::Options(format!(
            "no *.profile.json in {}: run `reproj analyze SHADER --session SESSION` first, or pass --profile",
            dir.display()
        )))
}

/// Find a file a profile refers to: relative to the profile's directory (profiles from version 3
/// on record it so), else as recorded (relative to the working directory), else beside the
/// profile.
pub fn resolve(recorded: &str, profile_path: &Path) -> PathBuf {
    let p = PathBuf::from(recorded);
    if p.is_relative()
        && let Some(dir) = profile_path.parent().filter(|d| !d.as_os_str().is_empty())
        && dir.join(&p).exists()
    {
        return dir.join(&p);
    }
    if p.exists() {
        return p;
    }
    match (profile_path.parent(), p.file_name()) {
        (Some(dir), Some(name)) if dir.join(name).exists() => dir.join(name),
        _ => p,
    }
}

/// The shader file a profile names, resolved against the profile's directory. It must be a
/// shader file by its extension: a profile is data from anywhere, and loading what it names
/// shows that file's first lines in a diagnostic (a profile naming `/etc/passwd` must not print
/// it).
pub fn profile_shader(profile: &Profile, profile_path: &Path) -> Result<PathBuf, AnalyzeError> {
    let path = resolve(&profile.shader.path, profile_path);
    if reproj_front::Lang::from_path(&path).is_some() {
        Ok(path)
    } else {
        Err(AnalyzeError::BadProfile {
            path: profile_path.to_owned(),
            message: format!(
                "field `shader.path`: `{}` is not a shader file (.wgsl, .glsl, .frag or .spv)",
                profile.shader.path
            ),
        })
    }
}

/// How the profile's variant of `node` was made (`None`: of its sets): its reconstruction (the
/// node's own, else the profile's) and the cache format, which the written and rendered variants
/// must share to run what was measured.
pub fn profile_variant_settings(
    profile: &Profile,
    node: Option<&reproj_models::profile::NodeProfile>,
    profile_path: &Path,
) -> Result<(Reconstruct, CacheFormatChoice), AnalyzeError> {
    let bad = |field: &str, value: &str| AnalyzeError::BadProfile {
        path: profile_path.to_owned(),
        message: format!("field `{field}`: `{value}` is not one reproj writes"),
    };
    let (field, name) = match node {
        Some(n) if n.reconstruct.is_some() => (
            format!("reconstruct` of node `{}", n.id),
            n.reconstruct_in(profile),
        ),
        _ => ("reconstruct".to_string(), profile.reconstruct.as_str()),
    };
    let reconstruct = Reconstruct::from_name(name).ok_or_else(|| bad(&field, name))?;
    let cache_format = CacheFormatChoice::from_name(&profile.cache_format)
        .ok_or_else(|| bad("cache_format", &profile.cache_format))?;
    Ok((reconstruct, cache_format))
}

/// A profile's usable sets (in `opts.strategy`, when one is named) and the selector records of its
/// usable nodes and sets in `opts.metric`.
#[allow(clippy::type_complexity)]
fn records_of<'p>(
    profile: &'p Profile,
    profile_path: &Path,
    opts: &EmitOptions,
) -> Result<
    (
        Vec<&'p reproj_models::profile::SetProfile>,
        Vec<NodeRecord>,
        Vec<SetRecord>,
    ),
    AnalyzeError,
> {
    let usable: Vec<_> = profile
        .nodes
        .iter()
        .filter(|n| n.status == NodeStatus::Ok)
        .filter(|n| opts.strategy.is_none_or(|s| s.name() == n.strategy))
        .filter(|n| opts.node.is_none_or(|c| c.admits(n)))
        .collect();
    if usable.iter().any(|n| n.fit(opts.metric).is_none()) {
        return Err(AnalyzeError::BadProfile {
            path: profile_path.to_owned(),
            message: format!(
                "it has no {} measurements (profile version {}; they are recorded from version 4): re-run `reproj analyze` to bound {}",
                opts.metric, profile.version, opts.metric
            ),
        });
    }
    let records: Vec<NodeRecord> = usable
        .iter()
        .filter_map(|n| NodeRecord::from_profile(profile, n, opts.metric))
        .collect();
    let usable_sets: Vec<_> = profile
        .sets
        .iter()
        .filter(|s| s.status == NodeStatus::Ok)
        .filter(|s| opts.strategy.is_none_or(|st| st.name() == s.strategy))
        .filter(|_| opts.node.is_none())
        .collect();
    let set_records: Vec<SetRecord> = usable_sets
        .iter()
        .filter_map(|s| {
            Some(SetRecord {
                members: s.members.clone(),
                texts: s.texts.clone(),
                strategy: s.strategy.clone(),
                error: s.fit(opts.metric)?.clone(),
                timing: s.timing_fit.clone(),
                mean_pixels: profile.original.mean_pixels,
                measured_errors: reproj_select::measured_errors(&s.measurements, opts.metric),
            })
        })
        .collect();
    Ok((usable_sets, records, set_records))
}

/// Another session's profile must be of the same shader (IR), entry, unrolling and cache
/// settings as the first: its node ids and variants are then the same ones.
fn same_shader(
    first: &Profile,
    first_path: &Path,
    other: &Profile,
    other_path: &Path,
) -> Result<(), AnalyzeError> {
    let shader = |p: &Profile| {
        p.shader
            .ir_hash
            .clone()
            .unwrap_or_else(|| p.shader.hash.clone())
    };
    let differs = if shader(first) != shader(other) {
        Some("shader")
    } else if first.entry != other.entry {
        Some("entry point")
    } else if first.unroll != other.unroll {
        Some("--unroll")
    } else if first.block != other.block || first.depth_epsilon != other.depth_epsilon {
        Some("block size or depth tolerance")
    } else {
        None
    };
    match differs {
        None => Ok(()),
        Some(what) => Err(AnalyzeError::BadProfile {
            path: other_path.to_owned(),
            message: format!(
                "its {what} differs from {}'s: profiles selected together must be of one shader with one setting, over different sessions",
                first_path.display()
            ),
        }),
    }
}

/// Select under the budget and write the result into `opts.out`: the three passes and the
/// manifest, or the original shader unchanged when nothing fits; plus `report.json`.
pub fn emit(
    profile: &Profile,
    profile_path: &Path,
    opts: &EmitOptions,
) -> Result<(EmitReport, Option<Variant>), AnalyzeError> {
    let shader_path = match &opts.shader {
        Some(s) => s.clone(),
        None => profile_shader(profile, profile_path)?,
    };
    let load_options = LoadOptions {
        unroll: UnrollOptions {
            max_trip: profile.unroll,
        },
        ..Default::default()
    };
    let loaded = load(&shader_path, Some(&profile.entry), &load_options)?;
    // `analyze` profiled (and hashed) the WGSL the replay renders: naga's WGSL for GLSL.
    let shader = loaded.shader.to_wgsl()?;
    let fresh = match &profile.shader.ir_hash {
        Some(h) => ir_hash(&shader) == *h,
        None => content_hash(shader.source.as_bytes()) == profile.shader.hash,
    };
    if !fresh {
        return Err(AnalyzeError::Stale {
            path: shader_path,
            what: "shader".into(),
        });
    }
    let (usable_sets, records, set_records) = records_of(profile, profile_path, opts)?;
    // The sets' reconstruction and the cache format (each node's own filter is read below).
    let (set_reconstruct, profiled_format) = profile_variant_settings(profile, None, profile_path)?;
    let cache_format = opts.cache_format.unwrap_or(profiled_format);
    let select_opts = SelectOptions {
        max_error: opts.max_error,
        min_delta_n: opts.min_delta_n,
        max_delta_n: opts.max_delta_n,
    };
    // Other sessions' profiles of the same shader: the budget must hold on each (worst case).
    let mut others = Vec::new();
    for (path, other) in &opts.also {
        same_shader(profile, profile_path, other, path)?;
        let (_, nodes, sets) = records_of(other, path, opts)?;
        others.push((other, nodes, sets));
    }
    let name = |p: &'_ Profile| p.session.path.clone();
    let names: Vec<String> = std::iter::once(name(profile))
        .chain(others.iter().map(|(p, _, _)| name(p)))
        .collect();
    // Each session's slower and faster halves (per-frame L2 errors, profile version 9).
    let segments: Vec<Vec<crate::motion::Segment>> = std::iter::once((profile, &records))
        .chain(others.iter().map(|(p, n, _)| (*p, n)))
        .map(|(p, nodes)| match opts.metric {
            Metric::L2 => crate::motion::profile_segments(p, nodes),
            Metric::Flip => Vec::new(),
        })
        .collect();
    let profiled: Vec<crate::motion::ProfiledSession> =
        std::iter::once((profile, &records, &set_records))
            .chain(others.iter().map(|(p, n, s)| (*p, n, s)))
            .zip(&names)
            .zip(&segments)
            .map(
                |(((p, nodes, sets), name), segments)| crate::motion::ProfiledSession {
                    name,
                    hash: &p.session.hash,
                    motion: p.motion.as_ref(),
                    nodes,
                    sets,
                    segments,
                },
            )
            .collect();
    let (mut motion, carried) = crate::motion::carry(&profiled, opts.target.as_ref());
    let target_name = opts
        .target
        .as_ref()
        .map(|t| format!("{} (carried)", t.name));
    let mut scenes = vec![Scene {
        name: &names[0],
        nodes: &records,
        sets: &set_records,
        hit_rate: &profile.hit_rate,
        original_ms: profile.original.frame_ms,
    }];
    for ((p, nodes, sets), name) in others.iter().zip(&names[1..]) {
        scenes.push(Scene {
            name,
            nodes,
            sets,
            hit_rate: &p.hit_rate,
            original_ms: p.original.frame_ms,
        });
    }
    if let (Some(c), Some(name)) = (&carried, &target_name) {
        let from = scenes[c.from];
        scenes.push(Scene {
            name,
            nodes: &c.nodes,
            sets: &c.sets,
            ..from
        });
    }
    let (selection, sessions) = if scenes.len() == 1 {
        let selection = select_with_sets(
            &records,
            &set_records,
            &profile.hit_rate,
            profile.original.frame_ms,
            &select_opts,
        );
        (selection, Vec::new())
    } else {
        select_worst_case(&scenes, &select_opts)
    };
    let (selection, adaptive) = match opts.period {
        crate::motion::PeriodChoice::Fixed => (selection, None),
        crate::motion::PeriodChoice::Adaptive => {
            let profiles: Vec<(&Profile, &[NodeRecord], &[SetRecord])> =
                std::iter::once((profile, &records[..], &set_records[..]))
                    .chain(others.iter().map(|(p, n, s)| (*p, &n[..], &s[..])))
                    .collect();
            crate::motion::choose_adaptive(
                &profiles,
                &names,
                opts.target.as_ref(),
                motion.exponent.beta,
                &select_opts,
                &selection,
            )
        }
    };
    if let Some(name) = &target_name {
        motion.target_predicted_error = sessions
            .iter()
            .find(|s| s.session == *name)
            .map(|s| s.predicted_error);
        if let Some(a) = &adaptive {
            // The target's whole-session error, as --verify measures it: the frames' mean.
            motion.target_predicted_error = Some(a.predicted_mean_error);
        }
    }
    let motion = (!motion.profiled.is_empty() || motion.target.is_some()).then_some(motion);
    // The run-time Δn schedule of the choice (manifest `params.schedule`): at bands of motion
    // around the profiled ones, each from the profile nearest in motion.
    let beta = motion.as_ref().map_or(1.0, |m| m.exponent.beta);
    let motions: Vec<Option<f64>> = std::iter::once(profile)
        .chain(others.iter().map(|(p, _, _)| *p))
        .map(|p| p.motion.as_ref().map(|m| m.pixels_per_frame))
        .collect();
    let schedule_of = |find: &dyn Fn(usize) -> Option<NodeRecord>| {
        crate::motion::manifest_schedule(
            motions.iter().enumerate().map(|(i, m)| (*m, find(i))),
            beta,
            &select_opts,
        )
    };
    let nodes_of = |i: usize| -> &[NodeRecord] { if i == 0 { &records } else { &others[i - 1].1 } };
    let sets_of = |i: usize| -> &[SetRecord] {
        if i == 0 {
            &set_records
        } else {
            &others[i - 1].2
        }
    };
    let mut report = EmitReport {
        schema: EMIT_REPORT_SCHEMA.into(),
        version: EMIT_REPORT_VERSION,
        profile: profile_path.display().to_string(),
        shader: shader_path.display().to_string(),
        metric: opts.metric,
        max_error: opts.max_error,
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
        sessions,
        motion,
        adaptive,
    };
    let staging = reproj_io::StagedDir::new(&opts.out, Replace::OwnFiles(VARIANT_FILES))?;
    let variant = match selection {
        Selection::Node(choice) if !choice.members.is_empty() => {
            let set = usable_sets
                .iter()
                .find(|s| s.members == choice.members && s.strategy == choice.strategy)
                .expect("the selection comes from the profile's sets");
            let strategy: Strategy =
                set.strategy
                    .parse()
                    .map_err(|e: String| AnalyzeError::BadProfile {
                        path: profile_path.to_owned(),
                        message: format!("set {}: {e}", set.name()),
                    })?;
            let sels: Vec<NodeSelector> =
                set.members.iter().map(|&id| NodeSelector::Id(id)).collect();
            let mut variant = instance_nodes(
                &shader,
                &loaded.norm,
                &loaded.table,
                &sels,
                &InstanceOptions {
                    strategy,
                    reconstruct: set_reconstruct,
                    cache_format,
                    delta_n: choice.delta_n,
                    block: set.block,
                    depth_epsilon: profile.depth_epsilon,
                    group: opts.integration.group,
                    frame_load: opts.integration.frame_load,
                },
            )?;
            variant.manifest.params.schedule = schedule_of(&|i| {
                sets_of(i)
                    .iter()
                    .find(|r| r.members == set.members && r.strategy == set.strategy)
                    .map(SetRecord::as_node)
            });
            write_variant(&variant, &staging, opts, &mut report)?;
            let first = profile.nodes.iter().find(|n| n.id == set.members[0]);
            report.node = Some(set.name());
            report.node_text = Some(choice.node_text.clone());
            report.strategy = Some(set.strategy.clone());
            report.reconstruct = Some(set_reconstruct.name().into());
            report.line = first.map(|n| n.line);
            report.col = first.map(|n| n.col);
            report.delta_n = Some(choice.delta_n);
            report.predicted_error = Some(choice.predicted_error);
            report.predicted_psnr = set.mse_at(choice.delta_n).map(psnr);
            report.predicted_ms = Some(choice.predicted_ms);
            // The session whose speedup is the lowest (the profile's own with one session).
            report.original_ms = choice.original_ms;
            report.predicted_speedup = Some(choice.predicted_speedup);
            report.predicted_speedup_ci95 = choice.predicted_speedup_ci95;
            Some(variant)
        }
        Selection::Node(choice) => {
            let node = profile
                .nodes
                .iter()
                .find(|n| n.id == choice.node_id && n.strategy == choice.strategy)
                .expect("the selection comes from the profile's nodes");
            let strategy: Strategy =
                node.strategy
                    .parse()
                    .map_err(|e: String| AnalyzeError::BadProfile {
                        path: profile_path.to_owned(),
                        message: format!("node {}: {e}", node.id),
                    })?;
            let sel = if node.root {
                NodeSelector::Root
            } else {
                NodeSelector::Id(node.id)
            };
            let (reconstruct, _) = profile_variant_settings(profile, Some(node), profile_path)?;
            let mut variant = instance(
                &shader,
                &loaded.norm,
                &loaded.table,
                sel,
                &InstanceOptions {
                    strategy,
                    reconstruct,
                    cache_format,
                    delta_n: choice.delta_n,
                    block: node.block.unwrap_or(profile.block),
                    depth_epsilon: profile.depth_epsilon,
                    group: opts.integration.group,
                    frame_load: opts.integration.frame_load,
                },
            )?;
            variant.manifest.params.schedule = schedule_of(&|i| {
                nodes_of(i)
                    .iter()
                    .find(|r| r.id == node.id && r.strategy == node.strategy)
                    .cloned()
            });
            write_variant(&variant, &staging, opts, &mut report)?;
            report.node = Some(if node.root {
                "root".into()
            } else {
                node.id.to_string()
            });
            report.node_text = Some(node.text.clone());
            report.strategy = Some(node.strategy.clone());
            report.reconstruct = Some(reconstruct.name().into());
            report.line = Some(node.line);
            report.col = Some(node.col);
            report.delta_n = Some(choice.delta_n);
            report.predicted_error = Some(choice.predicted_error);
            report.predicted_psnr = node.mse_at(choice.delta_n).map(psnr);
            report.predicted_ms = Some(choice.predicted_ms);
            // The session whose speedup is the lowest (the profile's own with one session).
            report.original_ms = choice.original_ms;
            report.predicted_speedup = Some(choice.predicted_speedup);
            report.predicted_speedup_ci95 = choice.predicted_speedup_ci95;
            Some(variant)
        }
        Selection::Original { reason } => {
            let name = shader_path
                .file_name()
                .map_or_else(|| "original.wgsl".into(), |n| n.to_owned());
            // The file as it was given (GLSL or SPIR-V stay what they were).
            let original = std::fs::read(&shader_path).map_err(|source| {
                AnalyzeError::Front(reproj_front::FrontError::Io {
                    path: shader_path.clone(),
                    source,
                })
            })?;
            staging.write(&name, &original)?;
            report
                .files
                .push(opts.out.join(&name).display().to_string());
            report.reason = Some(reason.to_string());
            None
        }
    };
    report
        .files
        .push(opts.out.join("report.json").display().to_string());
    write_report(&report, staging.path())?;
    staging.commit()?;
    Ok((report, variant))
}

/// Stage the variant's files (passes in every language, manifest) and list them in the report.
fn write_variant(
    variant: &Variant,
    staging: &reproj_io::StagedDir,
    opts: &EmitOptions,
    report: &mut EmitReport,
) -> Result<(), AnalyzeError> {
    for (name, bytes) in variant_files(variant, &opts.outputs)? {
        staging.write(name, &bytes)?;
    }
    for p in &variant.manifest.passes {
        report
            .files
            .push(opts.out.join(&p.file).display().to_string());
    }
    report
        .files
        .push(opts.out.join("manifest.json").display().to_string());
    Ok(())
}

pub use reproj_instance::ir_hash;

/// Write `out/report.json`.
pub(crate) fn write_report(report: &EmitReport, out: &Path) -> Result<(), AnalyzeError> {
    let mut json = serde_json::to_vec_pretty(report).expect("report serializes");
    json.push(b'\n');
    Ok(reproj_io::write_file(&out.join("report.json"), &json)?)
}
