//! A session's GPU resources (meshes, textures, samplers, uniform and storage buffers, depth
//! passes) and the per-frame writes.

use std::collections::{BTreeMap, BTreeSet, HashMap};
use std::num::NonZeroU64;

use crate::error::ReplayError;
use crate::vertex::TransformUniform;
use reproj_scene::reflect::{self, Interface, ResourceKind, TexDim};
use reproj_scene::session::{Address, Compare, Filter, SamplerSpec, Session};

use super::depth::DepthPassGpu;
use super::*;

/// GPU resources of a session (shared by every pipeline of one render).
pub(super) struct Scene {
    pub(super) objects: Vec<ObjectGpu>,
    pub(super) textures: HashMap<String, wgpu::TextureView>,
    pub(super) samplers: HashMap<String, wgpu::Sampler>,
    /// Uniform buffers by variable name, with their reflected fields.
    pub(super) uniforms: BTreeMap<String, (wgpu::Buffer, u32, Vec<reflect::UniformField>)>,
    /// Read-only storage buffers by variable name, with their leaves for the session's data.
    pub(super) storage: BTreeMap<String, (wgpu::Buffer, u32, Vec<reflect::UniformField>)>,
    /// The session's depth passes, by the depth texture variable they fill.
    pub(super) depth: BTreeMap<String, DepthPassGpu>,
    pub(super) vertex_bgl: wgpu::BindGroupLayout,
}

/// Lowest group index not in `used`.
pub(super) fn free_group(used: &BTreeSet<u32>) -> Result<u32, ReplayError> {
    let g = (0..MAX_BIND_GROUPS).find(|g| !used.contains(g)).ok_or_else(|| ReplayError::Unsupported {
        what: format!(
            "the fragment modules use every bind group 0..{MAX_BIND_GROUPS}; the replay needs a free one for the vertex transforms"
        ),
    })?;
    Ok(g)
}

impl Renderer {
    /// Build every session resource the interfaces use (except `skip_group`, the variant's own
    /// group). Missing ones are reported together, by name.
    pub(super) fn build_scene(
        &self,
        session: &Session,
        ifaces: &[&Interface],
        skip_group: Option<u32>,
    ) -> Result<Scene, ReplayError> {
        let mut missing_fields = Vec::new();
        let mut missing_textures = Vec::new();
        let mut unsupported = Vec::new();
        let mut tex_needed: BTreeMap<String, TexDim> = BTreeMap::new();
        let mut samp_needed: BTreeSet<(String, bool)> = BTreeSet::new();
        let mut missing_buffers = Vec::new();
        let mut missing_depth = Vec::new();
        let mut uni_needed: BTreeMap<String, (u32, Vec<reflect::UniformField>)> = BTreeMap::new();
        let mut storage_needed: BTreeMap<String, (u32, Vec<reflect::UniformField>)> =
            BTreeMap::new();
        let mut depth_needed: BTreeSet<String> = BTreeSet::new();
        for iface in ifaces {
            for r in &iface.resources {
                if Some(r.group) == skip_group {
                    continue;
                }
                match &r.kind {
                    ResourceKind::Uniform { size, fields } => {
                        for f in fields {
                            if !reproj_scene::uniforms::session_must_provide(&f.name) {
                                continue;
                            }
                            match session.uniform(&f.name) {
                                None => missing_fields.push(format!("`{}` (field of uniform `{}`)", f.name, r.name)),
                                Some(v) if !v.is_leaf() => unsupported.push(format!(
                                    "uniform field `{}` is {} but the session gives it an object or a list of objects",
                                    f.name, f.ty
                                )),
                                Some(v) if v.len() != f.len() => unsupported.push(format!(
                                    "uniform field `{}` is {} ({} values) but the session gives {} values",
                                    f.name,
                                    f.ty,
                                    f.len(),
                                    v.len()
                                )),
                                Some(_) => {}
                            }
                        }
                        uni_needed.insert(r.name.clone(), (*size, fields.clone()));
                    }
                    ResourceKind::Texture { dim } => {
                        if !session.textures.contains_key(&r.name) {
                            missing_textures.push(format!("`{}`", r.name));
                        } else {
                            tex_needed.insert(r.name.clone(), *dim);
                        }
                    }
                    ResourceKind::Storage(layout) => {
                        if !session.buffers.contains_key(&r.name) {
                            missing_buffers.push(format!("`{}`", r.name));
                            continue;
                        }
                        match reproj_scene::uniforms::storage_fields(session, &r.name, layout) {
                            Ok(sf) => {
                                storage_needed.insert(r.name.clone(), sf);
                            }
                            Err(e) => unsupported.push(e),
                        }
                    }
                    ResourceKind::Sampler { comparison } => {
                        let compare = session.samplers.get(&r.name).and_then(|s| s.compare);
                        if !*comparison && compare.is_some() {
                            unsupported.push(format!(
                                "sampler `{}` is a plain `sampler`, but the session gives it a `compare` function",
                                r.name
                            ));
                        }
                        samp_needed.insert((r.name.clone(), *comparison));
                    }
                    ResourceKind::DepthTexture => {
                        if session.depth_passes.contains_key(&r.name) {
                            depth_needed.insert(r.name.clone());
                        } else {
                            missing_depth.push(format!("`{}`", r.name));
                        }
                    }
                    ResourceKind::Unsupported(what) => unsupported.push(what.clone()),
                }
            }
        }
        missing_textures.sort();
        missing_textures.dedup();
        missing_fields.sort();
        missing_fields.dedup();
        missing_buffers.sort();
        missing_buffers.dedup();
        missing_depth.sort();
        missing_depth.dedup();
        if !missing_textures.is_empty()
            || !missing_fields.is_empty()
            || !missing_buffers.is_empty()
            || !missing_depth.is_empty()
        {
            let mut names = missing_textures
                .iter()
                .map(|t| format!("texture {t}"))
                .collect::<Vec<_>>();
            names.extend(missing_fields.iter().map(|f| format!("uniform {f}")));
            names.extend(
                missing_buffers
                    .iter()
                    .map(|b| format!("storage buffer {b} (in `buffers`)")),
            );
            names.extend(
                missing_depth
                    .iter()
                    .map(|d| format!("depth texture {d} (in `depth_passes`)")),
            );
            return Err(ReplayError::MissingResources {
                what: "resources the shader declares".into(),
                names,
            });
        }
        if !unsupported.is_empty() {
            unsupported.sort();
            unsupported.dedup();
            return Err(ReplayError::Unsupported {
                what: unsupported.join("; "),
            });
        }
        self.scoped(
            "creating the session's resources",
            || -> Result<Scene, ReplayError> {
                let dev = &self.device;
                // Meshes and per-object transforms.
                let vertex_bgl = dev.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
                    label: Some("replay vertex transforms"),
                    entries: &[wgpu::BindGroupLayoutEntry {
                        binding: 0,
                        visibility: wgpu::ShaderStages::VERTEX,
                        ty: wgpu::BindingType::Buffer {
                            ty: wgpu::BufferBindingType::Uniform,
                            has_dynamic_offset: false,
                            min_binding_size: NonZeroU64::new(
                                std::mem::size_of::<TransformUniform>() as u64,
                            ),
                        },
                        count: None,
                    }],
                });
                let mut objects = Vec::new();
                for (i, o) in session.geometry.objects.iter().enumerate() {
                    let m = self.assets.mesh(self, session, &o.mesh)?;
                    let xf_buf = dev.create_buffer(&wgpu::BufferDescriptor {
                        label: Some(&format!("object {i} transforms")),
                        size: std::mem::size_of::<TransformUniform>() as u64,
                        usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
                        mapped_at_creation: false,
                    });
                    let xf_bg = dev.create_bind_group(&wgpu::BindGroupDescriptor {
                        label: Some("object transforms"),
                        layout: &vertex_bgl,
                        entries: &[wgpu::BindGroupEntry {
                            binding: 0,
                            resource: xf_buf.as_entire_binding(),
                        }],
                    });
                    objects.push(ObjectGpu {
                        vbuf: m.vbuf,
                        ibuf: m.ibuf,
                        count: m.count,
                        cull: o.cull,
                        xf_buf,
                        xf_bg,
                    });
                }
                // Textures.
                let mut textures = HashMap::new();
                for (name, dim) in &tex_needed {
                    let view =
                        self.assets
                            .texture(self, session, name, &session.textures[name], *dim)?;
                    textures.insert(name.clone(), view);
                }
                // Samplers.
                let mut samplers = HashMap::new();
                for (name, comparison) in &samp_needed {
                    let spec = session
                        .samplers
                        .get(name)
                        .cloned()
                        .unwrap_or(if *comparison {
                            SamplerSpec {
                                address: Address::Clamp,
                                ..Default::default()
                            }
                        } else {
                            SamplerSpec::default()
                        });
                    let compare = comparison.then(|| match spec.compare.unwrap_or_default() {
                        Compare::Never => wgpu::CompareFunction::Never,
                        Compare::Less => wgpu::CompareFunction::Less,
                        Compare::Equal => wgpu::CompareFunction::Equal,
                        Compare::LessEqual => wgpu::CompareFunction::LessEqual,
                        Compare::Greater => wgpu::CompareFunction::Greater,
                        Compare::NotEqual => wgpu::CompareFunction::NotEqual,
                        Compare::GreaterEqual => wgpu::CompareFunction::GreaterEqual,
                        Compare::Always => wgpu::CompareFunction::Always,
                    });
                    let f = |x: Filter| match x {
                        Filter::Linear => wgpu::FilterMode::Linear,
                        Filter::Nearest => wgpu::FilterMode::Nearest,
                    };
                    let mf = match spec.mipmap_filter {
                        Filter::Linear => wgpu::MipmapFilterMode::Linear,
                        Filter::Nearest => wgpu::MipmapFilterMode::Nearest,
                    };
                    let a = match spec.address {
                        Address::Repeat => wgpu::AddressMode::Repeat,
                        Address::Clamp => wgpu::AddressMode::ClampToEdge,
                        Address::Mirror => wgpu::AddressMode::MirrorRepeat,
                    };
                    let all_linear =
                        spec.filter == Filter::Linear && spec.mipmap_filter == Filter::Linear;
                    let s = dev.create_sampler(&wgpu::SamplerDescriptor {
                        label: Some(name),
                        address_mode_u: a,
                        address_mode_v: a,
                        address_mode_w: a,
                        mag_filter: f(spec.filter),
                        min_filter: f(spec.filter),
                        mipmap_filter: mf,
                        anisotropy_clamp: if all_linear { spec.anisotropy } else { 1 },
                        compare,
                        ..Default::default()
                    });
                    samplers.insert(name.clone(), s);
                }
                // Uniform buffers.
                let mut uniforms = BTreeMap::new();
                for (name, (size, fields)) in uni_needed {
                    let buf = dev.create_buffer(&wgpu::BufferDescriptor {
                        label: Some(&name),
                        size: size.max(16) as u64,
                        usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
                        mapped_at_creation: false,
                    });
                    uniforms.insert(name, (buf, size, fields));
                }
                let mut storage = BTreeMap::new();
                for (name, (size, fields)) in storage_needed {
                    let buf = dev.create_buffer(&wgpu::BufferDescriptor {
                        label: Some(&name),
                        size: size.max(16) as u64,
                        usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_DST,
                        mapped_at_creation: false,
                    });
                    storage.insert(name, (buf, size, fields));
                }
                let mut depth = BTreeMap::new();
                for name in depth_needed {
                    let pass = self.depth_pass(session, &name, &objects, &vertex_bgl)?;
                    depth.insert(name, pass);
                }
                Ok(Scene {
                    objects,
                    textures,
                    samplers,
                    uniforms,
                    storage,
                    depth,
                    vertex_bgl,
                })
            },
        )?
    }

    /// Write the frame's uniform values and transforms.
    pub(super) fn write_frame_uniforms(&self, session: &Session, scene: &Scene, frame: u32) {
        let st = session.frame_state(frame);
        let prev = session.frame_state(frame.saturating_sub(1));
        for (i, o) in scene.objects.iter().enumerate() {
            let u = TransformUniform::new(
                st.camera.view_proj,
                prev.camera.view_proj,
                st.models[i],
                prev.models[i],
            );
            self.queue
                .write_buffer(&o.xf_buf, 0, bytemuck::bytes_of(&u));
        }
        for (buf, size, fields) in scene.uniforms.values() {
            let bytes = reproj_scene::uniforms::uniform_bytes(session, &st, *size, fields);
            self.queue.write_buffer(buf, 0, &bytes);
        }
        for (name, (buf, size, fields)) in &scene.storage {
            let bytes = reproj_scene::uniforms::storage_bytes(session, &st, name, *size, fields);
            self.queue.write_buffer(buf, 0, &bytes);
        }
        if !scene.depth.is_empty() {
            self.render_depth_passes(session, &scene.depth, &scene.objects, &st);
        }
    }
}
