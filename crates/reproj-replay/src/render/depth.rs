//! Depth passes a session declares (`depth_passes`): every frame, before the shader's own pass,
//! the scene's objects are drawn depth-only with the pass's view-projection into a
//! `depth32float` texture, which the shader reads as its `texture_depth_2d` (a shadow map from a
//! light, or a depth pre-pass from the camera). The pass has its own per-object transforms and
//! a vertex-only pipeline from the generated vertex stage with no fragment inputs; it is submitted
//! on its own, ahead of the frame, so the frame loops do not change.

use std::collections::BTreeMap;
use std::num::NonZeroU64;

use crate::error::ReplayError;
use crate::vertex::{self, TransformUniform, VERTEX_ENTRY};
use reproj_scene::session::{Cull, FrameState, Session};

use super::object::ObjectGpu;
use super::*;

/// One depth pass on the GPU.
pub(super) struct DepthPassGpu {
    /// The depth texture the shader samples.
    pub(super) view: wgpu::TextureView,
    /// Per-object transform buffers and their bind groups, in object order.
    transforms: Vec<(wgpu::Buffer, wgpu::BindGroup)>,
    /// Depth-only pipelines by cull mode.
    pipelines: Vec<(Cull, wgpu::RenderPipeline)>,
}

impl Renderer {
    /// The GPU side of the session's depth pass filling depth texture `name`: the texture, the
    /// per-object transforms, a depth-only pipeline per cull mode the objects use.
    pub(super) fn depth_pass(
        &self,
        session: &Session,
        name: &str,
        objects: &[ObjectGpu],
        vertex_bgl: &wgpu::BindGroupLayout,
    ) -> Result<DepthPassGpu, ReplayError> {
        let spec = &session.depth_passes[name];
        let [w, h] = spec.size.unwrap_or(session.resolution);
        let tex = self.device.create_texture(&wgpu::TextureDescriptor {
            label: Some(name),
            size: wgpu::Extent3d {
                width: w,
                height: h,
                depth_or_array_layers: 1,
            },
            mip_level_count: 1,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format: DEPTH_FORMAT,
            usage: wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::TEXTURE_BINDING,
            view_formats: &[],
        });
        let view = tex.create_view(&Default::default());
        let transforms = self.depth_transforms(name, objects.len(), vertex_bgl);
        let vs_src = vertex::vertex_wgsl(0, &[], &session.inputs, None)?;
        let vs = self.shader_module("replay depth pass vertex stage", &vs_src)?;
        let layout = self
            .device
            .create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
                label: Some(name),
                bind_group_layouts: &[Some(vertex_bgl)],
                immediate_size: 0,
            });
        let mut pipelines = Vec::new();
        for cull in [Cull::Back, Cull::None] {
            if !objects.iter().any(|o| o.cull == cull) {
                continue;
            }
            let p = self.scoped(&format!("depth pass `{name}`"), || {
                self.depth_pipeline(name, &layout, &vs, cull)
            })?;
            pipelines.push((cull, p));
        }
        Ok(DepthPassGpu {
            view,
            transforms,
            pipelines,
        })
    }

    /// The pass's own transform buffer and bind group for each of `objects` objects.
    fn depth_transforms(
        &self,
        name: &str,
        objects: usize,
        vertex_bgl: &wgpu::BindGroupLayout,
    ) -> Vec<(wgpu::Buffer, wgpu::BindGroup)> {
        let dev = &self.device;
        (0..objects)
            .map(|i| {
                let buf = dev.create_buffer(&wgpu::BufferDescriptor {
                    label: Some(&format!("{name}: object {i} transforms")),
                    size: std::mem::size_of::<TransformUniform>() as u64,
                    usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
                    mapped_at_creation: false,
                });
                let bg = dev.create_bind_group(&wgpu::BindGroupDescriptor {
                    label: Some(name),
                    layout: vertex_bgl,
                    entries: &[wgpu::BindGroupEntry {
                        binding: 0,
                        resource: wgpu::BindingResource::Buffer(wgpu::BufferBinding {
                            buffer: &buf,
                            offset: 0,
                            size: NonZeroU64::new(std::mem::size_of::<TransformUniform>() as u64),
                        }),
                    }],
                });
                (buf, bg)
            })
            .collect()
    }

    /// The depth-only pipeline of the pass for objects of `cull`.
    fn depth_pipeline(
        &self,
        name: &str,
        layout: &wgpu::PipelineLayout,
        vs: &wgpu::ShaderModule,
        cull: Cull,
    ) -> wgpu::RenderPipeline {
        let attrs = wgpu::vertex_attr_array![0 => Float32x3, 1 => Float32x3, 2 => Float32x2, 3 => Float32x4];
        self.device
            .create_render_pipeline(&wgpu::RenderPipelineDescriptor {
                label: Some(name),
                layout: Some(layout),
                vertex: wgpu::VertexState {
                    module: vs,
                    entry_point: Some(VERTEX_ENTRY),
                    compilation_options: Default::default(),
                    buffers: &[Some(wgpu::VertexBufferLayout {
                        array_stride: std::mem::size_of::<reproj_scene::mesh::Vertex>() as u64,
                        step_mode: wgpu::VertexStepMode::Vertex,
                        attributes: &attrs,
                    })],
                },
                primitive: wgpu::PrimitiveState {
                    topology: wgpu::PrimitiveTopology::TriangleList,
                    front_face: wgpu::FrontFace::Ccw,
                    cull_mode: (cull == Cull::Back).then_some(wgpu::Face::Back),
                    ..Default::default()
                },
                depth_stencil: Some(wgpu::DepthStencilState {
                    format: DEPTH_FORMAT,
                    depth_write_enabled: Some(true),
                    depth_compare: Some(wgpu::CompareFunction::Less),
                    stencil: Default::default(),
                    bias: Default::default(),
                }),
                multisample: Default::default(),
                fragment: None,
                multiview_mask: None,
                cache: None,
            })
    }

    /// Draw every depth pass of the frame `st` and submit them (ahead of the frame's own work).
    pub(super) fn render_depth_passes(
        &self,
        session: &Session,
        passes: &BTreeMap<String, DepthPassGpu>,
        objects: &[ObjectGpu],
        st: &FrameState,
    ) {
        let mut enc = self.device.create_command_encoder(&Default::default());
        for (name, pass) in passes {
            let vp = session.depth_view_proj(&session.depth_passes[name], st);
            for ((buf, _), model) in pass.transforms.iter().zip(&st.models) {
                let u = TransformUniform::new(vp, vp, *model, *model);
                self.queue.write_buffer(buf, 0, bytemuck::bytes_of(&u));
            }
            let mut rp = enc.begin_render_pass(&wgpu::RenderPassDescriptor {
                label: Some(name),
                color_attachments: &[],
                depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                    view: &pass.view,
                    depth_ops: Some(wgpu::Operations {
                        load: wgpu::LoadOp::Clear(1.0),
                        store: wgpu::StoreOp::Store,
                    }),
                    stencil_ops: None,
                }),
                timestamp_writes: None,
                occlusion_query_set: None,
                multiview_mask: None,
            });
            for (o, (_, bg)) in objects.iter().zip(&pass.transforms) {
                if let Some((_, p)) = pass.pipelines.iter().find(|(c, _)| *c == o.cull) {
                    rp.set_pipeline(p);
                }
                rp.set_bind_group(0, bg, &[]);
                rp.set_vertex_buffer(0, o.vbuf.slice(..));
                rp.set_index_buffer(o.ibuf.slice(..), wgpu::IndexFormat::Uint32);
                rp.draw_indexed(0..o.count, 0, 0..1);
            }
        }
        self.queue.submit([enc.finish()]);
    }
}
