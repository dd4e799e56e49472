//! The reference renders: the original shader over the session, as it is (`render_original`),
//! jittered, or scored against a reference; the frame counts and size checks they share, and
//! their report. The loop itself, pass and targets, is in `plain`.

use reproj_front::Shader;

use crate::error::ReplayError;
use crate::jitter::Jitter;
use reproj_metrics::RenderReport;
use reproj_metrics::l2;
use reproj_scene::session::Session;

use super::*;

mod plain;

pub(super) use plain::PlainPass;
use plain::{Keep, Plain};

impl Renderer {
    /// How many frames a render draws: the session's from `first_frame` on, at most
    /// `max_frames`, at least one.
    pub(super) fn frame_count(session: &Session, opts: &RenderOptions) -> u32 {
        let left = session.frames.saturating_sub(opts.first_frame);
        opts.max_frames.map_or(left, |m| m.min(left)).max(1)
    }

    /// Refuse, before allocating anything, a render the adapter or the machine cannot hold: a
    /// side past the adapter's largest texture, or reference frames (kept on the GPU and, read
    /// back, on the CPU: about 40 bytes per pixel per frame, plus the targets) past the memory
    /// the machine has available.
    pub(super) fn check_size(
        &self,
        session: &Session,
        frames: u32,
        keeps_frames: bool,
    ) -> Result<(), ReplayError> {
        let [w, h] = session.resolution;
        let max_side = self.device.limits().max_texture_dimension_2d;
        if w > max_side || h > max_side {
            return Err(ReplayError::TooLarge {
                session: session.display_name(),
                what: format!(
                    "its resolution {w}×{h} is past {}'s largest texture side, {max_side}",
                    self.adapter_info.name
                ),
            });
        }
        let pixels = u64::from(w) * u64::from(h);
        let per_frame = if keeps_frames { 40 } else { 0 };
        let need = pixels * (per_frame * u64::from(frames) + 160);
        if let Some(available) = available_memory()
            && need > available
        {
            let fits = (available / pixels.max(1)).saturating_sub(160) / per_frame.max(1);
            return Err(ReplayError::TooLarge {
                session: session.display_name(),
                what: format!(
                    "{frames} frames at {w}×{h} need about {:.1} GiB for the reference frames and targets, and {:.1} GiB are available; replay fewer frames (--max-frames {}) or a lower resolution",
                    need as f64 / (1u64 << 30) as f64,
                    available as f64 / (1u64 << 30) as f64,
                    fits.max(1)
                ),
            });
        }
        Ok(())
    }

    /// The first frame a render draws (`first_frame`, checked against the session).
    pub(super) fn first_frame(session: &Session, opts: &RenderOptions) -> Result<u32, ReplayError> {
        if opts.first_frame >= session.frames {
            return Err(ReplayError::Variant {
                message: format!(
                    "first frame {} is past the session's {} frames",
                    opts.first_frame, session.frames
                ),
            });
        }
        Ok(opts.first_frame)
    }

    /// Render the original shader's fragment entry `entry_index` over the session: the reference
    /// frames (kept in memory) and a report with frame times and shaded-pixel counts.
    pub fn render_original(
        &self,
        shader: &Shader,
        entry_index: usize,
        session: &Session,
        opts: &RenderOptions,
    ) -> Result<Reference, ReplayError> {
        self.render_original_with(shader, entry_index, session, opts, &())
    }

    /// [`Renderer::render_original`] with the projection moved by `jitter` each frame (one
    /// sample of a supersampled reference: [`Jitter::Fixed`]).
    pub fn render_original_jittered(
        &self,
        shader: &Shader,
        entry_index: usize,
        session: &Session,
        opts: &RenderOptions,
        jitter: Jitter,
    ) -> Result<Reference, ReplayError> {
        self.render_reference(shader, entry_index, session, opts, &(), jitter)
    }

    /// [`Renderer::render_original`], telling `progress` as frames come back.
    pub fn render_original_with(
        &self,
        shader: &Shader,
        entry_index: usize,
        session: &Session,
        opts: &RenderOptions,
        progress: &dyn FrameProgress,
    ) -> Result<Reference, ReplayError> {
        self.render_reference(shader, entry_index, session, opts, progress, Jitter::None)
    }

    /// The frames kept as a [`Reference`]; refused where no frame covers a pixel.
    fn render_reference(
        &self,
        shader: &Shader,
        entry_index: usize,
        session: &Session,
        opts: &RenderOptions,
        progress: &dyn FrameProgress,
        jitter: Jitter,
    ) -> Result<Reference, ReplayError> {
        let keep = Keep::Frames;
        let plain = Plain { keep, jitter };
        let (report, kept) =
            self.render_plain(shader, entry_index, session, opts, progress, plain)?;
        let kept = kept.expect("Keep::Frames keeps the frames");
        if !opts.timing_only && report.frames.iter().all(|f| f.covered == 0) {
            return Err(ReplayError::NothingCovered {
                session: session.display_name(),
                frames: report.frames.len() as u32,
            });
        }
        let [w, h] = session.resolution;
        Ok(Reference {
            width: w,
            height: h,
            frames: kept.0,
            depth: kept.1,
            report,
            gpu: kept.2,
        })
    }

    /// Render another shader of the original's kind (no cache: a simplified or resized shader)
    /// over the session and score each frame against `reference` as a variant's replay does: the
    /// error reduced on the GPU, ꟻLIP and SSIM at `opts.perceptual_stride`. No frame is kept, so
    /// at 1080p this costs the frames' rendering and the sampled frames' metrics, not 33 MB per
    /// frame of readback and a CPU pass over each.
    pub fn render_scored(
        &self,
        shader: &Shader,
        entry_index: usize,
        session: &Session,
        reference: &Reference,
        opts: &RenderOptions,
    ) -> Result<RenderReport, ReplayError> {
        let frames = Self::frame_count(session, opts);
        let first = Self::first_frame(session, opts)?;
        let [w, h] = session.resolution;
        reference.covers([w, h], first + frames)?;
        let opts = RenderOptions {
            png_dir: None,
            timing_only: false,
            ..opts.clone()
        };
        let (report, _) = self.render_plain(
            shader,
            entry_index,
            session,
            &opts,
            &(),
            Plain {
                keep: Keep::ScoreAgainst(reference),
                jitter: Jitter::None,
            },
        )?;
        Ok(report)
    }

    pub(super) fn new_report(
        &self,
        kind: &str,
        shader: &Shader,
        entry: &str,
        session: &Session,
    ) -> RenderReport {
        RenderReport {
            schema: reproj_metrics::RENDER_REPORT_SCHEMA.into(),
            version: reproj_metrics::RENDER_REPORT_VERSION,
            kind: kind.into(),
            shader: shader.path.display().to_string(),
            entry: entry.into(),
            session: session.display_name(),
            resolution: session.resolution,
            adapter: self.adapter_info.clone(),
            timing: self.timing_method(),
            node: None,
            delta_n: None,
            block: None,
            depth_epsilon: None,
            error: 0.0,
            error_worst: None,
            flip: None,
            ssim: None,
            mse: 0.0,
            psnr: l2::PSNR_CAP,
            hit_rate: 0.0,
            frame_ms: 0.0,
            cpu_ms: 0.0,
            nonfinite_pixels: 0,
            nonfinite_reference_pixels: 0,
            frames: Vec::new(),
        }
    }
}

/// The memory the machine has available (`MemAvailable` in `/proc/meminfo`), in bytes; `None`
/// where that cannot be read (not Linux).
pub fn available_memory() -> Option<u64> {
    let text = std::fs::read_to_string("/proc/meminfo").ok()?;
    let line = text.lines().find(|l| l.starts_with("MemAvailable:"))?;
    let kib: u64 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kib * 1024)
}
