//! Shader stages, the render pipelines of a pass (cached across replays), targets and draws.

use std::collections::{BTreeSet, HashMap};
use std::path::Path;
use std::sync::atomic::Ordering;

use reproj_front::Shader;

use crate::error::ReplayError;
use crate::vertex::VERTEX_ENTRY;
use reproj_scene::mesh::Vertex;
use reproj_scene::reflect::{self, Interface};
use reproj_scene::session::Cull;

use super::*;

/// A shader module plus its reflected fragment interface.
pub(super) struct Stage {
    pub(super) shader: Shader,
    pub(super) iface: Interface,
}

/// One pipeline per cull mode used by the scene.
#[derive(Clone)]
pub(super) struct Pipe {
    pub(super) by_cull: HashMap<Cull, wgpu::RenderPipeline>,
}

/// One pass's stages and fixed-function state: what [`Renderer::pipeline`] compiles (with the
/// pass's bindings and the scene's vertex layout and cull modes).
pub(super) struct PipelineSpec<'a> {
    pub(super) label: &'a str,
    /// The vertex and fragment stages' WGSL, for the cache key.
    pub(super) sources: [&'a str; 2],
    pub(super) vs: &'a wgpu::ShaderModule,
    pub(super) fs: &'a wgpu::ShaderModule,
    /// The fragment entry point.
    pub(super) entry: &'a str,
    /// By `@location`: the color targets' formats.
    pub(super) formats: &'a [Option<wgpu::TextureFormat>],
    pub(super) compare: wgpu::CompareFunction,
    pub(super) depth_write: bool,
}

impl PipelineSpec<'_> {
    /// The pipeline cache key: every piece of state and both whole sources.
    fn key(&self, bindings: &Bindings, vertex_group: u32, culls: &BTreeSet<u8>) -> String {
        let PipelineSpec {
            label,
            sources,
            entry,
            formats,
            compare,
            depth_write,
            ..
        } = self;
        format!(
            "{label}|{entry}|{:?}|{vertex_group}|{formats:?}|{compare:?}|{depth_write}|{culls:?}|{}|{}",
            bindings.layout_keys, sources[0], sources[1],
        )
    }
}

/// The pipeline layout's bind group layouts, by group: the pass's, and the vertex transforms'
/// at `vertex_group`.
fn bind_group_layouts<'a>(
    bindings: &'a Bindings,
    scene: &'a Scene,
    vertex_group: u32,
) -> Vec<Option<&'a wgpu::BindGroupLayout>> {
    let max_group = bindings
        .layouts
        .keys()
        .copied()
        .chain([vertex_group])
        .max()
        .unwrap_or(0);
    (0..=max_group)
        .map(|g| {
            if g == vertex_group {
                Some(&scene.vertex_bgl)
            } else {
                bindings.layouts.get(&g)
            }
        })
        .collect()
}

/// Pipelines kept at most; the cache starts over beyond (an `analyze` keeps one node's few).
pub(super) const PIPELINE_CACHE_LEN: usize = 64;

impl Renderer {
    pub(super) fn make_stage(
        &self,
        path: &Path,
        source: String,
        entry: &str,
    ) -> Result<Stage, ReplayError> {
        let shader =
            reproj_front::parse_shader(path, source).map_err(|e| ReplayError::Variant {
                message: e.to_string(),
            })?;
        let idx = reflect::fragment_entry_index(&shader.module, entry).ok_or_else(|| {
            ReplayError::Variant {
                message: format!("{}: no @fragment entry point `{entry}`", path.display()),
            }
        })?;
        let iface = reflect::reflect(&shader.module, &shader.info, idx)?;
        Ok(Stage { shader, iface })
    }

    /// The render pipelines of one pass, one per cull mode. Kept across replays (keyed by the
    /// stages' whole WGSL sources and every piece of state), so replaying a variant again at another Δn
    /// does not compile its shaders again: on a CPU rasterizer compilation is most of a replay's
    /// set-up time.
    pub(super) fn pipeline(
        &self,
        spec: &PipelineSpec<'_>,
        bindings: &Bindings,
        scene: &Scene,
        vertex_group: u32,
    ) -> Result<Pipe, ReplayError> {
        let culls: BTreeSet<u8> = scene.objects.iter().map(|o| o.cull as u8).collect();
        let key = spec.key(bindings, vertex_group, &culls);
        if let Some(p) = self
            .pipelines
            .lock()
            .unwrap_or_else(|e| e.into_inner())
            .get(&key)
        {
            self.pipeline_hits.fetch_add(1, Ordering::Relaxed);
            return Ok(p.clone());
        }
        let bgls = bind_group_layouts(bindings, scene, vertex_group);
        let by_cull = self.scoped(&format!("render pipeline {}", spec.label), || {
            self.create_pipelines(spec, &bgls, culls)
        })?;
        let pipe = Pipe { by_cull };
        let mut cache = self.pipelines.lock().unwrap_or_else(|e| e.into_inner());
        if cache.len() >= PIPELINE_CACHE_LEN {
            cache.clear();
        }
        cache.insert(key, pipe.clone());
        Ok(pipe)
    }

    /// Compile the pass's pipeline layout and one pipeline per cull mode in `culls`.
    fn create_pipelines(
        &self,
        spec: &PipelineSpec<'_>,
        bgls: &[Option<&wgpu::BindGroupLayout>],
        culls: BTreeSet<u8>,
    ) -> HashMap<Cull, wgpu::RenderPipeline> {
        let label = spec.label;
        let targets: Vec<Option<wgpu::ColorTargetState>> = spec
            .formats
            .iter()
            .map(|f| {
                f.map(|format| wgpu::ColorTargetState {
                    format,
                    blend: None,
                    write_mask: wgpu::ColorWrites::ALL,
                })
            })
            .collect();
        let mut by_cull = HashMap::new();
        let layout = self
            .device
            .create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
                label: Some(label),
                bind_group_layouts: bgls,
                immediate_size: 0,
            });
        let attrs = wgpu::vertex_attr_array![0 => Float32x3, 1 => Float32x3, 2 => Float32x2, 3 => Float32x4];
        for c in culls {
            let cull = if c == Cull::Back as u8 {
                Cull::Back
            } else {
                Cull::None
            };
            let p = self
                .device
                .create_render_pipeline(&wgpu::RenderPipelineDescriptor {
                    label: Some(label),
                    layout: Some(&layout),
                    vertex: wgpu::VertexState {
                        module: spec.vs,
                        entry_point: Some(VERTEX_ENTRY),
                        compilation_options: Default::default(),
                        buffers: &[Some(wgpu::VertexBufferLayout {
                            array_stride: std::mem::size_of::<Vertex>() as u64,
                            step_mode: wgpu::VertexStepMode::Vertex,
                            attributes: &attrs,
                        })],
                    },
                    primitive: wgpu::PrimitiveState {
                        topology: wgpu::PrimitiveTopology::TriangleList,
                        front_face: wgpu::FrontFace::Ccw,
                        cull_mode: if cull == Cull::Back {
                            Some(wgpu::Face::Back)
                        } else {
                            None
                        },
                        ..Default::default()
                    },
                    depth_stencil: Some(wgpu::DepthStencilState {
                        format: DEPTH_FORMAT,
                        depth_write_enabled: Some(spec.depth_write),
                        depth_compare: Some(spec.compare),
                        stencil: Default::default(),
                        bias: Default::default(),
                    }),
                    multisample: Default::default(),
                    fragment: Some(wgpu::FragmentState {
                        module: spec.fs,
                        entry_point: Some(spec.entry),
                        compilation_options: Default::default(),
                        targets: &targets,
                    }),
                    multiview_mask: None,
                    cache: None,
                });
            by_cull.insert(cull, p);
        }
        by_cull
    }

    pub(super) fn draw(
        &self,
        pass: &mut wgpu::RenderPass<'_>,
        pipe: &Pipe,
        bindings: &Bindings,
        scene: &Scene,
        vertex_group: u32,
    ) {
        for (g, bg) in &bindings.groups {
            pass.set_bind_group(*g, bg, &[]);
        }
        for o in &scene.objects {
            if let Some(p) = pipe.by_cull.get(&o.cull) {
                pass.set_pipeline(p);
            }
            o.draw(pass, vertex_group);
        }
    }

    pub(super) fn target(
        &self,
        label: &str,
        w: u32,
        h: u32,
        format: wgpu::TextureFormat,
        binding: bool,
    ) -> wgpu::Texture {
        let mut usage = wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::COPY_SRC;
        if binding {
            usage |= wgpu::TextureUsages::TEXTURE_BINDING;
        }
        self.device.create_texture(&wgpu::TextureDescriptor {
            label: Some(label),
            size: wgpu::Extent3d {
                width: w,
                height: h,
                depth_or_array_layers: 1,
            },
            mip_level_count: 1,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format,
            usage,
            view_formats: &[],
        })
    }
}
