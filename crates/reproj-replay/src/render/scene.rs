//! A session's GPU resources (meshes, textures, samplers, uniform and storage buffers, depth
//! passes) and the per-frame writes.

use std::collections::{BTreeMap, BTreeSet, HashMap};

use crate::error::ReplayError;
use crate::vertex::TransformUniform;
use reproj_scene::reflect::{self, Interface, ResourceKind, TexDim};
use reproj_scene::session::{FrameState, Session};
use reproj_scene_gpu::{DepthPass, Transforms, sampler_descriptor};

use super::*;

/// GPU resources of a session (shared by every pipeline of one render).
pub(super) struct Scene {
    pub(super) objects: Vec<SceneObject>,
    pub(super) textures: HashMap<String, wgpu::TextureView>,
    pub(super) samplers: HashMap<String, wgpu::Sampler>,
    /// Uniform buffers by variable name, with their reflected fields.
    pub(super) uniforms: BTreeMap<String, (wgpu::Buffer, u32, Vec<reflect::UniformField>)>,
    /// Read-only storage buffers by variable name, with their leaves for the session's data.
    pub(super) storage: BTreeMap<String, (wgpu::Buffer, u32, Vec<reflect::UniformField>)>,
    /// The session's depth passes, by the depth texture variable they fill.
    pub(super) depth: BTreeMap<String, DepthPass>,
    pub(super) vertex_bgl: wgpu::BindGroupLayout,
}

/// The group of the replay's own vertex transforms: the lowest index not in `used`, below the
/// device's `max_bind_groups` (`limit`). The replay asks for the adapter's limits (8 on lavapipe
/// and on desktop GPUs), so a shader that uses groups 0–2 and a variant that adds group 3 still
/// leave it one: this group is the replay's, never part of what a host binds.
pub(super) fn free_group(used: &BTreeSet<u32>, limit: u32) -> Result<u32, ReplayError> {
    let g = (0..limit).find(|g| !used.contains(g)).ok_or_else(|| ReplayError::Unsupported {
        what: format!(
            "the fragment modules use bind groups {used:?}, every one this device has (0..{limit}); the replay needs a free one for the vertex transforms"
        ),
    })?;
    Ok(g)
}

/// A buffer's size in bytes and its reflected fields (or a storage buffer's leaves).
type BufferNeed = (u32, Vec<reflect::UniformField>);

/// What the interfaces need from the session, gathered before any GPU object, with what the
/// session lacks or gives in a shape the shader cannot take ([`SceneNeeds::of`]).
#[derive(Default)]
struct SceneNeeds {
    uniforms: BTreeMap<String, BufferNeed>,
    storage: BTreeMap<String, BufferNeed>,
    textures: BTreeMap<String, TexDim>,
    /// Samplers by name, and whether the shader declares a comparison sampler.
    samplers: BTreeSet<(String, bool)>,
    depth: BTreeSet<String>,
    missing_fields: Vec<String>,
    missing_textures: Vec<String>,
    missing_buffers: Vec<String>,
    missing_depth: Vec<String>,
    unsupported: Vec<String>,
}

impl SceneNeeds {
    /// The resources of `ifaces` (except those at `added`, the variant's own) against `session`.
    fn of(session: &Session, ifaces: &[&Interface], added: Option<AddedPlace>) -> SceneNeeds {
        let mut needs = SceneNeeds::default();
        for iface in ifaces {
            for r in &iface.resources {
                if !added.is_some_and(|a| a.holds(r.group, r.binding)) {
                    needs.add(session, r);
                }
            }
        }
        needs
    }

    /// Note resource `r`: what it needs, or what is missing or unsupported.
    fn add(&mut self, session: &Session, r: &reflect::Resource) {
        match &r.kind {
            ResourceKind::Uniform { size, fields } => {
                for f in fields {
                    self.check_uniform_field(session, &r.name, f);
                }
                self.uniforms
                    .insert(r.name.clone(), (*size, fields.clone()));
            }
            ResourceKind::Texture { dim } => {
                if !session.textures.contains_key(&r.name) {
                    self.missing_textures.push(format!("`{}`", r.name));
                } else {
                    self.textures.insert(r.name.clone(), *dim);
                }
            }
            ResourceKind::Storage(layout) => {
                if !session.buffers.contains_key(&r.name) {
                    self.missing_buffers.push(format!("`{}`", r.name));
                    return;
                }
                match reproj_scene::uniforms::storage_fields(session, &r.name, layout) {
                    Ok(sf) => {
                        self.storage.insert(r.name.clone(), sf);
                    }
                    Err(e) => self.unsupported.push(e),
                }
            }
            ResourceKind::Sampler { comparison } => {
                let compare = session.samplers.get(&r.name).and_then(|s| s.compare);
                if !*comparison && compare.is_some() {
                    self.unsupported.push(format!(
                        "sampler `{}` is a plain `sampler`, but the session gives it a `compare` function",
                        r.name
                    ));
                }
                self.samplers.insert((r.name.clone(), *comparison));
            }
            ResourceKind::DepthTexture => {
                if session.depth_passes.contains_key(&r.name) {
                    self.depth.insert(r.name.clone());
                } else {
                    self.missing_depth.push(format!("`{}`", r.name));
                }
            }
            ResourceKind::Unsupported(what) => self.unsupported.push(what.clone()),
        }
    }

    /// Field `f` of uniform `uniform`: given by the session, as one value of the field's length.
    fn check_uniform_field(&mut self, session: &Session, uniform: &str, f: &reflect::UniformField) {
        if !reproj_scene::uniforms::session_must_provide(&f.name) {
            return;
        }
        match session.uniform(&f.name) {
            None => self
                .missing_fields
                .push(format!("`{}` (field of uniform `{}`)", f.name, uniform)),
            Some(v) if !v.is_leaf() => self.unsupported.push(format!(
                "uniform field `{}` is {} but the session gives it an object or a list of objects",
                f.name, f.ty
            )),
            Some(v) if v.len() != f.len() => self.unsupported.push(format!(
                "uniform field `{}` is {} ({} values) but the session gives {} values",
                f.name,
                f.ty,
                f.len(),
                v.len()
            )),
            Some(_) => {}
        }
    }

    /// The missing resources together, by name, else the unsupported ones together.
    fn check(&mut self) -> Result<(), ReplayError> {
        for list in [
            &mut self.missing_textures,
            &mut self.missing_fields,
            &mut self.missing_buffers,
            &mut self.missing_depth,
        ] {
            list.sort();
            list.dedup();
        }
        if !self.missing_textures.is_empty()
            || !self.missing_fields.is_empty()
            || !self.missing_buffers.is_empty()
            || !self.missing_depth.is_empty()
        {
            let mut names = self
                .missing_textures
                .iter()
                .map(|t| format!("texture {t}"))
                .collect::<Vec<_>>();
            names.extend(self.missing_fields.iter().map(|f| format!("uniform {f}")));
            names.extend(
                self.missing_buffers
                    .iter()
                    .map(|b| format!("storage buffer {b} (in `buffers`)")),
            );
            names.extend(
                self.missing_depth
                    .iter()
                    .map(|d| format!("depth texture {d} (in `depth_passes`)")),
            );
            return Err(ReplayError::MissingResources {
                what: "resources the shader declares".into(),
                names,
            });
        }
        if !self.unsupported.is_empty() {
            self.unsupported.sort();
            self.unsupported.dedup();
            return Err(ReplayError::Unsupported {
                what: self.unsupported.join("; "),
            });
        }
        Ok(())
    }
}

impl Renderer {
    /// Build every session resource the interfaces use (except the variant's own bindings,
    /// `added`). Missing ones are reported together, by name. In phases: what the interfaces need
    /// (checked before any GPU object), then the objects, textures, samplers, uniform and storage
    /// buffers and depth passes, in one error scope.
    pub(super) fn build_scene(
        &self,
        session: &Session,
        ifaces: &[&Interface],
        added: Option<AddedPlace>,
    ) -> Result<Scene, ReplayError> {
        let mut needs = SceneNeeds::of(session, ifaces, added);
        needs.check()?;
        self.scoped(
            "creating the session's resources",
            || -> Result<Scene, ReplayError> {
                let vertex_bgl =
                    reproj_scene_gpu::transform_layout(&self.device, "replay vertex transforms");
                let objects = self.scene_objects(session, &vertex_bgl)?;
                let mut textures = HashMap::new();
                for (name, dim) in &needs.textures {
                    let view =
                        self.assets
                            .texture(self, session, name, &session.textures[name], *dim)?;
                    textures.insert(name.clone(), view);
                }
                let mut samplers = HashMap::new();
                for (name, comparison) in &needs.samplers {
                    let s =
                        self.device
                            .create_sampler(&sampler_descriptor(session, name, *comparison));
                    samplers.insert(name.clone(), s);
                }
                let uniforms = self.scene_buffers(needs.uniforms, wgpu::BufferUsages::UNIFORM);
                let storage = self.scene_buffers(needs.storage, wgpu::BufferUsages::STORAGE);
                let mut depth = BTreeMap::new();
                for name in needs.depth {
                    let pass = DepthPass::new(&self.device, session, &name, &objects, &vertex_bgl);
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

    /// The session's objects: their meshes (kept across replays) and transform buffers.
    fn scene_objects(
        &self,
        session: &Session,
        vertex_bgl: &wgpu::BindGroupLayout,
    ) -> Result<Vec<SceneObject>, ReplayError> {
        let mut objects = Vec::new();
        for (i, o) in session.geometry.objects.iter().enumerate() {
            objects.push(SceneObject {
                mesh: self.assets.mesh(self, session, &o.mesh)?,
                cull: o.cull,
                transforms: Transforms::new(
                    &self.device,
                    vertex_bgl,
                    &format!("object {i} transforms"),
                ),
            });
        }
        Ok(objects)
    }

    /// One buffer of `usage` per need, by name ([`reproj_scene_gpu::buffer`]).
    fn scene_buffers(
        &self,
        needs: BTreeMap<String, BufferNeed>,
        usage: wgpu::BufferUsages,
    ) -> BTreeMap<String, (wgpu::Buffer, u32, Vec<reflect::UniformField>)> {
        needs
            .into_iter()
            .map(|(name, (size, fields))| {
                let buf = reproj_scene_gpu::buffer(&self.device, &name, u64::from(size), usage);
                (name, (buf, size, fields))
            })
            .collect()
    }

    /// Write the frame's uniform values and transforms: this frame's view-projection moved by
    /// `jitter`'s offset of this frame, the previous one by its offset of the previous frame
    /// (where the previous frame was drawn: a cache written then is found there).
    pub(super) fn write_frame_uniforms(
        &self,
        session: &Session,
        scene: &Scene,
        frame: u32,
        jitter: &crate::jitter::Jitter,
    ) {
        let st = session.frame_state(frame);
        let before = frame.saturating_sub(1);
        let prev = session.frame_state(before);
        let size = session.resolution;
        let view_proj = crate::jitter::jittered(st.camera.view_proj, jitter.offset(frame), size);
        let prev_view_proj =
            crate::jitter::jittered(prev.camera.view_proj, jitter.offset(before), size);
        for (i, o) in scene.objects.iter().enumerate() {
            let u = TransformUniform::new(view_proj, prev_view_proj, st.models[i], prev.models[i]);
            o.transforms.write(&self.queue, &u);
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
            self.render_depth_passes(session, scene, &st);
        }
    }

    /// Draw every depth pass of the frame `st` and submit them (ahead of the frame's own work:
    /// the frame loops do not change).
    fn render_depth_passes(&self, session: &Session, scene: &Scene, st: &FrameState) {
        let mut enc = self.device.create_command_encoder(&Default::default());
        for pass in scene.depth.values() {
            pass.write(&self.queue, session, st);
            pass.encode(&mut enc, &scene.objects);
        }
        self.queue.submit([enc.finish()]);
    }
}
