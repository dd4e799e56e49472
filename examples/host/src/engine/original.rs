//! The engine's own pass: the original shader drawn over the scene with the layouts the engine
//! reflects from it, as the engine ran before reproj (`reproj-host --original`); and those bind
//! groups, which the variant's passes bind too ([`own_groups`]).

use std::collections::BTreeMap;
use std::num::NonZeroU64;

use anyhow::anyhow;
use reproj_scene::reflect::{self, ResourceKind, TexDim};

use super::{DEPTH_FORMAT, Engine, FRAME_FORMAT, Pipelines};
use crate::gpu::Gpu;

/// The engine's own pass: the original shader, as the engine ran it before reproj.
pub struct Original {
    groups: Vec<OwnGroup>,
    pipes: Pipelines,
}

/// One bind group of the original shader's resources, as the engine binds them.
pub struct OwnGroup {
    pub group: u32,
    /// The layout's entries (a variant that shares this group binds them beside its own).
    pub entries: Vec<wgpu::BindGroupLayoutEntry>,
    pub layout: wgpu::BindGroupLayout,
    pub bind: wgpu::BindGroup,
}

/// The original shader's bind groups, with layouts from the engine's reflection of it.
pub fn own_groups(gpu: &Gpu, engine: &Engine) -> anyhow::Result<Vec<OwnGroup>> {
    let dev = &gpu.device;
    let mut by_group: BTreeMap<u32, Vec<&reflect::Resource>> = BTreeMap::new();
    for r in &engine.iface.resources {
        by_group.entry(r.group).or_default().push(r);
    }
    let mut groups = Vec::new();
    for (g, rs) in &by_group {
        let mut entries = Vec::new();
        let mut binds = Vec::new();
        for r in rs {
            entries.push(wgpu::BindGroupLayoutEntry {
                binding: r.binding,
                visibility: wgpu::ShaderStages::FRAGMENT,
                ty: binding_type(&r.kind),
                count: None,
            });
            binds.push(wgpu::BindGroupEntry {
                binding: r.binding,
                resource: engine
                    .own_resource(r.group, r.binding)
                    .ok_or_else(|| anyhow!("no resource for `{}`", r.name))?,
            });
        }
        let layout = dev.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("original"),
            entries: &entries,
        });
        let bind = dev.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("original"),
            layout: &layout,
            entries: &binds,
        });
        groups.push(OwnGroup {
            group: *g,
            entries,
            layout,
            bind,
        });
    }
    Ok(groups)
}

/// The layout entry type of one of the shader's resources.
fn binding_type(kind: &ResourceKind) -> wgpu::BindingType {
    match kind {
        ResourceKind::Uniform { size, .. } => wgpu::BindingType::Buffer {
            ty: wgpu::BufferBindingType::Uniform,
            has_dynamic_offset: false,
            min_binding_size: NonZeroU64::new(u64::from(*size)),
        },
        ResourceKind::Storage(_) => wgpu::BindingType::Buffer {
            ty: wgpu::BufferBindingType::Storage { read_only: true },
            has_dynamic_offset: false,
            min_binding_size: None,
        },
        ResourceKind::DepthTexture => wgpu::BindingType::Texture {
            sample_type: wgpu::TextureSampleType::Depth,
            view_dimension: wgpu::TextureViewDimension::D2,
            multisampled: false,
        },
        ResourceKind::Sampler { comparison: true } => {
            wgpu::BindingType::Sampler(wgpu::SamplerBindingType::Comparison)
        }
        ResourceKind::Texture { dim } => wgpu::BindingType::Texture {
            sample_type: wgpu::TextureSampleType::Float { filterable: true },
            view_dimension: match dim {
                TexDim::D2 => wgpu::TextureViewDimension::D2,
                TexDim::D2Array => wgpu::TextureViewDimension::D2Array,
                TexDim::D3 => wgpu::TextureViewDimension::D3,
                TexDim::Cube => wgpu::TextureViewDimension::Cube,
            },
            multisampled: false,
        },
        _ => wgpu::BindingType::Sampler(wgpu::SamplerBindingType::Filtering),
    }
}

impl Original {
    pub fn new(gpu: &Gpu, engine: &Engine) -> anyhow::Result<Original> {
        let dev = &gpu.device;
        let vs_src = engine.vertex_wgsl(None)?;
        let vs = Engine::shader_module(gpu, "host vertex stage", &vs_src)?;
        let fs = Engine::shader_module(gpu, "original shader", &engine.shader_source)?;
        // Layouts from the engine's reflection of its own shader.
        let groups = own_groups(gpu, engine)?;
        let layouts: BTreeMap<u32, &wgpu::BindGroupLayout> =
            groups.iter().map(|g| (g.group, &g.layout)).collect();
        let top = layouts
            .keys()
            .copied()
            .chain([engine.vertex_group])
            .max()
            .unwrap_or(0);
        let bgls: Vec<Option<&wgpu::BindGroupLayout>> = (0..=top)
            .map(|g| {
                if g == engine.vertex_group {
                    Some(engine.vertex_layout())
                } else {
                    layouts.get(&g).copied()
                }
            })
            .collect();
        let layout = dev.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("original"),
            bind_group_layouts: &bgls,
            immediate_size: 0,
        });
        let pipes = engine.pipelines(
            gpu,
            "original",
            &layout,
            &vs,
            &fs,
            &engine.iface.entry,
            &[Some(wgpu::ColorTargetState {
                format: FRAME_FORMAT,
                blend: None,
                write_mask: wgpu::ColorWrites::ALL,
            })],
            wgpu::DepthStencilState {
                format: DEPTH_FORMAT,
                depth_write_enabled: Some(true),
                depth_compare: Some(wgpu::CompareFunction::Less),
                stencil: Default::default(),
                bias: Default::default(),
            },
        );
        gpu.check("building the original shader's pipeline")?;
        Ok(Original { groups, pipes })
    }

    /// Record the frame: clear color and depth, draw the scene with the original shader.
    pub fn encode(
        &self,
        enc: &mut wgpu::CommandEncoder,
        engine: &Engine,
        timer: &crate::gpu::Timer,
    ) {
        let mut pass = enc.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("original"),
            color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                view: &engine.frame_view,
                depth_slice: None,
                resolve_target: None,
                ops: wgpu::Operations {
                    load: wgpu::LoadOp::Clear(engine.clear),
                    store: wgpu::StoreOp::Store,
                },
            })],
            depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                view: &engine.depth_view,
                depth_ops: Some(wgpu::Operations {
                    load: wgpu::LoadOp::Clear(1.0),
                    store: wgpu::StoreOp::Store,
                }),
                stencil_ops: None,
            }),
            timestamp_writes: timer.writes(0),
            occlusion_query_set: None,
            multiview_mask: None,
        });
        for g in &self.groups {
            pass.set_bind_group(g.group, &g.bind, &[]);
        }
        engine.draw(&mut pass, &self.pipes);
    }
}
