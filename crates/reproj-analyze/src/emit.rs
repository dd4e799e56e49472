//! `emit`: select the fastest (node, Δn) under an error budget from a profile and write its passes.
//! Needs no GPU; `verify` re-renders the selection to check the prediction.

use std::path::{Path, PathBuf};

use reproj_front::{LoadOptions, load};
use reproj_instance::{
    CacheFormatChoice, InstanceOptions, NodeSelector, Strategy, Variant, backends::OutputLang,
    instance, write_variant_in,
};
use reproj_models::profile::NodeStatus;
use reproj_models::{Profile, content_hash};
use reproj_replay::metrics::{PSNR_CAP, psnr};
use reproj_replay::{RenderOptions, Renderer, Session, VariantInput};
use reproj_select::{NodeRecord, SelectOptions, Selection, select};
use serde::{Deserialize, Serialize};

use crate::AnalyzeError;

/// Options of [`emit`].
#[derive(Debug, Clone)]
pub struct EmitOptions {
    /// Error budget: mean per-pixel L2 RGB distance to the original.
    pub max_error: f64,
    pub min_delta_n: u32,
    pub max_delta_n: u32,
    /// Directory for the passes and the report.
    pub out: PathBuf,
    pub cache_format: CacheFormatChoice,
    /// Only consider nodes profiled in this strategy (`None`: any).
    pub strategy: Option<Strategy>,
    /// Where the written passes fit in a host: its `group` and `frame_load` are used (the rest
    /// comes from the selection and the profile).
    pub integration: InstanceOptions,
    /// The shader to instance (`None`: the profile's, relative to the profile file). Either way
    /// it must be the shader that was profiled, up to comments and formatting.
    pub shader: Option<PathBuf>,
    /// Languages to write the passes in besides WGSL.
    pub langs: Vec<OutputLang>,
}

/// Schema name of an [`EmitReport`] (`report.json`).
pub const EMIT_REPORT_SCHEMA: &str = "reproj.report";
/// Version of the [`EmitReport`] schema. Bump on any incompatible change.
pub const EMIT_REPORT_VERSION: u32 = 1;

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
    pub max_error: f64,
    /// Node id, `"root"`, or `null` when the original shader is kept.
    pub node: Option<String>,
    pub node_text: Option<String>,
    /// Variant strategy of the choice (`3pass`, `2pass`, `fused`).
    #[serde(default)]
    pub strategy: Option<String>,
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
    /// Why the original shader was kept.
    pub reason: Option<String>,
    pub files: Vec<String>,
    pub measured_error: Option<f64>,
    /// The re-rendered session's PSNR, as `reproj render` reports it.
    pub measured_psnr: Option<f64>,
    pub measured_ms: Option<f64>,
    pub measured_original_ms: Option<f64>,
    pub measured_speedup: Option<f64>,
    pub adapter: String,
}

/// Read a profile, naming the field when it is malformed.
pub fn load_profile(path: &Path) -> Result<Profile, AnalyzeError> {
    let bytes = std::fs::read(path).map_err(|source| AnalyzeError::Io {
        path: path.to_owned(),
        source,
    })?;
    let de = &mut serde_json::Deserializer::from_slice(&bytes);
    let profile: Profile =
        serde_path_to_error::deserialize(de).map_err(|e| AnalyzeError::BadProfile {
            path: path.to_owned(),
            message: format!("at `{}`: {}", e.path(), e.inner()),
        })?;
    if profile.schema != "reproj.profile"
        || !(1..=reproj_models::PROFILE_VERSION).contains(&profile.version)
    {
        return Err(AnalyzeError::BadProfile {
            path: path.to_owned(),
            message: format!(
                "schema {} version {} (this reproj reads reproj.profile version {})",
                profile.schema,
                profile.version,
                reproj_models::PROFILE_VERSION
            ),
        });
    }
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

/// Select under the budget and write the result into `opts.out`: the three passes and the
/// manifest, or the original shader unchanged when nothing fits; plus `report.json`.
pub fn emit(
    profile: &Profile,
    profile_path: &Path,
    opts: &EmitOptions,
) -> Result<(EmitReport, Option<Variant>), AnalyzeError> {
    let shader_path = opts
        .shader
        .clone()
        .unwrap_or_else(|| resolve(&profile.shader.path, profile_path));
    let loaded = load(&shader_path, Some(&profile.entry), &LoadOptions::default())?;
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
    let records: Vec<NodeRecord> = profile
        .nodes
        .iter()
        .filter(|n| n.status == NodeStatus::Ok)
        .filter(|n| opts.strategy.is_none_or(|s| s.name() == n.strategy))
        .map(|n| NodeRecord {
            id: n.id,
            text: n.text.clone(),
            strategy: n.strategy.clone(),
            error: n.error_fit.clone(),
            timing: n.timing_fit.clone(),
            mean_pixels: profile.original.mean_pixels,
        })
        .collect();
    let select_opts = SelectOptions {
        max_error: opts.max_error,
        min_delta_n: opts.min_delta_n,
        max_delta_n: opts.max_delta_n,
    };
    let selection = select(
        &records,
        &profile.hit_rate,
        profile.original.frame_ms,
        &select_opts,
    );
    let mut report = EmitReport {
        schema: EMIT_REPORT_SCHEMA.into(),
        version: EMIT_REPORT_VERSION,
        profile: profile_path.display().to_string(),
        shader: shader_path.display().to_string(),
        max_error: opts.max_error,
        node: None,
        node_text: None,
        strategy: None,
        line: None,
        col: None,
        delta_n: None,
        predicted_error: None,
        predicted_psnr: None,
        predicted_ms: None,
        original_ms: profile.original.frame_ms,
        predicted_speedup: None,
        reason: None,
        files: Vec::new(),
        measured_error: None,
        measured_psnr: None,
        measured_ms: None,
        measured_original_ms: None,
        measured_speedup: None,
        adapter: profile.machine.adapter.clone(),
    };
    let staging = Staging::new(&opts.out)?;
    let variant = match selection {
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
            let variant = instance(
                &shader,
                &loaded.norm,
                &loaded.table,
                sel,
                &InstanceOptions {
                    strategy,
                    reconstruct: Default::default(),
                    cache_format: opts.cache_format,
                    delta_n: choice.delta_n,
                    block: node.block.unwrap_or(profile.block),
                    depth_epsilon: profile.depth_epsilon,
                    group: opts.integration.group,
                    frame_load: opts.integration.frame_load,
                },
            )?;
            write_variant_in(&variant, &staging.path, &opts.langs)?;
            for p in &variant.manifest.passes {
                report
                    .files
                    .push(opts.out.join(&p.file).display().to_string());
            }
            report
                .files
                .push(opts.out.join("manifest.json").display().to_string());
            report.node = Some(if node.root {
                "root".into()
            } else {
                node.id.to_string()
            });
            report.node_text = Some(node.text.clone());
            report.strategy = Some(node.strategy.clone());
            report.line = Some(node.line);
            report.col = Some(node.col);
            report.delta_n = Some(choice.delta_n);
            report.predicted_error = Some(choice.predicted_error);
            report.predicted_psnr = node.mse_at(choice.delta_n).map(psnr);
            report.predicted_ms = Some(choice.predicted_ms);
            report.predicted_speedup = Some(choice.predicted_speedup);
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
            write_atomic(&staging.path.join(&name), &original)?;
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
    write_report(&report, &staging.path)?;
    staging.replace(&opts.out)?;
    Ok((report, variant))
}

/// FNV-1a 64 of the shader's IR written back as WGSL by naga: the same for two sources that differ
/// only in comments and formatting.
pub fn ir_hash(shader: &reproj_front::Shader) -> String {
    let text = reproj_front::validator()
        .validate(&shader.module)
        .ok()
        .and_then(|info| reproj_instance::write_wgsl(&shader.module, &info).ok())
        .unwrap_or_else(|| shader.source.clone());
    content_hash(text.as_bytes())
}

/// A temporary directory beside the output directory: everything `emit` writes goes there
/// first, then it replaces the output directory whole, so the directory never mixes an old run's
/// files with a new run's and a failure leaves the previous output as it was.
struct Staging {
    path: PathBuf,
    done: bool,
}

impl Staging {
    fn new(out: &Path) -> Result<Staging, AnalyzeError> {
        let io = |path: &Path| {
            let path = path.to_owned();
            move |source| AnalyzeError::Io { path, source }
        };
        check_replaceable(out)?;
        let parent = out
            .parent()
            .filter(|p| !p.as_os_str().is_empty())
            .unwrap_or(Path::new("."));
        std::fs::create_dir_all(parent).map_err(io(parent))?;
        let name = out
            .file_name()
            .map_or_else(|| "out".into(), |n| n.to_string_lossy().into_owned());
        let path = parent.join(format!(".{name}.tmp{}", std::process::id()));
        if path.exists() {
            std::fs::remove_dir_all(&path).map_err(io(&path))?;
        }
        std::fs::create_dir_all(&path).map_err(io(&path))?;
        Ok(Staging { path, done: false })
    }

    /// Put the staged directory in place of `out` (two renames; the old one is removed after).
    fn replace(mut self, out: &Path) -> Result<(), AnalyzeError> {
        let io = |path: &Path| {
            let path = path.to_owned();
            move |source| AnalyzeError::Io { path, source }
        };
        let old = self
            .path
            .with_extension(format!("old{}", std::process::id()));
        let had_old = out.exists();
        if had_old {
            std::fs::rename(out, &old).map_err(io(out))?;
        }
        if let Err(e) = std::fs::rename(&self.path, out) {
            if had_old {
                let _ = std::fs::rename(&old, out);
            }
            return Err(io(out)(e));
        }
        self.done = true;
        if had_old {
            let _ = std::fs::remove_dir_all(&old);
        }
        Ok(())
    }
}

impl Drop for Staging {
    fn drop(&mut self) {
        if !self.done {
            let _ = std::fs::remove_dir_all(&self.path);
        }
    }
}

/// `emit` replaces its output directory whole: refuse one that holds anything it would not
/// have written (a typo'd `--out .` must not delete a project).
fn check_replaceable(out: &Path) -> Result<(), AnalyzeError> {
    if !out.exists() {
        return Ok(());
    }
    let refuse = |why: String| {
        Err(AnalyzeError::Options(format!(
            "refusing to replace {}: {why}; emit replaces its output directory whole, so choose a new or reproj-written --out",
            out.display()
        )))
    };
    if !out.is_dir() {
        return refuse("it is not a directory".into());
    }
    let entries = std::fs::read_dir(out).map_err(|source| AnalyzeError::Io {
        path: out.to_owned(),
        source,
    })?;
    for e in entries.filter_map(Result::ok) {
        let name = e.file_name().to_string_lossy().into_owned();
        let ours = e.file_type().is_ok_and(|t| t.is_file())
            && (name.ends_with(".wgsl") || name.ends_with(".json"));
        if !ours {
            return refuse(format!("it holds `{name}`, which emit does not write"));
        }
    }
    Ok(())
}

/// Re-render the selection over `session`, record measured error and speedup in `report`, and
/// rewrite `out/report.json` (`out`: the directory [`emit`] wrote into; the shader is the one the
/// report names).
pub fn verify(
    report: &mut EmitReport,
    out: &Path,
    variant: Option<&Variant>,
    profile: &Profile,
    session: &Session,
    renderer: &Renderer,
) -> Result<(), AnalyzeError> {
    let shader = reproj_front::load_file(Path::new(&report.shader))?.to_wgsl()?;
    let entry = shader.fragment_entry(Some(&profile.entry))?;
    let opts = RenderOptions {
        png_dir: None,
        max_frames: None,
        classify: false,
        raw_frames: false,
    };
    let reference = renderer.render_original(&shader, entry, session, &opts)?;
    report.measured_original_ms = Some(reference.report.frame_ms);
    match variant {
        None => {
            report.measured_error = Some(0.0);
            report.measured_psnr = Some(PSNR_CAP);
            report.measured_ms = Some(reference.report.frame_ms);
            report.measured_speedup = Some(1.0);
        }
        Some(v) => {
            let input = VariantInput::new(
                v.passes.iter().map(|p| p.wgsl.clone()).collect(),
                v.manifest.clone(),
                report.delta_n.unwrap_or(1),
            );
            let r = renderer.render_variant(&shader, session, &input, &reference, &opts)?;
            report.measured_error = Some(r.error);
            report.measured_psnr = Some(r.psnr).filter(|p| p.is_finite());
            report.measured_ms = Some(r.frame_ms);
            report.measured_speedup =
                (r.frame_ms > 0.0).then(|| reference.report.frame_ms / r.frame_ms);
        }
    }
    write_report(report, out)
}

/// Write `out/report.json`.
fn write_report(report: &EmitReport, out: &Path) -> Result<(), AnalyzeError> {
    let mut json = serde_json::to_vec_pretty(report).expect("report serializes");
    json.push(b'\n');
    write_atomic(&out.join("report.json"), &json)
}

/// Write a file through a temporary name and a rename.
pub fn write_atomic(path: &Path, bytes: &[u8]) -> Result<(), AnalyzeError> {
    let io = |source| AnalyzeError::Io {
        path: path.to_owned(),
        source,
    };
    if let Some(dir) = path.parent().filter(|d| !d.as_os_str().is_empty()) {
        std::fs::create_dir_all(dir).map_err(io)?;
    }
    let tmp = path.with_extension(format!("tmp{}", std::process::id()));
    std::fs::write(&tmp, bytes).map_err(|e| {
        let _ = std::fs::remove_file(&tmp);
        io(e)
    })?;
    std::fs::rename(&tmp, path).map_err(io)
}
