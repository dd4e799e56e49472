//! The engine's pipelines and draw calls: one pipeline per culling mode of the scene's objects,
//! for the original shader's pass and, as vertex stages handed to reproj-runtime, the variant's.

use std::collections::HashMap;

use reproj_runtime::VertexStage;
use reproj_scene::session::Cull;

use super::vertex::VERTEX_BUFFERS;
use super::{Engine, Pipelines, VERTEX_ENTRY};
use crate::gpu::Gpu;
use reproj_scene_gpu::SceneObject;

impl Engine {
    /// The culling modes of the scene's objects, each once: one pipeline per mode.
    fn culls(&self) -> Vec<Cull> {
        let mut out = Vec::new();
        for o in &self.objects {
            if !out.contains(&o.cull) {
                out.push(o.cull);
            }
        }
        out
    }

    fn primitive(cull: Cull) -> wgpu::PrimitiveState {
        wgpu::PrimitiveState {
            topology: wgpu::PrimitiveTopology::TriangleList,
            front_face: wgpu::FrontFace::Ccw,
            cull_mode: (cull == Cull::Back).then_some(wgpu::Face::Back),
            ..Default::default()
        }
    }

    /// The vertex stage `vs` once per culling mode (the engine's business: the manifest says
    /// nothing about culling), for the variant's pipelines: [`Engine::draw_stages`] draws with
    /// them in this order.
    pub fn vertex_stages<'a>(&self, vs: &'a wgpu::ShaderModule) -> Vec<VertexStage<'a>> {
        self.culls()
            .into_iter()
            .map(|cull| VertexStage {
                module: vs,
                entry_point: VERTEX_ENTRY,
                buffers: &VERTEX_BUFFERS,
                primitive: Self::primitive(cull),
            })
            .collect()
    }

    /// One pipeline per culling mode of the scene's objects, drawing the scene's vertex layout as
    /// triangle lists.
    #[allow(clippy::too_many_arguments)]
    pub fn pipelines(
        &self,
        gpu: &Gpu,
        label: &str,
        layout: &wgpu::PipelineLayout,
        vs: &wgpu::ShaderModule,
        fs: &wgpu::ShaderModule,
        entry: &str,
        targets: &[Option<wgpu::ColorTargetState>],
        depth: wgpu::DepthStencilState,
    ) -> Pipelines {
        let mut out = HashMap::new();
        for cull in self.culls() {
            let p = gpu
                .device
                .create_render_pipeline(&wgpu::RenderPipelineDescriptor {
                    label: Some(label),
                    layout: Some(layout),
                    vertex: wgpu::VertexState {
                        module: vs,
                        entry_point: Some(VERTEX_ENTRY),
                        compilation_options: Default::default(),
                        buffers: &VERTEX_BUFFERS,
                    },
                    primitive: Self::primitive(cull),
                    depth_stencil: Some(depth.clone()),
                    multisample: Default::default(),
                    fragment: Some(wgpu::FragmentState {
                        module: fs,
                        entry_point: Some(entry),
                        compilation_options: Default::default(),
                        targets,
                    }),
                    multiview_mask: None,
                    cache: None,
                });
            out.insert(cull, p);
        }
        out
    }

    /// Draw every object with `pipes` (the pass's other bind groups are already set).
    pub fn draw(&self, pass: &mut wgpu::RenderPass<'_>, pipes: &Pipelines) {
        for o in &self.objects {
            if let Some(p) = pipes.get(&o.cull) {
                pass.set_pipeline(p);
            }
            self.draw_object(pass, o);
        }
    }

    /// Draw every object with the pipeline of its culling mode among `pipes`, one per
    /// [`Engine::vertex_stages`] entry (the variant's passes).
    pub fn draw_stages(&self, pass: &mut wgpu::RenderPass<'_>, pipes: &[wgpu::RenderPipeline]) {
        let culls = self.culls();
        for o in &self.objects {
            if let Some(p) = culls
                .iter()
                .position(|c| *c == o.cull)
                .and_then(|i| pipes.get(i))
            {
                pass.set_pipeline(p);
            }
            self.draw_object(pass, o);
        }
    }

    fn draw_object(&self, pass: &mut wgpu::RenderPass<'_>, o: &SceneObject) {
        o.draw(pass, self.vertex_group);
    }
}
