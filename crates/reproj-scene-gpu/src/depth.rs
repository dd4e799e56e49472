//! The depth passes a session declares (`depth_passes`): every frame, before the shader's own
//! pass, the scene's objects are drawn depth-only with the pass's view-projection into a
//! [`DEPTH_FORMAT`] texture, which the shader reads as its `texture_depth_2d` (a shadow map from a
//! light, or a depth pre-pass from the camera). Each pass has its own per-object transforms and a
//! position-only vertex stage whose clip arithmetic is the scene's vertex stage's
//! (`view_proj * (model * position)`, `@invariant`), so a pre-pass from the camera meets the
//! frame's own depth exactly.

use reproj_scene::Session;
use reproj_scene::session::{Cull, FrameState};
use reproj_scene::vertex::TransformUniform;

use crate::DEPTH_FORMAT;
use crate::object::{SceneObject, Transforms};

/// The depth passes' vertex stage: the transforms at group 0 ([`crate::transform_layout`]).
const VERTEX_WGSL: &str = "struct DepthTransform {
    view_proj: mat4x4<f32>,
    prev_view_proj: mat4x4<f32>,
    model: mat4x4<f32>,
    prev_model: mat4x4<f32>,
    normal_matrix: mat4x4<f32>,
};
@group(0) @binding(0) var<uniform> depth_xf: DepthTransform;
@vertex
fn depth_vs(@location(0) position: vec3<f32>) -> @builtin(position) @invariant vec4<f32> {
    let world = depth_xf.model * vec4<f32>(position, 1.0);
    return depth_xf.view_proj * world;
}
";

/// One depth pass on the GPU: the texture the shader samples, the objects' transforms in the
/// pass, a depth-only pipeline per cull mode the objects use.
#[derive(Debug)]
pub struct DepthPass {
    name: String,
    /// The depth texture the shader samples.
    pub view: wgpu::TextureView,
    /// Per-object transforms, in object order.
    transforms: Vec<Transforms>,
    pipelines: Vec<(Cull, wgpu::RenderPipeline)>,
}

impl DepthPass {
    /// The GPU side of the session's depth pass filling depth texture `name` (a key of
    /// `session.depth_passes`) for `objects`; `layout` is [`crate::transform_layout`]'s.
    pub fn new(
        device: &wgpu::Device,
        session: &Session,
        name: &str,
        objects: &[SceneObject],
        layout: &wgpu::BindGroupLayout,
    ) -> DepthPass {
        let [w, h] = session.depth_passes[name]
            .size
            .unwrap_or(session.resolution);
        let view = device
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
        let transforms = (0..objects.len())
            .map(|i| Transforms::new(device, layout, &format!("{name}: object {i} transforms")))
            .collect();
        let vs = device.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some("depth pass vertex stage"),
            source: wgpu::ShaderSource::Wgsl(VERTEX_WGSL.into()),
        });
        let pipeline_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some(name),
            bind_group_layouts: &[Some(layout)],
            immediate_size: 0,
        });
        let pipelines = [Cull::Back, Cull::None]
            .into_iter()
            .filter(|cull| objects.iter().any(|o| o.cull == *cull))
            .map(|cull| (cull, pipeline(device, name, &pipeline_layout, &vs, cull)))
            .collect();
        DepthPass {
            name: name.to_owned(),
            view,
            transforms,
            pipelines,
        }
    }

    /// Write frame `st`'s transforms: the pass's view-projection and each object's model matrix.
    pub fn write(&self, queue: &wgpu::Queue, session: &Session, st: &FrameState) {
        let vp = session.depth_view_proj(&session.depth_passes[&self.name], st);
        for (t, model) in self.transforms.iter().zip(&st.models) {
            t.write(queue, &TransformUniform::new(vp, vp, *model, *model));
        }
    }

    /// Record the pass (after [`DepthPass::write`]) ahead of the frame's own passes.
    pub fn encode(&self, enc: &mut wgpu::CommandEncoder, objects: &[SceneObject]) {
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
        for (o, t) in objects.iter().zip(&self.transforms) {
            if let Some((_, p)) = self.pipelines.iter().find(|(c, _)| *c == o.cull) {
                pass.set_pipeline(p);
            }
            o.draw_with(&mut pass, 0, t);
        }
    }
}

/// The pass's depth-only pipeline for objects of `cull`.
fn pipeline(
    device: &wgpu::Device,
    name: &str,
    layout: &wgpu::PipelineLayout,
    vs: &wgpu::ShaderModule,
    cull: Cull,
) -> wgpu::RenderPipeline {
    device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
        label: Some(name),
        layout: Some(layout),
        vertex: wgpu::VertexState {
            module: vs,
            entry_point: Some("depth_vs"),
            compilation_options: Default::default(),
            buffers: &[Some(wgpu::VertexBufferLayout {
                array_stride: size_of::<reproj_scene::mesh::Vertex>() as u64,
                step_mode: wgpu::VertexStepMode::Vertex,
                attributes: &wgpu::vertex_attr_array![0 => Float32x3],
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
