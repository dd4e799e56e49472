//! Temporal upsampling, the peer engines ship (FSR 2, TSR, Bevy's TAA): the original drawn at a
//! lower resolution with a Halton sub-pixel jitter, then one full-screen resolve pass at the
//! session's resolution (`upsample.wgsl`) that reprojects last frame's output with the motion
//! pass's vectors, clips it to the current samples' neighbourhood and accumulates the jittered
//! samples into it. A frame's time is the low-resolution draw and the resolve (timestamps from the
//! first's start to the second's end); the motion pass stands for the engine's velocity pass,
//! drawn before them and not timed, as for a variant that reads motion vectors.

use bytemuck::{Pod, Zeroable};
use reproj_front::Shader;
use reproj_metrics::{FrameRecord, RenderReport};
use reproj_scene::reflect;
use reproj_scene::session::Session;

use super::original::PlainPass;
use super::variant::motion::{self, MotionGpu};
use super::*;
use crate::jitter::Jitter;

const RESOLVE_WGSL: &str = include_str!("upsample.wgsl");

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

/// The resolve's uniforms (`Params` in `upsample.wgsl`).
#[repr(C)]
#[derive(Debug, Clone, Copy, Pod, Zeroable)]
struct Params {
    full: [f32; 2],
    low: [f32; 2],
    jitter: [f32; 2],
    max_weight: f32,
    reset: u32,
    sigma_out: f32,
    sigma_low: f32,
    clip_still: f32,
    motion_damping: f32,
    clip_moving: f32,
    pad: f32,
}

/// The resolve pass: its pipeline, the two outputs it alternates between (each frame reads the
/// other as its history), a bind group per direction, and its uniforms.
struct Resolve {
    pipe: wgpu::RenderPipeline,
    outs: [wgpu::Texture; 2],
    views: [wgpu::TextureView; 2],
    /// `groups[i]` writes `outs[i]` and reads `outs[1 - i]`.
    groups: [wgpu::BindGroup; 2],
    params: wgpu::Buffer,
}

/// What the frame loop of an upsampling render draws with.
struct UpsampleGpu {
    low: PlainPass,
    motion: MotionGpu,
    color_view: wgpu::TextureView,
    depth_view: wgpu::TextureView,
    resolve: Resolve,
    clear: wgpu::Color,
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
        let [w, h] = session.resolution;
        let low = [spec.low[0].clamp(1, w), spec.low[1].clamp(1, h)];
        let mut small = session.clone();
        small.resolution = low;
        let frames = Self::frame_count(session, opts);
        let keeps = !opts.timing_only;
        self.check_size(session, frames, keeps)?;
        let first = Self::first_frame(session, opts)?;
        let scale = f64::from(low[0]) / f64::from(w);
        let jitter = Jitter::Halton {
            phases: Jitter::phases_for(scale),
        };
        let gpu = self.upsample_gpu(shader, entry_index, &small, [w, h])?;
        let slots = self.batch_len(frames, Staging::slot_bytes(w, h, 16));
        let q = QueryKit::new(self, 1, 2, slots);
        let staging = keeps.then(|| Staging::new(self, "upsampled readback", w, h, 16, slots));
        let mut rb_bufs = q.read_buffers();
        if let Some(s) = &staging {
            rb_bufs.push(&s.buf);
        }
        let mut report = self.new_report("upsampled", shader, &gpu.low.iface.entry, session);
        let mut kept = Vec::new();
        let end = first + frames;
        let mut batch = FrameBatch::new("upsampled ", slots, end);
        for f in first..end {
            let slot = batch.slot();
            let offset = jitter.offset(f);
            let params = Params {
                full: [w as f32, h as f32],
                low: [low[0] as f32, low[1] as f32],
                jitter: offset,
                max_weight: spec.max_weight,
                reset: u32::from(f == first),
                sigma_out: spec.sigma_out * (1.0 / scale as f32).sqrt(),
                sigma_low: spec.sigma_low,
                clip_still: spec.clip_gamma[0],
                motion_damping: spec.motion_damping,
                clip_moving: spec.clip_gamma[1],
                pad: 0.0,
            };
            self.queue
                .write_buffer(&gpu.resolve.params, 0, bytemuck::bytes_of(&params));
            self.write_frame_uniforms(&small, &gpu.low.scene, f, offset);
            let out = (f % 2) as usize;
            let enc = self.encode_upsampled_frame(&gpu, &q, out, slot);
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
                report.frames.push(upsampled_record(
                    f,
                    span.unwrap_or(cpu_ms),
                    cpu_ms,
                    pass_ms,
                    occ[0],
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

    /// The low-resolution pass (its vertex stage also writing the previous clip position), the
    /// motion pass beside it, the render targets and the resolve.
    fn upsample_gpu(
        &self,
        shader: &Shader,
        entry_index: usize,
        small: &Session,
        full: [u32; 2],
    ) -> Result<UpsampleGpu, ReplayError> {
        let iface = reflect::reflect(&shader.module, &shader.info, entry_index)?;
        let prev_clip = motion::prev_clip_input(&iface.inputs);
        let location = prev_clip.location;
        let low = self.plain_pass(shader, iface, small, Some(prev_clip))?;
        let size = small.resolution;
        let motion =
            self.motion_gpu(size, &low.vs, &low.vs_src, &low.scene, low.vgroup, location)?;
        let color_view = self
            .target("upsampler input", size[0], size[1], FRAME_FORMAT, true)
            .create_view(&Default::default());
        let depth_view = self
            .target("upsampler depth", size[0], size[1], DEPTH_FORMAT, false)
            .create_view(&Default::default());
        let resolve = self.resolve_pass(full, &color_view, &motion.view)?;
        let bg = small.background;
        Ok(UpsampleGpu {
            low,
            motion,
            color_view,
            depth_view,
            resolve,
            clear: wgpu::Color {
                r: bg[0] as f64,
                g: bg[1] as f64,
                b: bg[2] as f64,
                a: bg[3] as f64,
            },
        })
    }

    /// The resolve's pipeline, its two outputs at `full` and their bind groups.
    fn resolve_pass(
        &self,
        full: [u32; 2],
        color: &wgpu::TextureView,
        motion: &wgpu::TextureView,
    ) -> Result<Resolve, ReplayError> {
        if !self
            .device
            .features()
            .contains(wgpu::Features::FLOAT32_FILTERABLE)
        {
            return Err(ReplayError::Unsupported {
                what: format!(
                    "the temporal upsampler filters its 32-bit float history, which {} cannot (wgpu feature FLOAT32_FILTERABLE)",
                    self.adapter_info.name
                ),
            });
        }
        let module = self.shader_module("reproj temporal upsampler", RESOLVE_WGSL)?;
        let texture =
            |binding: u32, sample_type: wgpu::TextureSampleType| wgpu::BindGroupLayoutEntry {
                binding,
                visibility: wgpu::ShaderStages::FRAGMENT,
                ty: wgpu::BindingType::Texture {
                    sample_type,
                    view_dimension: wgpu::TextureViewDimension::D2,
                    multisampled: false,
                },
                count: None,
            };
        let float = wgpu::TextureSampleType::Float { filterable: false };
        let layout = self
            .device
            .create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
                label: Some("upsampler"),
                entries: &[
                    texture(0, float),
                    wgpu::BindGroupLayoutEntry {
                        binding: 1,
                        visibility: wgpu::ShaderStages::FRAGMENT,
                        ty: wgpu::BindingType::Sampler(wgpu::SamplerBindingType::Filtering),
                        count: None,
                    },
                    texture(2, float),
                    texture(3, wgpu::TextureSampleType::Float { filterable: true }),
                    wgpu::BindGroupLayoutEntry {
                        binding: 4,
                        visibility: wgpu::ShaderStages::FRAGMENT,
                        ty: wgpu::BindingType::Buffer {
                            ty: wgpu::BufferBindingType::Uniform,
                            has_dynamic_offset: false,
                            min_binding_size: None,
                        },
                        count: None,
                    },
                ],
            });
        let pipe = self.scoped("the upsampler's pipeline", || {
            let pl = self
                .device
                .create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
                    label: Some("upsampler"),
                    bind_group_layouts: &[Some(&layout)],
                    immediate_size: 0,
                });
            self.device
                .create_render_pipeline(&wgpu::RenderPipelineDescriptor {
                    label: Some("upsampler"),
                    layout: Some(&pl),
                    vertex: wgpu::VertexState {
                        module: &module,
                        entry_point: Some("upsample_vs"),
                        compilation_options: Default::default(),
                        buffers: &[],
                    },
                    fragment: Some(wgpu::FragmentState {
                        module: &module,
                        entry_point: Some("upsample_fs"),
                        compilation_options: Default::default(),
                        targets: &[Some(FRAME_FORMAT.into())],
                    }),
                    primitive: Default::default(),
                    depth_stencil: None,
                    multisample: Default::default(),
                    multiview_mask: None,
                    cache: None,
                })
        })?;
        let params = self.buffer(
            "upsampler params",
            std::mem::size_of::<Params>() as u64,
            wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
        );
        let outs = [0, 1].map(|i| {
            self.target(
                &format!("upsampled {i}"),
                full[0],
                full[1],
                FRAME_FORMAT,
                true,
            )
        });
        let views = [0, 1].map(|i| outs[i].create_view(&Default::default()));
        let sampler = self.device.create_sampler(&wgpu::SamplerDescriptor {
            label: Some("upsampler history"),
            mag_filter: wgpu::FilterMode::Linear,
            min_filter: wgpu::FilterMode::Linear,
            ..Default::default()
        });
        let groups = [0, 1].map(|i| {
            self.device.create_bind_group(&wgpu::BindGroupDescriptor {
                label: Some("upsampler"),
                layout: &layout,
                entries: &[
                    wgpu::BindGroupEntry {
                        binding: 0,
                        resource: wgpu::BindingResource::TextureView(color),
                    },
                    wgpu::BindGroupEntry {
                        binding: 1,
                        resource: wgpu::BindingResource::Sampler(&sampler),
                    },
                    wgpu::BindGroupEntry {
                        binding: 2,
                        resource: wgpu::BindingResource::TextureView(motion),
                    },
                    wgpu::BindGroupEntry {
                        binding: 3,
                        resource: wgpu::BindingResource::TextureView(&views[1 - i]),
                    },
                    wgpu::BindGroupEntry {
                        binding: 4,
                        resource: params.as_entire_binding(),
                    },
                ],
            })
        });
        Ok(Resolve {
            pipe,
            outs,
            views,
            groups,
            params,
        })
    }

    /// One frame's commands: the motion pass (not timed), the low-resolution pass (timestamps
    /// 0, occlusion query 0), the resolve into `outs[out]` (timestamps 1); the queries resolved
    /// into `slot`.
    fn encode_upsampled_frame(
        &self,
        gpu: &UpsampleGpu,
        q: &QueryKit,
        out: usize,
        slot: u32,
    ) -> wgpu::CommandEncoder {
        let p = &gpu.low;
        let mut enc = self.device.create_command_encoder(&Default::default());
        self.encode_motion(&mut enc, &gpu.motion, &p.scene, p.vgroup);
        {
            let mut pass = enc.begin_render_pass(&wgpu::RenderPassDescriptor {
                label: Some("upsampler input"),
                color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                    view: &gpu.color_view,
                    depth_slice: None,
                    resolve_target: None,
                    ops: wgpu::Operations {
                        load: wgpu::LoadOp::Clear(gpu.clear),
                        store: wgpu::StoreOp::Store,
                    },
                })],
                depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                    view: &gpu.depth_view,
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
        }
        {
            let r = &gpu.resolve;
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
                timestamp_writes: q.writes(1),
                occlusion_query_set: None,
                multiview_mask: None,
            });
            pass.set_pipeline(&r.pipe);
            pass.set_bind_group(0, &r.groups[out], &[]);
            pass.draw(0..3, 0..1);
        }
        q.resolve(&mut enc, slot);
        enc
    }
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
