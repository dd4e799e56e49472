//! The frames of each selection, rendered with the replay at report time: the original once (the
//! reference), then each chosen variant over the whole session; for a few frames (the middle one
//! and the one with the largest error) the reference, the variant, its error map (with its colour
//! bar) and its hit map, as PNG bytes.

use std::path::Path;

use reproj_front::Shader;
use reproj_instance::InstanceOptions;
use reproj_metrics::RenderReport;
use reproj_metrics::srgb::frame_to_rgba8;
use reproj_models::Profile;
use reproj_replay::{RenderOptions, Renderer, VariantInput};
use reproj_scene::Session;
use reproj_select::Choice;

use crate::ReportError;

/// One frame of one selection, as PNGs.
#[derive(Debug, Clone)]
pub struct FrameImages {
    /// Frame index in the session.
    pub index: u32,
    /// Why this frame (`middle frame`, `largest error`).
    pub why: &'static str,
    /// This frame's error (mean per-pixel L2).
    pub error: f64,
    pub reference: Vec<u8>,
    pub variant: Vec<u8>,
    pub errmap: Vec<u8>,
    pub hitmap: Option<Vec<u8>>,
}

/// A selection rendered: the replay's report and the chosen frames.
#[derive(Debug, Clone)]
pub struct Rendered {
    pub report: RenderReport,
    pub original_ms: f64,
    pub frames: Vec<FrameImages>,
    /// The variant, for the interleaved timing of every rendered selection together.
    pub input: VariantInput,
    /// Its speedup over the original from that timing (`reproj-bench`), with its 95 % interval;
    /// `None` until timed (or when no frame time was usable).
    pub speedup: Option<f64>,
    pub speedup_ci95: Option<[f64; 2]>,
}

/// The original's replay over the profile's frames.
pub fn reference(
    renderer: &Renderer,
    shader: &Shader,
    profile: &Profile,
    session: &Session,
) -> Result<reproj_replay::Reference, ReportError> {
    let entry = shader.fragment_entry(Some(&profile.entry))?;
    Ok(renderer.render_original(
        shader,
        entry,
        session,
        &RenderOptions {
            png_dir: None,
            max_frames: Some(profile.frames),
            first_frame: 0,
            timing_only: false,
            classify: false,
            raw_frames: false,
            perceptual_stride: None,
        },
    )?)
}

/// Render `choice` (its node or set in the strategy the profile measured, at its Δn) and pick
/// its frames. `loaded` is the profile's shader as `load_profiled` gave it (its node table).
/// Phases: the variant ([`choice_variant`]), its replay, the frames picked ([`picked_frames`])
/// and their images ([`frame_images`]).
pub fn render_choice(
    renderer: &Renderer,
    shader: &Shader,
    loaded: &reproj_front::Loaded,
    profile: &Profile,
    session: &Session,
    reference: &reproj_replay::Reference,
    choice: &Choice,
) -> Result<Rendered, ReportError> {
    let variant = choice_variant(shader, loaded, profile, choice)?;
    let input = VariantInput::new(
        variant.passes.iter().map(|p| p.wgsl.clone()).collect(),
        variant.manifest.clone(),
        choice.delta_n,
    );
    let dir = tempfile::tempdir().map_err(|source| reproj_analyze::AnalyzeError::Io {
        path: std::env::temp_dir(),
        source,
    })?;
    let report = renderer.render_variant(
        shader,
        session,
        &input,
        reference,
        &RenderOptions {
            png_dir: Some(dir.path().to_owned()),
            max_frames: Some(profile.frames),
            first_frame: 0,
            timing_only: false,
            classify: true,
            raw_frames: false,
            // The perceptual metrics on the profile's frames (or analyze's default stride).
            perceptual_stride: Some(
                profile
                    .perceptual_stride
                    .unwrap_or(reproj_analyze::DEFAULT_PERCEPTUAL_STRIDE),
            ),
        },
    )?;
    let picks = picked_frames(&report);
    let frames = frame_images(dir.path(), reference, &report, picks)?;
    Ok(Rendered {
        report,
        original_ms: reference.report.frame_ms,
        frames,
        input,
        speedup: None,
        speedup_ci95: None,
    })
}

/// The variant of `choice`: its node, or its set in one payload, in the strategy and with the
/// settings the profile measured, at the choice's Δn ([`reproj_emit::VariantSpec`]).
fn choice_variant(
    shader: &Shader,
    loaded: &reproj_front::Loaded,
    profile: &Profile,
    choice: &Choice,
) -> Result<reproj_instance::Variant, ReportError> {
    let profile_path = Path::new(&profile.shader.path);
    let spec = reproj_emit::VariantSpec::of_choice(profile, profile_path, choice)?;
    Ok(spec.instance(shader, loaded, &InstanceOptions::default())?)
}

/// The frames shown: the middle one, and the one with the largest error when it is another.
fn picked_frames(report: &RenderReport) -> Vec<(u32, &'static str)> {
    let mut picks: Vec<(u32, &'static str)> = Vec::new();
    let n = report.frames.len() as u32;
    if n > 0 {
        picks.push((n / 2, "middle frame"));
        let worst = report
            .frames
            .iter()
            .max_by(|a, b| a.error.total_cmp(&b.error).then(b.frame.cmp(&a.frame)))
            .map_or(0, |f| f.frame);
        if worst != n / 2 {
            picks.push((worst, "largest error"));
        }
    }
    picks
}

/// The picked frames' images: the reference's (as PNG), and the variant's frame, error map and
/// hit map the replay wrote into `dir`.
fn frame_images(
    dir: &Path,
    reference: &reproj_replay::Reference,
    report: &RenderReport,
    picks: Vec<(u32, &'static str)>,
) -> Result<Vec<FrameImages>, ReportError> {
    let mut frames = Vec::new();
    for (index, why) in picks {
        let read = |name: &str| -> Result<Vec<u8>, ReportError> {
            let p = dir.join(format!("{name}_{index:03}.png"));
            std::fs::read(&p).map_err(|source| {
                ReportError::from(reproj_analyze::AnalyzeError::Io { path: p, source })
            })
        };
        let hitmap = dir
            .join(format!("hitmap_{index:03}.png"))
            .is_file()
            .then(|| read("hitmap"))
            .transpose()?;
        frames.push(FrameImages {
            index,
            why,
            error: report.frames.get(index as usize).map_or(0.0, |f| f.error),
            reference: png(
                reference.width,
                reference.height,
                &frame_to_rgba8(&reference.frames[index as usize]),
            )?,
            variant: read("frame")?,
            errmap: read("errmap")?,
            hitmap,
        });
    }
    Ok(frames)
}

/// RGBA8 pixels as PNG bytes.
fn png(width: u32, height: u32, rgba: &[u8]) -> Result<Vec<u8>, ReportError> {
    use image::ImageEncoder;
    let mut bytes = Vec::new();
    image::codecs::png::PngEncoder::new(&mut bytes)
        .write_image(rgba, width, height, image::ExtendedColorType::Rgba8)
        .map_err(|e| ReportError::Png(e.to_string()))?;
    Ok(bytes)
}

/// The session, read as the replay reads it.
pub fn session(path: &Path) -> Result<Session, ReportError> {
    Session::load(path).map_err(|e| ReportError::from(reproj_replay::ReplayError::from(e)))
}
