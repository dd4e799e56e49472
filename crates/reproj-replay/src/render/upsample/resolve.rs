//! The resolve pass of the temporal upsampler (`upsample.wgsl`): its uniforms, pipeline, the two
//! outputs it alternates between and their bind groups.

use bytemuck::{Pod, Zeroable};

use super::super::*;

const RESOLVE_WGSL: &str = include_str!("upsample.wgsl");

/// The resolve's uniforms (`Params` in `upsample.wgsl`).
#[repr(C)]
#[derive(Debug, Clone, Copy, Pod, Zeroable)]
pub(super) struct Params {
    pub(super) full: [f32; 2],
    pub(super) low: [f32; 2],
    pub(super) jitter: [f32; 2],
    pub(super) max_weight: f32,
    pub(super) reset: u32,
    pub(super) sigma_out: f32,
    pub(super) sigma_low: f32,
    pub(super) clip_still: f32,
    pub(super) motion_damping: f32,
    pub(super) clip_moving: f32,
    pub(super) pad: f32,
    /// The previous frame's jitter: the motion pass's vectors hold `jitter - prev_jitter`.
    pub(super) prev_jitter: [f32; 2],
}

/// The resolve pass: its pipeline, the two outputs it alternates between (each frame reads the
/// other as its history), a bind group per direction, and its uniforms.
pub(super) struct Resolve {
    pub(super) pipe: wgpu::RenderPipeline,
    pub(super) outs: [wgpu::Texture; 2],
    pub(super) views: [wgpu::TextureView; 2],
    /// `groups[i]` writes `outs[i]` and reads `outs[1 - i]`.
    pub(super) groups: [wgpu::BindGroup; 2],
    pub(super) params: wgpu::Buffer,
}

impl Renderer {
    /// The resolve's pipeline, its two outputs at `full` and their bind groups.
    pub(super) fn resolve_pass(
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
}
