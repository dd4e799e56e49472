//! Phase 2 of a variant render: its GPU objects. The variant itself — its payload and depth-copy
//! ping-pong, samplers, parameters, bind groups and pipelines — is built by `reproj-runtime`, the
//! code a host ships, and kept across replays ([`VARIANT_CACHE_LEN`]); the replay adds the scene,
//! its vertex stage and bindings, the frame and depth targets, the classification map and the
//! motion pass.

use std::sync::atomic::Ordering;
use std::sync::{Arc, Mutex, PoisonError};

use reproj_runtime::{SharedGroup, VertexStage};
use reproj_scene::session::Cull;

use super::*;

/// Variants kept built across replays (an `analyze` races a node's few at once; a bench's blocks
/// replay the same ones again and again): on a CPU rasterizer compiling the passes is most of a
/// replay's set-up time.
pub(in crate::render) const VARIANT_CACHE_LEN: usize = 6;

/// A variant built on the device, kept across replays under its key ([`Renderer::variant_gpu`]).
pub(in crate::render) type BuiltVariant = Arc<Mutex<reproj_runtime::VariantResources>>;

impl Renderer {
    /// The GPU objects of a variant render: the scene, its bindings and vertex stage, the frame,
    /// depth and classification targets, the motion pass, and the variant built by the runtime
    /// (or found built by an earlier replay). `motion`: draw the motion pass also for a variant
    /// that reads no motion vectors (the temporal upsampler reads them).
    pub(in crate::render) fn variant_gpu(
        &self,
        session: &Session,
        variant: &VariantInput,
        plan: &VariantPlan,
        motion: bool,
    ) -> Result<VariantGpu, ReplayError> {
        let m = &variant.manifest;
        let shaders = self.variant_shaders(session, m, plan, motion)?;
        let VariantShaders {
            scene,
            vgroup,
            vs_src,
            vs,
            motion,
        } = shaders;
        let [w, h] = session.resolution;
        let depth = self.target("depth", w, h, DEPTH_FORMAT, false);
        let depth_view = depth.create_view(&Default::default());
        let color = self.target("frame color", w, h, FRAME_FORMAT, true);
        let color_view = color.create_view(&Default::default());
        let cls = self.target("classify", w, h, CLASSIFY_FORMAT, false);
        let cls_view = cls.create_view(&Default::default());
        let cls_depth = self.target("classify depth", w, h, DEPTH_FORMAT, false);
        let cls_depth_view = cls_depth.create_view(&Default::default());
        let scene_iface = scene_interface(plan, m.added_place());
        let binds = self.bindings("scene", &scene_iface, &scene)?;
        let culls = culls(&scene);
        let built = self.built_variant(
            plan,
            &BuildInputs {
                scene: &scene,
                culls: &culls,
                scene_iface: &scene_iface,
                binds: &binds,
                vgroup,
                vs: (&vs_src, &vs),
                size: [w, h],
                // The upsampler draws the motion pass for its resolve; the passes read it only
                // where the variant reads motion vectors.
                motion: motion
                    .as_ref()
                    .filter(|_| m.reprojection == Reprojection::MotionVectors)
                    .map(|mg| &mg.view),
            },
        )?;
        Ok(VariantGpu {
            runtime: built,
            group: m.group,
            culls,
            scene,
            vgroup,
            binds,
            depth_view,
            color,
            color_view,
            cls,
            cls_view,
            cls_depth_view,
            clear: background_color(session),
            host_clears_frame: plan.runtime.loads_frame_first(),
            host_clears_depth: plan.runtime.loads_depth_first(),
            motion,
            _textures: [depth, cls_depth],
        })
    }

    /// The scene, the vertex stage writing every input the passes read (and the previous clip
    /// position), and the motion pass where the variant reads motion vectors.
    fn variant_shaders(
        &self,
        session: &Session,
        m: &reproj_instance::Manifest,
        plan: &VariantPlan,
        always_motion: bool,
    ) -> Result<VariantShaders, ReplayError> {
        let [w, h] = session.resolution;
        let ifaces: Vec<&Interface> = plan.interfaces().collect();
        let used: BTreeSet<u32> = ifaces
            .iter()
            .flat_map(|i| i.groups())
            .chain([m.group])
            .collect();
        let vgroup = free_group(&used, self.device.limits().max_bind_groups)?;
        let input_sets: Vec<&[reflect::FragInput]> =
            ifaces.iter().map(|i| i.inputs.as_slice()).collect();
        let mut inputs = vertex::merge_inputs(&input_sets)?;
        let scene = self.build_scene(session, &ifaces, Some(m.added_place()))?;
        // With motion vectors the passes read no previous clip position; the replay's motion
        // pass (the engine's velocity pass) does, one location past the shader's inputs.
        let prev_clip_location = match m.vertex.prev_clip_location {
            Some(location) => location,
            None => {
                let input = motion::prev_clip_input(&inputs);
                let location = input.location;
                inputs.push(input);
                location
            }
        };
        let vs_src =
            vertex::vertex_wgsl(vgroup, &inputs, &session.inputs, Some(prev_clip_location))?;
        let vs = self.shader_module("replay vertex stage (variant)", &vs_src)?;
        let motion = match m.reprojection {
            Reprojection::Vertex if !always_motion => None,
            Reprojection::Vertex | Reprojection::MotionVectors => {
                Some(self.motion_gpu([w, h], &vs, &vs_src, &scene, vgroup, prev_clip_location)?)
            }
        };
        Ok(VariantShaders {
            scene,
            vgroup,
            vs_src,
            vs,
            motion,
        })
    }

    /// The variant built by the runtime for this scene and frame size: found built by an earlier
    /// replay under the same key (the passes, the vertex stage, the scene's layouts, the size,
    /// whether it reads motion and draws the hit map; its motion vectors and shared bindings
    /// given again), else built and kept.
    fn built_variant(
        &self,
        plan: &VariantPlan,
        b: &BuildInputs<'_>,
    ) -> Result<BuiltVariant, ReplayError> {
        let runtime = &plan.runtime;
        let group = runtime.group();
        let shared = b.binds.layouts.contains_key(&group);
        let key = format!(
            "{}|{:?}|{}|{:?}|{:?}|{}|{:?}|{}|{}",
            plan.manifest_json,
            plan.sources,
            b.vs.0,
            b.binds.layout_keys,
            b.culls,
            b.vgroup,
            b.size,
            b.motion.is_some(),
            plan.classify_stage.is_some(),
        );
        // The shared group's resources (a shader on all four groups): the scene's, given to the
        // runtime to bind beside its own.
        let shared_rs = by_group(b.scene_iface).remove(&group).unwrap_or_default();
        let (shared_layout, shared_bind) = if shared {
            group_entries("scene", group, &shared_rs, b.scene)?
        } else {
            Default::default()
        };
        let shared_entries = entries_of(&shared_rs, shared_bind);
        let shared = shared.then_some(SharedGroup {
            layout: &shared_layout,
            resources: &shared_entries,
        });
        let found = {
            let mut cache = self.variants.lock().unwrap_or_else(PoisonError::into_inner);
            // Not one another render holds (beside the cache): its frames would interleave.
            let at = cache
                .iter()
                .position(|(k, v)| *k == key && Arc::strong_count(v) == 1);
            at.map(|i| {
                let hit = cache.remove(i);
                cache.push(hit.clone());
                hit.1
            })
        };
        let gpu_err = |e| runtime_error(&plan.label, e);
        if let Some(built) = found {
            self.pipeline_hits.fetch_add(1, Ordering::Relaxed);
            {
                let mut res = built.lock().unwrap_or_else(PoisonError::into_inner);
                if let Some(view) = b.motion {
                    res.set_motion(&self.device, view).map_err(gpu_err)?;
                }
                if let Some(shared) = &shared {
                    res.set_shared(&self.device, shared).map_err(gpu_err)?;
                }
            }
            return Ok(built);
        }
        let attrs = wgpu::vertex_attr_array![0 => Float32x3, 1 => Float32x3, 2 => Float32x2, 3 => Float32x4];
        let buffers = [Some(wgpu::VertexBufferLayout {
            array_stride: std::mem::size_of::<reproj_scene::mesh::Vertex>() as u64,
            step_mode: wgpu::VertexStepMode::Vertex,
            attributes: &attrs,
        })];
        let stages: Vec<VertexStage<'_>> = b
            .culls
            .iter()
            .map(|cull| VertexStage {
                module: b.vs.1,
                entry_point: crate::vertex::VERTEX_ENTRY,
                buffers: &buffers,
                primitive: wgpu::PrimitiveState {
                    topology: wgpu::PrimitiveTopology::TriangleList,
                    front_face: wgpu::FrontFace::Ccw,
                    cull_mode: (*cull == Cull::Back).then_some(wgpu::Face::Back),
                    ..Default::default()
                },
            })
            .collect();
        let mut layouts: Vec<(u32, &wgpu::BindGroupLayout)> = b
            .binds
            .layouts
            .iter()
            .filter(|(g, _)| **g != group)
            .map(|(g, l)| (*g, l))
            .collect();
        layouts.push((b.vgroup, &b.scene.vertex_bgl));
        let resources = runtime
            .create(
                &self.device,
                &reproj_runtime::Setup {
                    size: b.size,
                    color_format: FRAME_FORMAT,
                    vertex: &stages,
                    bind_group_layouts: &layouts,
                    motion: b.motion,
                    shared,
                    classification: plan.classify_stage.as_ref().map(|_| CLASSIFY_FORMAT),
                },
            )
            .map_err(gpu_err)?;
        let built = Arc::new(Mutex::new(resources));
        let mut cache = self.variants.lock().unwrap_or_else(PoisonError::into_inner);
        cache.retain(|(k, _)| *k != key);
        if cache.len() >= VARIANT_CACHE_LEN {
            cache.remove(0);
        }
        cache.push((key, built.clone()));
        Ok(built)
    }
}

/// The cull modes the scene's objects use, in order: the runtime builds one pipeline of each
/// pass per mode ([`reproj_runtime::Setup::vertex`]).
fn culls(scene: &Scene) -> Vec<Cull> {
    let mut culls: Vec<Cull> = Vec::new();
    for o in &scene.objects {
        if !culls.contains(&o.cull) {
            culls.push(o.cull);
        }
    }
    culls.sort_by_key(|c| *c as u8);
    culls
}

/// The original shader's resources the passes (and the classification entry) read, once each:
/// what the scene binds. The variant's own bindings (its group, from its binding base) are the
/// runtime's.
fn scene_interface(plan: &VariantPlan, added: reproj_instance::contract::AddedPlace) -> Interface {
    let mut iface = plan.stages[0].iface.clone();
    iface.resources.clear();
    for r in plan.interfaces().flat_map(|i| &i.resources) {
        if !added.holds(r.group, r.binding)
            && !iface
                .resources
                .iter()
                .any(|o| (o.group, o.binding) == (r.group, r.binding))
        {
            iface.resources.push(r.clone());
        }
    }
    iface.resources.sort_by_key(|r| (r.group, r.binding));
    iface
}

/// What building a variant reads ([`Renderer::built_variant`]).
struct BuildInputs<'a> {
    scene: &'a Scene,
    /// The scene's cull modes ([`culls`]): one vertex stage each.
    culls: &'a [Cull],
    scene_iface: &'a Interface,
    binds: &'a Bindings,
    vgroup: u32,
    /// The vertex stage's WGSL (for the cache key) and module.
    vs: (&'a str, &'a wgpu::ShaderModule),
    size: [u32; 2],
    motion: Option<&'a wgpu::TextureView>,
}

/// The scene and the replay's shaders ([`Renderer::variant_shaders`]).
struct VariantShaders {
    scene: Scene,
    /// The bind group the replay's vertex stage uses (free in every stage).
    vgroup: u32,
    /// The vertex stage, its WGSL (for the cache key) and module.
    vs_src: String,
    vs: wgpu::ShaderModule,
    motion: Option<motion::MotionGpu>,
}

/// The GPU objects of a variant render ([`Renderer::variant_gpu`]).
pub(in crate::render) struct VariantGpu {
    /// The variant on the device, built by the runtime.
    pub(in crate::render) runtime: BuiltVariant,
    /// The variant's group: the scene sets no bind group there.
    pub(in crate::render) group: u32,
    /// The cull modes, as the runtime's pipelines of each pass are ordered.
    pub(in crate::render) culls: Vec<Cull>,
    pub(in crate::render) scene: Scene,
    /// The bind group the replay's vertex stage uses (free in every stage).
    pub(in crate::render) vgroup: u32,
    /// The scene's bindings of the original shader's resources the passes read.
    pub(in crate::render) binds: Bindings,
    pub(in crate::render) depth_view: wgpu::TextureView,
    pub(in crate::render) color: wgpu::Texture,
    pub(in crate::render) color_view: wgpu::TextureView,
    pub(in crate::render) cls: wgpu::Texture,
    pub(in crate::render) cls_view: wgpu::TextureView,
    pub(in crate::render) cls_depth_view: wgpu::TextureView,
    /// The session's background.
    pub(in crate::render) clear: wgpu::Color,
    /// No pass clears the frame (`--frame-load load`): the host clears it to the background.
    pub(in crate::render) host_clears_frame: bool,
    /// The first pass loads the depth (`--depth-load load`): the host clears it (there is no
    /// other geometry in a replay).
    pub(in crate::render) host_clears_depth: bool,
    /// The motion vectors' texture and pass, for a variant that reads them.
    pub(in crate::render) motion: Option<motion::MotionGpu>,
    /// The depth and classification depth textures, held (their views are what is used).
    _textures: [wgpu::Texture; 2],
}

impl VariantGpu {
    /// The scene's bind groups a frame sets (every group but the variant's).
    pub(in crate::render) fn scene_groups(&self) -> Vec<(u32, &wgpu::BindGroup)> {
        self.binds
            .groups
            .iter()
            .filter(|(g, _)| **g != self.group)
            .map(|(g, bg)| (*g, bg))
            .collect()
    }

    /// Draw the scene's objects with `pipelines` (one per cull mode, [`VariantGpu::culls`]).
    pub(in crate::render) fn draw_objects(
        &self,
        pass: &mut wgpu::RenderPass<'_>,
        pipelines: &[wgpu::RenderPipeline],
    ) {
        for o in &self.scene.objects {
            if let Some(i) = self.culls.iter().position(|c| *c == o.cull) {
                pass.set_pipeline(&pipelines[i]);
            }
            o.draw(pass, self.vgroup);
        }
    }
}
