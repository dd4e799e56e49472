//! Shader stages, the render pipelines of a pass (cached across replays), targets and draws.

use std::collections::{BTreeSet, HashMap};
use std::path::Path;
use std::sync::atomic::Ordering;

use reproj_front::Shader;
use reproj_instance::{Manifest, PassKind};

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

/// A color attachment of a variant pass.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum Attachment {
    Frame,
    Cache,
    /// The fragment's depth, read by the next frame's lookup.
    DepthCopy,
}

/// The render passes a variant's passes are drawn in, as ranges of pass indices: consecutive
/// passes that write the same targets (the same attachment at every location) share one where the
/// later loads every target and the depth — a host draws them so (`docs/PASSES.md`, "One render
/// pass"), and on a tiler or a CPU rasterizer a render pass boundary stores and reloads every
/// target. No pass of a shared render pass reads what it writes: a pass never binds its own
/// targets, and they are the same. With `separate`, one render pass per pass (per-pass timing).
pub(super) fn render_passes(specs: &[PassSpec], separate: bool) -> Vec<std::ops::Range<usize>> {
    let mut groups: Vec<std::ops::Range<usize>> = Vec::new();
    for (i, spec) in specs.iter().enumerate() {
        let joins = !separate
            && i > 0
            && spec.depth_load
            && spec.colors.iter().all(|c| c.is_none_or(|(_, load)| load))
            && spec
                .colors
                .iter()
                .map(|c| c.map(|(t, _)| t))
                .eq(specs[i - 1].colors.iter().map(|c| c.map(|(t, _)| t)));
        match groups.last_mut() {
            Some(g) if joins => g.end = i + 1,
            _ => groups.push(i..i + 1),
        }
    }
    groups
}

/// One variant pass as the manifest describes it.
#[derive(Debug)]
pub(super) struct PassSpec {
    pub(super) label: String,
    /// By `@location`: the attachment and whether it is loaded (else cleared).
    pub(super) colors: Vec<Option<(Attachment, bool)>>,
    pub(super) compare: wgpu::CompareFunction,
    pub(super) depth_write: bool,
    /// Depth loaded (else cleared to 1).
    pub(super) depth_load: bool,
}

/// The passes of a variant, from its manifest.
pub(super) fn pass_specs(m: &Manifest) -> Result<Vec<PassSpec>, ReplayError> {
    use reproj_instance::Strategy;
    let expected: &[PassKind] = match m.strategy {
        Strategy::ThreePass => &[PassKind::Reproject, PassKind::Recompute, PassKind::Shade],
        Strategy::TwoPass => &[PassKind::ShadeHits, PassKind::ShadeMisses],
        Strategy::Fused => &[PassKind::Fused],
    };
    let kinds: Vec<PassKind> = m.passes.iter().map(|p| p.kind).collect();
    let bad = |message: String| ReplayError::Variant { message };
    if kinds != expected {
        return Err(bad(format!(
            "a {} variant has the passes {expected:?}, the manifest lists {kinds:?}",
            m.strategy
        )));
    }
    m.passes
        .iter()
        .enumerate()
        .map(|(i, p)| {
            let mut colors = Vec::new();
            for c in &p.colors {
                let t = match c.attachment.as_str() {
                    reproj_instance::ATTACHMENT_FRAME => Attachment::Frame,
                    reproj_instance::ROLE_CUR_PAYLOAD => Attachment::Cache,
                    reproj_instance::ROLE_CUR_DEPTH_COPY => Attachment::DepthCopy,
                    other => return Err(bad(format!("unknown color attachment `{other}`"))),
                };
                let load = c.load.is_load();
                let at = c.location as usize;
                if at >= 8 {
                    return Err(bad(format!("color location {at} is out of range")));
                }
                if colors.len() <= at {
                    colors.resize(at + 1, None);
                }
                colors[at] = Some((t, load));
            }
            let compare = match p.depth.compare.as_str() {
                "less" => wgpu::CompareFunction::Less,
                "less-equal" => wgpu::CompareFunction::LessEqual,
                "equal" => wgpu::CompareFunction::Equal,
                "always" => wgpu::CompareFunction::Always,
                other => return Err(bad(format!("unknown depth compare `{other}`"))),
            };
            Ok(PassSpec {
                label: format!("pass {} {}", i + 1, p.file.trim_end_matches(".wgsl")),
                colors,
                compare,
                depth_write: p.depth.write,
                depth_load: p.depth.load.is_load(),
            })
        })
        .collect()
}

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
            pass.set_bind_group(vertex_group, &o.xf_bg, &[]);
            pass.set_vertex_buffer(0, o.vbuf.slice(..));
            pass.set_index_buffer(o.ibuf.slice(..), wgpu::IndexFormat::Uint32);
            pass.draw_indexed(0..o.count, 0, 0..1);
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

#[cfg(test)]
mod tests {
    use super::*;

    fn spec(colors: &[(Attachment, bool)], depth_load: bool) -> PassSpec {
        PassSpec {
            label: String::new(),
            colors: colors.iter().copied().map(Some).collect(),
            compare: wgpu::CompareFunction::Less,
            depth_write: true,
            depth_load,
        }
    }

    #[test]
    fn passes_that_load_the_same_targets_share_a_render_pass() {
        use Attachment::*;
        // 2pass: shade hits (clears), shade misses (loads the same two targets).
        let two = [
            spec(&[(Frame, false), (Cache, false)], false),
            spec(&[(Frame, true), (Cache, true)], true),
        ];
        assert_eq!(
            render_passes(&two, false),
            [std::ops::Range { start: 0, end: 2 }]
        );
        assert_eq!(render_passes(&two, true), [0..1, 1..2]);
        // 3pass: reproject and recompute share the cache; shade writes other targets.
        let three = [
            spec(&[(Cache, false)], false),
            spec(&[(Cache, true)], true),
            spec(&[(Frame, false), (DepthCopy, false)], true),
        ];
        assert_eq!(render_passes(&three, false), [0..2, 2..3]);
        // A pass that clears a target, or clears the depth, starts its own.
        let clears = [
            spec(&[(Frame, false), (Cache, false)], false),
            spec(&[(Frame, true), (Cache, false)], true),
            spec(&[(Frame, true), (Cache, true)], false),
        ];
        assert_eq!(render_passes(&clears, false), [0..1, 1..2, 2..3]);
        // The same targets at other locations are other targets.
        let swapped = [
            spec(&[(Frame, false), (Cache, false)], false),
            spec(&[(Cache, true), (Frame, true)], true),
        ];
        assert_eq!(render_passes(&swapped, false), [0..1, 1..2]);
        assert_eq!(render_passes(&two[..1], false).len(), 1);
        assert!(render_passes(&[], false).is_empty());
    }
}
