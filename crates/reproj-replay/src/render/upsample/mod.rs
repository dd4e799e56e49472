//! Temporal upsampling, the peer engines ship (FSR 2, TSR, Bevy's TAA): the original drawn at a
//! lower resolution with a Halton sub-pixel jitter, then one full-screen resolve pass at the
//! session's resolution (`upsample.wgsl`) that reprojects last frame's output with the motion
//! pass's vectors, clips it to the current samples' neighbourhood and accumulates the jittered
//! samples into it. A frame's time is the low-resolution draw and the resolve (timestamps from the
//! first's start to the second's end); the motion pass stands for the engine's velocity pass,
//! drawn before them and not timed, as for a variant that reads motion vectors.

use reproj_front::Shader;
use reproj_metrics::{FrameRecord, RenderReport};
use reproj_scene::reflect;
use reproj_scene::session::Session;

use super::original::PlainPass;
use super::variant::motion::{self, MotionGpu};
use super::*;
use crate::jitter::Jitter;
use resolve::{Params, Resolve};
use variant::{VariantGpu, VariantPlan};

mod resolve;

/// A temporal upsampling render: the render resolution and the resolve's settings.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct UpsampleSpec {
    /// The render resolution, `[width, height]` (each at most the session's).
    pub low: [u32; 2],
    /// Width (σ, output pixels) of the Gaussian that weights each sample into the history, at
    /// scale 1; it grows with the square root of the upsampling factor, as the samples sit
    /// further apart (0.4 → 0.57 at half the resolution: 31.9 → 33 dB on marble in motion).
    pub sigma_out: f32,
    /// Width (σ, render pixels) of the Gaussian of the frame-alone reconstruction.
    pub sigma_low: f32,
    /// The history is clipped to the samples' mean ± this many standard deviations (YCoCg): for
    /// a still pixel, and for one moving a quarter of an output pixel a frame or more. A still
    /// history may stray further from one frame's samples (it holds many more); a moving one
    /// drifts as it is resampled.
    pub clip_gamma: [f32; 2],
    /// Most weight the history accumulates (a sample's is at most 1): the longest memory.
    pub max_weight: f32,
    /// A pixel moving `m` output pixels a frame keeps at most `max_weight / (1 + motion_damping·m)`:
    /// each reprojection resamples the history and blurs it a little. On marble at half
    /// resolution, 0 lets the history blur below bilinear upsampling within 30 frames (25.5 against
    /// 32 dB); 16 keeps it above (33 dB).
    pub motion_damping: f32,
}

impl UpsampleSpec {
    /// The defaults at render resolution `low`.
    pub fn at(low: [u32; 2]) -> Self {
        UpsampleSpec {
            low,
            sigma_out: 0.4,
            sigma_low: 0.6,
            clip_gamma: [1.25, 1.0],
            max_weight: 16.0,
            motion_damping: 16.0,
        }
    }
}

/// A temporal upsampling render's frames at the session's resolution (RGB; alpha holds the
/// history's weight) and its report.
#[derive(Debug)]
pub struct Upsampled {
    pub frames: Vec<Vec<f32>>,
    pub report: RenderReport,
}

/// What the upsampler draws at the render resolution each frame: the original shader (its own
/// pass, motion pass and targets), or a variant of it, its cache at the render resolution
/// (reproj composed with temporal upsampling; its motion pass is the variant render's).
// One per render: its size does not matter.
#[allow(clippy::large_enum_variant)]
enum LowDraw<'a> {
    Original {
        pass: PlainPass,
        motion: MotionGpu,
        color_view: wgpu::TextureView,
        depth_view: wgpu::TextureView,
    },
    Variant {
        variant: &'a VariantInput,
        plan: VariantPlan,
        gpu: VariantGpu,
    },
}

impl LowDraw<'_> {
    /// The frame at the render resolution and its motion vectors, which the resolve reads.
    fn views(&self) -> (&wgpu::TextureView, &wgpu::TextureView) {
        match self {
            LowDraw::Original {
                motion, color_view, ..
            } => (color_view, &motion.view),
            LowDraw::Variant { gpu, .. } => (
                &gpu.color_view,
                &gpu.motion
                    .as_ref()
                    .expect("the upsampler's variant draws its motion pass")
                    .view,
            ),
        }
    }

    /// Occlusion queries and timed render passes of the low-resolution draw.
    fn queries(&self) -> (u32, u32) {
        match self {
            LowDraw::Original { .. } => (1, 1),
            LowDraw::Variant { plan, .. } => {
                (plan.runtime.pass_count() as u32, plan.render_pass_count)
            }
        }
    }
}

/// What the frame loop of an upsampling render draws with.
struct UpsampleGpu<'a> {
    low: LowDraw<'a>,
    resolve: Resolve,
}

impl Renderer {
    /// Render `shader`'s fragment entry `entry_index` over `session` at `spec.low` with a Halton
    /// jitter ([`Jitter::phases_for`] the scale) and resolve each frame to the session's
    /// resolution ([`UpsampleSpec`]). The history starts empty at `opts.first_frame`. With
    /// `opts.timing_only`, no frame comes back.
    pub fn render_upsampled(
        &self,
        shader: &Shader,
        entry_index: usize,
        session: &Session,
        spec: &UpsampleSpec,
        opts: &RenderOptions,
    ) -> Result<Upsampled, ReplayError> {
        session.validate()?;
        let small = low_session(session, spec);
        let iface = reflect::reflect(&shader.module, &shader.info, entry_index)?;
        let prev_clip = motion::prev_clip_input(&iface.inputs);
        let location = prev_clip.location;
        let pass = self.plain_pass(shader, iface, &small, Some(prev_clip))?;
        let size = small.resolution;
        let motion = self.motion_gpu(
            size,
            &pass.vs,
            &pass.vs_src,
            &pass.scene,
            pass.vgroup,
            location,
        )?;
        let color_view = self
            .target("upsampler input", size[0], size[1], FRAME_FORMAT, true)
            .create_view(&Default::default());
        let depth_view = self
            .target("upsampler depth", size[0], size[1], DEPTH_FORMAT, false)
            .create_view(&Default::default());
        let report = self.new_report("upsampled", shader, &pass.iface.entry, session);
        let low = LowDraw::Original {
            pass,
            motion,
            color_view,
            depth_view,
        };
        self.upsample_frames(low, session, &small, spec, opts, report)
    }

    /// [`Renderer::render_upsampled`] with `variant` (of `shader`) drawn at the render
    /// resolution instead of the original: reproj composed with temporal upsampling, the cache
    /// at the render resolution, the variant's passes and the resolve timed. The projection's
    /// jitter moves the previous frame's matrix too, so the lookup finds the cache where the
    /// previous frame drew it.
    pub fn render_upsampled_variant(
        &self,
        shader: &Shader,
        session: &Session,
        variant: &VariantInput,
        spec: &UpsampleSpec,
        opts: &RenderOptions,
    ) -> Result<Upsampled, ReplayError> {
        session.validate()?;
        let small = low_session(session, spec);
        let no_classify = RenderOptions {
            classify: false,
            ..opts.clone()
        };
        let plan = self.plan_variant(shader, &small, variant, None, &no_classify)?;
        let gpu = self.variant_gpu(&small, variant, &plan, true)?;
        let m = &variant.manifest;
        let mut report = self.new_report("upsampled variant", shader, &m.entry, session);
        report.node = Some(m.node.id.clone());
        report.delta_n = Some(variant.delta_n);
        report.block = Some(variant.block);
        report.depth_epsilon = Some(variant.depth_epsilon);
        let low = LowDraw::Variant { variant, plan, gpu };
        self.upsample_frames(low, session, &small, spec, opts, report)
    }

    /// The frame loop of an upsampling render: per frame the low-resolution draw and the
    /// resolve (timed), its output read back in batches unless timing only.
    fn upsample_frames(
        &self,
        low: LowDraw<'_>,
        session: &Session,
        small: &Session,
        spec: &UpsampleSpec,
        opts: &RenderOptions,
        mut report: RenderReport,
    ) -> Result<Upsampled, ReplayError> {
        let [w, h] = session.resolution;
        let frames = Self::frame_count(session, opts);
        let keeps = !opts.timing_only;
        self.check_size(session, frames, keeps)?;
        let first = Self::first_frame(session, opts)?;
        let scale = f64::from(small.resolution[0]) / f64::from(w);
        let jitter = Jitter::Halton {
            phases: Jitter::phases_for(scale),
        };
        let resolve = {
            let (color, motion) = low.views();
            self.resolve_pass([w, h], color, motion)?
        };
        let gpu = UpsampleGpu { low, resolve };
        let slots = self.batch_len(frames, Staging::slot_bytes(w, h, 16));
        let (occlusion, timed) = gpu.low.queries();
        let q = QueryKit::new(self, occlusion, timed + 1, slots);
        let staging = keeps.then(|| Staging::new(self, "upsampled readback", w, h, 16, slots));
        let mut rb_bufs = q.read_buffers();
        if let Some(s) = &staging {
            rb_bufs.push(&s.buf);
        }
        let mut kept = Vec::new();
        let end = first + frames;
        let mut batch = FrameBatch::new("upsampled ", slots, end);
        for f in first..end {
            let slot = batch.slot();
            let params = Params {
                full: [w as f32, h as f32],
                low: small.resolution.map(|x| x as f32),
                jitter: jitter.offset(f),
                max_weight: spec.max_weight,
                reset: u32::from(f == first),
                sigma_out: spec.sigma_out * (1.0 / scale as f32).sqrt(),
                sigma_low: spec.sigma_low,
                clip_still: spec.clip_gamma[0],
                motion_damping: spec.motion_damping,
                clip_moving: spec.clip_gamma[1],
                pad: 0.0,
                prev_jitter: jitter.offset(f.saturating_sub(1)),
            };
            self.queue
                .write_buffer(&gpu.resolve.params, 0, bytemuck::bytes_of(&params));
            let out = (f % 2) as usize;
            let enc = self.encode_upsampled_frame(&gpu, small, &jitter, f, first, &q, slot)?;
            let mut rb = self.device.create_command_encoder(&Default::default());
            if let Some(s) = &staging {
                s.copy(&mut rb, &gpu.resolve.outs[out], slot);
            }
            if !batch.submit(self, enc, rb, f)? {
                continue;
            }
            batch.read_back(self, &rb_bufs, |slot, f, cpu_ms| {
                let (occ, pass_ms, span) = q.read(slot)?;
                let pixels: Vec<f32> = match &staging {
                    Some(s) => bytemuck::pod_collect_to_vec(&s.image(slot)?),
                    None => Vec::new(),
                };
                let shaded = match &gpu.low {
                    LowDraw::Original { .. } => occ[0],
                    LowDraw::Variant { variant, .. } => {
                        variant::counts_of(variant.manifest.strategy, &occ, None).shaded
                    }
                };
                report.frames.push(upsampled_record(
                    f,
                    span.unwrap_or(cpu_ms),
                    cpu_ms,
                    pass_ms,
                    shaded,
                ));
                if keeps {
                    kept.push(pixels);
                }
                Ok(())
            })?;
        }
        report.summarize();
        Ok(Upsampled {
            frames: kept,
            report,
        })
    }

    /// Frame `f`'s commands: the low-resolution draw with its uniforms written (its passes timed
    /// first, its motion pass before them untimed), the resolve into `outs[f % 2]` (the last
    /// timestamps); the queries resolved into `slot`.
    #[allow(clippy::too_many_arguments)]
    fn encode_upsampled_frame(
        &self,
        gpu: &UpsampleGpu<'_>,
        small: &Session,
        jitter: &Jitter,
        f: u32,
        first: u32,
        q: &QueryKit,
        slot: u32,
    ) -> Result<wgpu::CommandEncoder, ReplayError> {
        let mut enc = self.device.create_command_encoder(&Default::default());
        let timed = match &gpu.low {
            LowDraw::Original {
                pass: p,
                motion,
                color_view,
                depth_view,
            } => {
                self.write_frame_uniforms(small, &p.scene, f, jitter);
                self.encode_motion(&mut enc, motion, &p.scene, p.vgroup);
                let clear = background_color(small);
                let mut pass = enc.begin_render_pass(&wgpu::RenderPassDescriptor {
                    label: Some("upsampler input"),
                    color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                        view: color_view,
                        depth_slice: None,
                        resolve_target: None,
                        ops: wgpu::Operations {
                            load: wgpu::LoadOp::Clear(clear),
                            store: wgpu::StoreOp::Store,
                        },
                    })],
                    depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                        view: depth_view,
                        depth_ops: Some(wgpu::Operations {
                            load: wgpu::LoadOp::Clear(1.0),
                            store: wgpu::StoreOp::Store,
                        }),
                        stencil_ops: None,
                    }),
                    timestamp_writes: q.writes(0),
                    occlusion_query_set: Some(&q.occlusion),
                    multiview_mask: None,
                });
                pass.begin_occlusion_query(0);
                self.draw(&mut pass, &p.pipe, &p.bindings, &p.scene, p.vgroup);
                pass.end_occlusion_query();
                1
            }
            LowDraw::Variant { variant, plan, gpu } => {
                self.write_frame_uniforms(small, &gpu.scene, f, jitter);
                self.encode_variant_passes_into(&mut enc, gpu, variant, (f, first), q)?;
                plan.render_pass_count
            }
        };
        {
            let r = &gpu.resolve;
            let out = (f % 2) as usize;
            let mut pass = enc.begin_render_pass(&wgpu::RenderPassDescriptor {
                label: Some("upsampler resolve"),
                color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                    view: &r.views[out],
                    depth_slice: None,
                    resolve_target: None,
                    ops: wgpu::Operations {
                        load: wgpu::LoadOp::Clear(wgpu::Color::TRANSPARENT),
                        store: wgpu::StoreOp::Store,
                    },
                })],
                depth_stencil_attachment: None,
                timestamp_writes: q.writes(timed),
                occlusion_query_set: None,
                multiview_mask: None,
            });
            pass.set_pipeline(&r.pipe);
            pass.set_bind_group(0, &r.groups[out], &[]);
            pass.draw(0..3, 0..1);
        }
        q.resolve(&mut enc, slot);
        Ok(enc)
    }
}

/// `session` at the render resolution of `spec` (each side at least 1, at most the session's).
fn low_session(session: &Session, spec: &UpsampleSpec) -> Session {
    let [w, h] = session.resolution;
    let mut small = session.clone();
    small.resolution = [spec.low[0].clamp(1, w), spec.low[1].clamp(1, h)];
    small
}

/// An upsampled frame's record: its time, the low-resolution pass's shaded pixels; no error
/// (the caller scores the frames).
fn upsampled_record(
    frame: u32,
    frame_ms: f64,
    cpu_ms: f64,
    pass_ms: Vec<f64>,
    shaded: u64,
) -> FrameRecord {
    FrameRecord {
        frame,
        frame_ms,
        cpu_ms,
        pass_ms,
        shaded,
        hits: 0,
        recomputes: shaded,
        hit_px: None,
        miss_px: None,
        refresh_px: None,
        hit_rate: 0.0,
        error: 0.0,
        mse: 0.0,
        covered: 0,
        psnr: reproj_metrics::l2::PSNR_CAP,
        max_abs_diff: 0.0,
        nonfinite: 0,
        nonfinite_reference: 0,
        flip: None,
        ssim: None,
    }
}
