//! The "engine": what a real engine already has before it runs reproj's output — its geometry, its
//! per-frame camera and object transforms, its vertex stage (`vertex.rs`), pipelines and draw calls
//! (`draw.rs`), the original shader's own uniforms, storage buffers, textures and samplers and
//! their bind groups (`original.rs`), the depth passes it draws before the frame (shadow maps,
//! depth pre-passes), and its frame and depth targets.
//!
//! Here all of that is the recorded session: its data built by `reproj-scene` (session animation,
//! meshes, texels, uniform reflection and packing, GPU-free) and put on the device by
//! `reproj-scene-gpu` (buffers, textures, samplers, depth passes), the code `reproj render` draws
//! the scene with, so the frames can be compared. An engine replaces this file with its own scene;
//! the variant itself runs through `reproj-runtime` (`variant.rs`).

use std::collections::{BTreeMap, BTreeSet, HashMap};
use std::path::Path;

use anyhow::{Context, anyhow, bail};
use reproj_scene::reflect::{self, Interface, ResourceKind, TexDim};
use reproj_scene::session::Cull;
use reproj_scene::vertex::TransformUniform;
use reproj_scene::{Session, mesh, textures, uniforms};
use reproj_scene_gpu::{DEPTH_FORMAT, DepthPass, SceneObject, Transforms};

mod draw;
mod original;
mod vertex;

use crate::gpu::Gpu;
pub use original::{Original, OwnGroup, own_groups};

/// The engine's frame target format. The manifest's `format: null` means this format.
pub const FRAME_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba32Float;
/// Entry point of the host's vertex stage.
pub const VERTEX_ENTRY: &str = "host_vs";
/// A resource of the original shader, owned by the engine.
enum Own {
    Uniform {
        buf: wgpu::Buffer,
        size: u32,
        fields: Vec<reflect::UniformField>,
    },
    /// A read-only storage buffer filled from the session's `buffers` every frame.
    Storage {
        /// The variable's name: its contents are the session's `buffers` entry of that name.
        name: String,
        buf: wgpu::Buffer,
        size: u32,
        fields: Vec<reflect::UniformField>,
    },
    Texture(wgpu::TextureView),
    /// A `texture_depth_2d` the engine renders every frame: index into `Engine::depth_passes`.
    Depth(usize),
    Sampler(wgpu::Sampler),
}

/// One render pipeline per face-culling mode the scene's objects use.
pub type Pipelines = HashMap<Cull, wgpu::RenderPipeline>;

/// The scene on the GPU, the original shader's resources, and the frame target.
pub struct Engine {
    pub session: Session,
    pub width: u32,
    pub height: u32,
    /// The engine's clear color (the session's background).
    pub clear: wgpu::Color,
    /// The frame target (`FRAME_FORMAT`, the frame size).
    pub frame: wgpu::Texture,
    pub frame_view: wgpu::TextureView,
    /// The depth target (`DEPTH_FORMAT`, the frame size).
    pub depth_view: wgpu::TextureView,
    shader_source: String,
    /// The original shader's fragment interface: inputs and resources by group and binding.
    iface: Interface,
    objects: Vec<SceneObject>,
    own: BTreeMap<(u32, u32), Own>,
    depth_passes: Vec<DepthPass>,
    /// The bind group of the per-object transforms.
    pub vertex_group: u32,
    vertex_layout: wgpu::BindGroupLayout,
}

impl std::fmt::Debug for Engine {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Engine")
            .field("session", &self.session.display_name())
            .field("objects", &self.objects.len())
            .field("vertex_group", &self.vertex_group)
            .finish()
    }
}

/// Parse and validate a WGSL file with naga and reflect fragment entry point `entry` (None: the
/// only one).
fn reflect_shader(path: &Path, entry: Option<&str>) -> anyhow::Result<(String, Interface)> {
    let source =
        std::fs::read_to_string(path).with_context(|| format!("reading {}", path.display()))?;
    let module = naga::front::wgsl::parse_str(&source).map_err(|e| {
        anyhow!(
            "{}",
            e.emit_to_string_with_path(&source, &path.display().to_string())
        )
    })?;
    let info = naga::valid::Validator::new(
        naga::valid::ValidationFlags::all(),
        naga::valid::Capabilities::all(),
    )
    .validate(&module)
    .map_err(|e| anyhow!("{}: {}", path.display(), e.emit_to_string(&source)))?;
    let fragments: Vec<&str> = module
        .entry_points
        .iter()
        .filter(|e| e.stage == naga::ShaderStage::Fragment)
        .map(|e| e.name.as_str())
        .collect();
    let name = match (entry, fragments.as_slice()) {
        (Some(e), _) => e,
        (None, [one]) => one,
        (None, _) => bail!(
            "{} has the fragment entry points {fragments:?}: name one with --entry",
            path.display()
        ),
    };
    let index = reflect::fragment_entry_index(&module, name)
        .ok_or_else(|| anyhow!("{}: no @fragment entry point `{name}`", path.display()))?;
    let iface = reflect::reflect(&module, &info, index)?;
    Ok((source, iface))
}

impl Engine {
    /// Load the session and the original shader, build the scene's meshes and the shader's own
    /// resources. `reserved_groups`: bind groups the engine must leave to others (the variant's);
    /// the per-object transforms take the lowest group neither the shader nor they use.
    pub fn new(
        gpu: &Gpu,
        session_path: &Path,
        shader_path: &Path,
        entry: Option<&str>,
        reserved_groups: &BTreeSet<u32>,
    ) -> anyhow::Result<Engine> {
        let session = Session::load(session_path)?;
        let (shader_source, iface) = reflect_shader(shader_path, entry)?;
        let [width, height] = session.resolution;
        let dev = &gpu.device;

        let mut used: BTreeSet<u32> = iface.groups().into_iter().collect();
        used.extend(reserved_groups);
        let max_groups = dev.limits().max_bind_groups;
        let vertex_group = (0..max_groups)
            .find(|g| !used.contains(g))
            .ok_or_else(|| anyhow!("no bind group left for the vertex transforms"))?;
        let vertex_layout = reproj_scene_gpu::transform_layout(dev, "object transforms");

        // Geometry: one vertex and index buffer per object, and its transform uniform.
        let mut objects = Vec::new();
        for (i, o) in session.geometry.objects.iter().enumerate() {
            let data = mesh::build(&session, &o.mesh).map_err(|e| anyhow!("object {i}: {e}"))?;
            objects.push(SceneObject {
                mesh: reproj_scene_gpu::mesh_buffers(dev, &data),
                cull: o.cull,
                transforms: Transforms::new(dev, &vertex_layout, "object transforms"),
            });
        }

        // The original shader's own resources, by group and binding.
        let mut own = BTreeMap::new();
        let mut depth_passes = Vec::new();
        let mut missing = Vec::new();
        for r in &iface.resources {
            let res = match &r.kind {
                ResourceKind::Uniform { size, fields } => {
                    for f in fields {
                        if uniforms::session_must_provide(&f.name)
                            && session.uniform(&f.name).is_none()
                        {
                            missing.push(format!("uniform field `{}`", f.name));
                        }
                    }
                    Own::Uniform {
                        buf: reproj_scene_gpu::buffer(
                            dev,
                            &r.name,
                            u64::from(*size),
                            wgpu::BufferUsages::UNIFORM,
                        ),
                        size: *size,
                        fields: fields.clone(),
                    }
                }
                ResourceKind::Texture { dim } => match session.textures.get(&r.name) {
                    Some(spec) => Own::Texture(Self::texture(gpu, &session, &r.name, spec, *dim)?),
                    None => {
                        missing.push(format!("texture `{}`", r.name));
                        continue;
                    }
                },
                ResourceKind::Storage(layout) => {
                    let (size, fields) = uniforms::storage_fields(&session, &r.name, layout)
                        .map_err(|e| anyhow!("{e}"))?;
                    Own::Storage {
                        name: r.name.clone(),
                        buf: reproj_scene_gpu::buffer(
                            dev,
                            &r.name,
                            u64::from(size),
                            wgpu::BufferUsages::STORAGE,
                        ),
                        size,
                        fields,
                    }
                }
                ResourceKind::DepthTexture => {
                    if !session.depth_passes.contains_key(&r.name) {
                        missing.push(format!("depth pass `{}`", r.name));
                        continue;
                    }
                    depth_passes.push(DepthPass::new(
                        dev,
                        &session,
                        &r.name,
                        &objects,
                        &vertex_layout,
                    ));
                    Own::Depth(depth_passes.len() - 1)
                }
                ResourceKind::Sampler { comparison } => {
                    let compare = session.samplers.get(&r.name).and_then(|s| s.compare);
                    if !*comparison && compare.is_some() {
                        bail!(
                            "sampler `{}` is a plain `sampler`, but the session gives it a `compare` function",
                            r.name
                        );
                    }
                    let desc = reproj_scene_gpu::sampler_descriptor(&session, &r.name, *comparison);
                    Own::Sampler(dev.create_sampler(&desc))
                }
                other => bail!(
                    "the shader's `{}` ({other:?}) is not something this host provides",
                    r.name
                ),
            };
            own.insert((r.group, r.binding), res);
        }
        if !missing.is_empty() {
            bail!(
                "the session provides no {} the shader declares",
                missing.join(", ")
            );
        }

        let frame = dev.create_texture(&wgpu::TextureDescriptor {
            label: Some("frame"),
            size: wgpu::Extent3d {
                width,
                height,
                depth_or_array_layers: 1,
            },
            mip_level_count: 1,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format: FRAME_FORMAT,
            usage: wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::COPY_SRC,
            view_formats: &[],
        });
        let frame_view = frame.create_view(&Default::default());
        let depth_view = dev
            .create_texture(&wgpu::TextureDescriptor {
                label: Some("depth"),
                size: frame.size(),
                mip_level_count: 1,
                sample_count: 1,
                dimension: wgpu::TextureDimension::D2,
                format: DEPTH_FORMAT,
                usage: wgpu::TextureUsages::RENDER_ATTACHMENT,
                view_formats: &[],
            })
            .create_view(&Default::default());
        let bg = session.background.map(f64::from);
        gpu.check("building the scene")?;
        Ok(Engine {
            clear: wgpu::Color {
                r: bg[0],
                g: bg[1],
                b: bg[2],
                a: bg[3],
            },
            session,
            width,
            height,
            frame,
            frame_view,
            depth_view,
            shader_source,
            iface,
            objects,
            own,
            depth_passes,
            vertex_group,
            vertex_layout,
        })
    }

    /// A session texture, uploaded with its mip levels.
    fn texture(
        gpu: &Gpu,
        session: &Session,
        name: &str,
        spec: &reproj_scene::session::TextureSpec,
        dim: TexDim,
    ) -> anyhow::Result<wgpu::TextureView> {
        let data = textures::build(session, name, spec, dim)
            .map_err(|e| anyhow!("texture `{name}`: {e}"))?;
        Ok(reproj_scene_gpu::texture(
            &gpu.device,
            &gpu.queue,
            name,
            &data,
            dim,
        ))
    }

    /// The engine's resource bound at `@group(group) @binding(binding)` of the original shader.
    pub fn own_resource(&self, group: u32, binding: u32) -> Option<wgpu::BindingResource<'_>> {
        Some(match self.own.get(&(group, binding))? {
            Own::Uniform { buf, .. } => buf.as_entire_binding(),
            Own::Storage { buf, .. } => buf.as_entire_binding(),
            Own::Texture(view) => wgpu::BindingResource::TextureView(view),
            Own::Depth(i) => wgpu::BindingResource::TextureView(&self.depth_passes[*i].view),
            Own::Sampler(s) => wgpu::BindingResource::Sampler(s),
        })
    }

    /// Write frame `frame`'s object transforms (this frame's and the previous frame's matrices;
    /// on frame 0 the previous ones are frame 0's) and the shader's own uniforms.
    pub fn write_frame(&self, gpu: &Gpu, frame: u32) {
        let st = self.session.frame_state(frame);
        let prev = self.session.frame_state(frame.saturating_sub(1));
        for (i, o) in self.objects.iter().enumerate() {
            let u = TransformUniform::new(
                st.camera.view_proj,
                prev.camera.view_proj,
                st.models[i],
                prev.models[i],
            );
            o.transforms.write(&gpu.queue, &u);
        }
        for own in self.own.values() {
            match own {
                Own::Uniform { buf, size, fields } => {
                    let bytes = uniforms::uniform_bytes(&self.session, &st, *size, fields);
                    gpu.queue.write_buffer(buf, 0, &bytes);
                }
                Own::Storage {
                    name,
                    buf,
                    size,
                    fields,
                } => {
                    let bytes = uniforms::storage_bytes(&self.session, &st, name, *size, fields);
                    gpu.queue.write_buffer(buf, 0, &bytes);
                }
                _ => {}
            }
        }
        for d in &self.depth_passes {
            d.write(&gpu.queue, &self.session, &st);
        }
    }

    /// Record the session's depth passes for the frame (after [`Engine::write_frame`]), ahead of
    /// the frame's own passes: the textures the shader samples are this frame's.
    pub fn encode_depth_passes(&self, enc: &mut wgpu::CommandEncoder) {
        for d in &self.depth_passes {
            d.encode(enc, &self.objects);
        }
    }

    /// The layout of the per-object transforms' bind group.
    pub fn vertex_layout(&self) -> &wgpu::BindGroupLayout {
        &self.vertex_layout
    }

    /// A shader module from WGSL text, with wgpu's validation message on failure.
    pub fn shader_module(
        gpu: &Gpu,
        label: &str,
        source: &str,
    ) -> anyhow::Result<wgpu::ShaderModule> {
        let scope = gpu.device.push_error_scope(wgpu::ErrorFilter::Validation);
        let m = gpu
            .device
            .create_shader_module(wgpu::ShaderModuleDescriptor {
                label: Some(label),
                source: wgpu::ShaderSource::Wgsl(source.into()),
            });
        if let Some(e) = pollster::block_on(scope.pop()) {
            bail!("shader module {label}: {e}");
        }
        Ok(m)
    }
}
