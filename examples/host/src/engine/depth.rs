//! The session's depth passes as the engine draws them: a shadow map from a light's
//! view-projection or a depth pre-pass from the camera, every object drawn depth-only into a
//! `depth32float` texture ahead of the frame, which the shader then samples.

use std::collections::HashMap;

use reproj_scene::Session;
use reproj_scene::mesh;
use reproj_scene::session::{Cull, FrameState};

use super::{DEPTH_FORMAT, Engine, Object, Pipelines, TransformUniform, VERTEX_ENTRY};
use crate::gpu::Gpu;

/// A depth pass the session declares (a shadow map from a light, a depth pre-pass from the
/// camera): every object drawn depth-only with the pass's view-projection, before the frame.
pub(super) struct DepthPass {
    name: String,
    pub(super) view: wgpu::TextureView,
    /// Per-object transform buffers and bind groups (the vertex layout), in object order.
    transforms: Vec<(wgpu::Buffer, wgpu::BindGroup)>,
    pipes: Pipelines,
}

impl DepthPass {
    /// The GPU side of the session's depth pass filling depth texture `name`: a `depth32float`
    /// texture, a transform buffer per object, a depth-only pipeline per culling mode.
    pub(super) fn new(
        gpu: &Gpu,
        session: &Session,
        name: &str,
        objects: &[Object],
        vertex_layout: &wgpu::BindGroupLayout,
    ) -> anyhow::Result<DepthPass> {
        let dev = &gpu.device;
        let [w, h] = session.depth_passes[name]
            .size
            .unwrap_or(session.resolution);
        let view = dev
            .create_texture(&wgpu::TextureDescriptor {
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
                usage: wgpu::TextureUsages::RENDER_ATTACHMENT
                    | wgpu::TextureUsages::TEXTURE_BINDING,
                view_formats: &[],
            })
            .create_view(&Default::default());
        let transforms = objects
            .iter()
            .map(|_| {
                let buf = dev.create_buffer(&wgpu::BufferDescriptor {
                    label: Some(name),
                    size: size_of::<TransformUniform>() as u64,
                    usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
                    mapped_at_creation: false,
                });
                let group = dev.create_bind_group(&wgpu::BindGroupDescriptor {
                    label: Some(name),
                    layout: vertex_layout,
                    entries: &[wgpu::BindGroupEntry {
                        binding: 0,
                        resource: buf.as_entire_binding(),
                    }],
                });
                (buf, group)
            })
            .collect();
        // The same clip-space arithmetic as the engine's vertex stage.
        let vs = Engine::shader_module(
            gpu,
            "host depth pass vertex stage",
            &format!(
                "struct HostObject {{\n    view_proj: mat4x4<f32>,\n    prev_view_proj: mat4x4<f32>,\n    \
                 model: mat4x4<f32>,\n    prev_model: mat4x4<f32>,\n    normal_matrix: mat4x4<f32>,\n}};\n\
                 @group(0) @binding(0) var<uniform> host_object: HostObject;\n\
                 @vertex\nfn {VERTEX_ENTRY}(@location(0) position: vec3<f32>) -> @builtin(position) @invariant vec4<f32> {{\n    \
                 let world = host_object.model * vec4<f32>(position, 1.0);\n    \
                 return host_object.view_proj * world;\n}}\n"
            ),
        )?;
        let layout = dev.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some(name),
            bind_group_layouts: &[Some(vertex_layout)],
            immediate_size: 0,
        });
        let attrs = wgpu::vertex_attr_array![0 => Float32x3];
        let mut pipes = HashMap::new();
        for cull in [Cull::Back, Cull::None] {
            if !objects.iter().any(|o| o.cull == cull) {
                continue;
            }
            let p = dev.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
                label: Some(name),
                layout: Some(&layout),
                vertex: wgpu::VertexState {
                    module: &vs,
                    entry_point: Some(VERTEX_ENTRY),
                    compilation_options: Default::default(),
                    buffers: &[Some(wgpu::VertexBufferLayout {
                        array_stride: size_of::<mesh::Vertex>() as u64,
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
            });
            pipes.insert(cull, p);
        }
        gpu.check(&format!("building depth pass `{name}`"))?;
        Ok(DepthPass {
            name: name.to_owned(),
            view,
            transforms,
            pipes,
        })
    }

    /// Write frame `st`'s transforms: the pass's view-projection and each object's model matrix.
    pub(super) fn write(&self, gpu: &Gpu, session: &Session, st: &FrameState) {
        let vp = session.depth_view_proj(&session.depth_passes[&self.name], st);
        for ((buf, _), model) in self.transforms.iter().zip(&st.models) {
            let u = TransformUniform::new(vp, vp, *model, *model);
            gpu.queue.write_buffer(buf, 0, bytemuck::bytes_of(&u));
        }
    }

    /// Record the pass (after [`DepthPass::write`]) ahead of the frame's own passes.
    pub(super) fn encode(&self, enc: &mut wgpu::CommandEncoder, objects: &[Object]) {
        let mut pass = enc.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some(&self.name),
            color_attachments: &[],
            depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                view: &self.view,
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
        for (o, (_, group)) in objects.iter().zip(&self.transforms) {
            if let Some(p) = self.pipes.get(&o.cull) {
                pass.set_pipeline(p);
            }
            pass.set_bind_group(0, group, &[]);
            pass.set_vertex_buffer(0, o.vbuf.slice(..));
            pass.set_index_buffer(o.ibuf.slice(..), wgpu::IndexFormat::Uint32);
            pass.draw_indexed(0..o.count, 0, 0..1);
        }
    }
}
