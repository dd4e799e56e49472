//! The variant, run by `reproj-runtime`: what an engine writes to use reproj's output. The
//! runtime reads the manifest and owns what reproj added (textures, samplers, the params buffer,
//! the variant's bind group, the passes' pipelines); the engine gives it its vertex stage (with
//! the manifest's vertex contract), its bind groups for the original shader's resources, its
//! frame and depth targets, and draws its geometry when a pass asks.

use reproj_runtime::{FrameInputs, FrameTargets, Setup, SharedGroup, Variant, VariantResources};

use crate::engine::{self, Engine, OwnGroup};
use crate::gpu::{Gpu, Timer};

/// A variant on the GPU, with the engine's bind groups for the original shader's resources.
pub struct HostVariant {
    pub variant: Variant,
    resources: VariantResources,
    groups: Vec<OwnGroup>,
}

impl std::fmt::Debug for HostVariant {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("HostVariant")
            .field("variant", &self.variant.dir())
            .field("passes", &self.variant.pass_count())
            .finish()
    }
}

impl HostVariant {
    /// Build `variant` for `engine`'s scene and frame target.
    pub fn new(gpu: &Gpu, engine: &Engine, variant: Variant) -> anyhow::Result<HostVariant> {
        let vs_src = engine.vertex_wgsl(Some(variant.vertex()))?;
        let vs = Engine::shader_module(gpu, "host vertex stage (variant)", &vs_src)?;
        let mut groups = engine::own_groups(gpu, engine)?;
        // Where the shader uses all four groups, the variant's shares one with it: the engine's
        // bindings of that group go to the runtime, which binds them beside its own.
        let shared = variant
            .shares_group()
            .then(|| groups.iter().position(|g| g.group == variant.group()))
            .flatten()
            .map(|i| groups.remove(i));
        let shared_resources: Vec<wgpu::BindGroupEntry<'_>> = shared
            .iter()
            .flat_map(|g| &g.entries)
            .map(|e| {
                let resource = engine
                    .own_resource(variant.group(), e.binding)
                    .ok_or_else(|| anyhow::anyhow!("no resource at binding {}", e.binding))?;
                Ok(wgpu::BindGroupEntry {
                    binding: e.binding,
                    resource,
                })
            })
            .collect::<anyhow::Result<_>>()?;
        let mut layouts: Vec<(u32, &wgpu::BindGroupLayout)> =
            groups.iter().map(|g| (g.group, &g.layout)).collect();
        layouts.push((engine.vertex_group, engine.vertex_layout()));
        let resources = variant.create(
            &gpu.device,
            &Setup {
                size: [engine.width, engine.height],
                color_format: engine::FRAME_FORMAT,
                vertex: &engine.vertex_stages(&vs),
                bind_group_layouts: &layouts,
                classification: None,
                motion: None,
                shared: shared.as_ref().map(|g| SharedGroup {
                    layout: &g.entries,
                    resources: &shared_resources,
                }),
            },
        )?;
        gpu.check("building the variant")?;
        Ok(HostVariant {
            variant,
            resources,
            groups,
        })
    }

    /// Record the next frame into `enc` against the engine's frame and depth targets, at the
    /// refresh period `delta_n` (`None`: the manifest's).
    pub fn encode_frame(
        &mut self,
        gpu: &Gpu,
        enc: &mut wgpu::CommandEncoder,
        engine: &Engine,
        delta_n: Option<u32>,
        timer: &Timer,
    ) -> anyhow::Result<()> {
        let bind_groups: Vec<(u32, &wgpu::BindGroup)> =
            self.groups.iter().map(|g| (g.group, &g.bind)).collect();
        self.resources.record(
            &gpu.queue,
            enc,
            &FrameTargets {
                color: &engine.frame_view,
                depth: &engine.depth_view,
                clear_color: engine.clear,
            },
            &FrameInputs {
                delta_n,
                restart: false,
                bind_groups: &bind_groups,
                timestamps: timer.query_set(),
                ..Default::default()
            },
            |pass, pipelines| engine.draw_stages(pass, pipelines),
        )?;
        Ok(())
    }
}
