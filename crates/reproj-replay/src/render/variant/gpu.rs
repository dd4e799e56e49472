//! Phase 2 of a variant render: its GPU objects, and the cache cleared before the first frame.

use super::*;
impl Renderer {
    /// The GPU objects of a variant render: the scene, the stages' modules, the payload and depth
    /// copy ping-pong, the frame and classification targets, the samplers, each parity's bind
    /// groups and the passes' pipelines. In phases: the interfaces and the vertex stage
    /// ([`Renderer::variant_shaders`]), the targets ([`Renderer::variant_targets`]), each
    /// parity's bindings ([`Renderer::parity_bindings`]), the pipelines
    /// ([`Renderer::variant_pipelines`]).
    /// `motion`: draw the motion pass also for a variant that reads no motion vectors (the
    /// temporal upsampler reads them).
    pub(in crate::render) fn variant_gpu(
        &self,
        session: &Session,
        variant: &VariantInput,
        plan: &VariantPlan,
        motion: bool,
    ) -> Result<VariantGpu, ReplayError> {
        let m = &variant.manifest;
        let shaders = self.variant_shaders(session, m, plan, motion)?;
        let targets = self.variant_targets(session.resolution, m, &plan.specs);
        // Bindings for each parity (cur = parity, prev = 1 − parity).
        let binds = (0..2usize)
            .map(|parity| self.parity_bindings(parity, m, plan, &shaders, &targets))
            .collect::<Result<Vec<_>, _>>()?;
        let (pipes, pc) = self.variant_pipelines(plan, &shaders, &binds, targets.cache_format)?;
        let specs = &plan.specs;
        let clear = background_color(session);
        let [r, g, b, a] = reproj_instance::payload_clear(m.depth_channel);
        let payload_clear = wgpu::Color { r, g, b, a };
        let host_clears_depth = specs.first().is_some_and(|s| s.depth_load);
        let host_clears_frame = !specs.iter().any(|s| {
            s.colors
                .iter()
                .flatten()
                .any(|(t, load)| *t == Attachment::Frame && !load)
        });
        let VariantShaders {
            scene,
            vgroup,
            motion,
            ..
        } = shaders;
        let VariantTargets {
            payload_v,
            depth_copy_v,
            depth_v,
            color,
            color_view,
            cls,
            cls_view,
            cls_depth_view,
            params,
            ..
        } = targets;
        Ok(VariantGpu {
            scene,
            vgroup,
            payload_v,
            depth_copy_v,
            depth_v,
            color,
            color_view,
            cls,
            cls_view,
            cls_depth_view,
            params,
            binds,
            pipes,
            pc,
            clear,
            payload_clear,
            host_clears_frame,
            host_clears_depth,
            motion,
        })
    }

    /// The passes' interfaces and shared vertex stage: the vertex transforms' group (free in
    /// every stage), the scene they use, the vertex stage writing every input they read (and the
    /// previous clip position), the motion pass where the variant reads motion vectors, and the
    /// passes' fragment modules.
    fn variant_shaders(
        &self,
        session: &Session,
        m: &reproj_instance::Manifest,
        plan: &VariantPlan,
        always_motion: bool,
    ) -> Result<VariantShaders, ReplayError> {
        let [w, h] = session.resolution;
        let (stages, classify_stage) = (&plan.stages, &plan.classify_stage);
        let mut used: BTreeSet<u32> = [m.group].into_iter().collect();
        for s in stages {
            used.extend(s.iface.groups());
        }
        if let Some(c) = &classify_stage {
            used.extend(c.groups());
        }
        let vgroup = free_group(&used, self.device.limits().max_bind_groups)?;
        let mut input_sets: Vec<&[reflect::FragInput]> =
            stages.iter().map(|s| s.iface.inputs.as_slice()).collect();
        if let Some(c) = &classify_stage {
            input_sets.push(&c.inputs);
        }
        let mut inputs = vertex::merge_inputs(&input_sets)?;
        let mut ifaces: Vec<&Interface> = stages.iter().map(|s| &s.iface).collect();
        if let Some(c) = &classify_stage {
            ifaces.push(c);
        }
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
        let fsm: Vec<wgpu::ShaderModule> = stages
            .iter()
            .map(|s| self.shader_module(&s.shader.path.display().to_string(), &s.shader.source))
            .collect::<Result<_, _>>()?;
        Ok(VariantShaders {
            scene,
            vgroup,
            vs_src,
            vs,
            fsm,
            motion,
        })
    }

    /// The targets of frames of `[w, h]`: the payload and depth copy of each parity, the depth
    /// buffer (two, alternating, for a variant written before the depth copy: `specs` list no
    /// depth copy target), the frame, the classification map and its depth; the parameters
    /// buffer and the variant's two samplers.
    fn variant_targets(
        &self,
        [w, h]: [u32; 2],
        m: &reproj_instance::Manifest,
        specs: &[PassSpec],
    ) -> VariantTargets {
        let cache_format = cache_texture_format(m.cache_format);
        let payload = [
            self.target("payload A", w, h, cache_format, true),
            self.target("payload B", w, h, cache_format, true),
        ];
        let depth_copy = [
            self.target("depth copy A", w, h, DEPTH_COPY_FORMAT, true),
            self.target("depth copy B", w, h, DEPTH_COPY_FORMAT, true),
        ];
        // The lookup reads the depth copy or the payload's depth channel; only a variant written
        // before both (no depth copy target) reads the previous depth buffer, which must then
        // alternate like the payload.
        let legacy_depth = m.depth_channel.is_none()
            && !specs.iter().any(|s| {
                s.colors
                    .iter()
                    .flatten()
                    .any(|c| c.0 == Attachment::DepthCopy)
            });
        let depth: Vec<wgpu::Texture> = if legacy_depth {
            vec![
                self.target("depth A", w, h, DEPTH_FORMAT, true),
                self.target("depth B", w, h, DEPTH_FORMAT, true),
            ]
        } else {
            vec![self.target("depth", w, h, DEPTH_FORMAT, false)]
        };
        let views = |ts: &[wgpu::Texture]| -> Vec<wgpu::TextureView> {
            ts.iter()
                .map(|t| t.create_view(&Default::default()))
                .collect()
        };
        let payload_v = views(&payload);
        let depth_copy_v = views(&depth_copy);
        let depth_v = views(&depth);
        let color = self.target("frame color", w, h, FRAME_FORMAT, true);
        let color_view = color.create_view(&Default::default());
        let cls = self.target("classify", w, h, CLASSIFY_FORMAT, false);
        let cls_view = cls.create_view(&Default::default());
        let cls_depth = self.target("classify depth", w, h, DEPTH_FORMAT, false);
        let cls_depth_view = cls_depth.create_view(&Default::default());
        let params = self.buffer(
            contract::PARAMS,
            u64::from(contract::PARAMS_SIZE),
            wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
        );
        let clamp = |filter: wgpu::FilterMode, label: &str| {
            self.device.create_sampler(&wgpu::SamplerDescriptor {
                label: Some(label),
                address_mode_u: wgpu::AddressMode::ClampToEdge,
                address_mode_v: wgpu::AddressMode::ClampToEdge,
                address_mode_w: wgpu::AddressMode::ClampToEdge,
                mag_filter: filter,
                min_filter: filter,
                ..Default::default()
            })
        };
        let point_sampler = clamp(wgpu::FilterMode::Nearest, contract::POINT_SAMPLER);
        let linear_sampler = clamp(wgpu::FilterMode::Linear, contract::LINEAR_SAMPLER);
        VariantTargets {
            cache_format,
            legacy_depth,
            _textures: (payload, depth_copy, depth, cls_depth),
            payload_v,
            depth_copy_v,
            depth_v,
            color,
            color_view,
            cls,
            cls_view,
            cls_depth_view,
            params,
            point_sampler,
            linear_sampler,
        }
    }

    /// The bindings of the frames of parity `parity` (cur = parity, prev = 1 − parity): each
    /// pass's, and the classification entry's (none where it is not rendered).
    fn parity_bindings(
        &self,
        parity: usize,
        m: &reproj_instance::Manifest,
        plan: &VariantPlan,
        shaders: &VariantShaders,
        t: &VariantTargets,
    ) -> Result<(Vec<Bindings>, Bindings), ReplayError> {
        let scene = &shaders.scene;
        let added = AddedResources {
            params: &t.params,
            point_sampler: &t.point_sampler,
            linear_sampler: &t.linear_sampler,
            payload_half: m.cache_format.is_half(),
            prev_payload: &t.payload_v[1 - parity],
            prev_depth_copy: &t.depth_copy_v[1 - parity],
            prev_depth_buffer: t.legacy_depth.then(|| t.depth_at(1 - parity)),
            cur_payload: &t.payload_v[parity],
            motion: shaders.motion.as_ref().map(|mg| &mg.view),
        };
        let mut per_pass = Vec::new();
        for (st, spec) in plan.stages.iter().zip(&plan.specs) {
            per_pass.push(self.bindings(
                &spec.label,
                &st.iface,
                scene,
                Some(m.added_place()),
                Some(&added),
            )?);
        }
        let bc = match &plan.classify_stage {
            Some(c) => self.bindings(
                CLASSIFY_ENTRY,
                c,
                scene,
                Some(m.added_place()),
                Some(&added),
            )?,
            None => Bindings::empty(),
        };
        Ok((per_pass, bc))
    }

    /// Each pass's pipelines (with the bindings of parity 0: both parities' layouts are the
    /// same), and the classification entry's where it is rendered.
    fn variant_pipelines(
        &self,
        plan: &VariantPlan,
        shaders: &VariantShaders,
        binds: &[(Vec<Bindings>, Bindings)],
        cache_format: wgpu::TextureFormat,
    ) -> Result<(Vec<Pipe>, Option<Pipe>), ReplayError> {
        let VariantShaders {
            scene,
            vgroup,
            vs_src,
            vs,
            fsm,
            ..
        } = shaders;
        let stages = &plan.stages;
        let mut pipes = Vec::new();
        for (i, spec) in plan.specs.iter().enumerate() {
            let formats: Vec<Option<wgpu::TextureFormat>> = spec
                .colors
                .iter()
                .map(|c| {
                    c.map(|(t, _)| match t {
                        Attachment::Frame => FRAME_FORMAT,
                        Attachment::Cache => cache_format,
                        Attachment::DepthCopy => DEPTH_COPY_FORMAT,
                    })
                })
                .collect();
            pipes.push(self.pipeline(
                &PipelineSpec {
                    label: &spec.label,
                    sources: [vs_src, &stages[i].shader.source],
                    vs,
                    fs: &fsm[i],
                    entry: &stages[i].iface.entry,
                    formats: &formats,
                    compare: spec.compare,
                    depth_write: spec.depth_write,
                },
                &binds[0].0[i],
                scene,
                *vgroup,
            )?);
        }
        let pc = match &plan.classify_stage {
            Some(_) => Some(self.pipeline(
                &PipelineSpec {
                    label: CLASSIFY_ENTRY,
                    sources: [vs_src, &stages[0].shader.source],
                    vs,
                    fs: &fsm[0],
                    entry: CLASSIFY_ENTRY,
                    formats: &[Some(CLASSIFY_FORMAT)],
                    compare: wgpu::CompareFunction::Less,
                    depth_write: true,
                },
                &binds[0].1,
                scene,
                *vgroup,
            )?),
            None => None,
        };
        Ok((pipes, pc))
    }

    /// Clear both parities' payload, depth copy and depth: the "previous" cache before the first
    /// frame (payload 0, depth 1).
    pub(in crate::render) fn clear_variant_cache(
        &self,
        gpu: &VariantGpu,
    ) -> Result<(), ReplayError> {
        let VariantGpu {
            payload_v,
            depth_copy_v,
            ..
        } = gpu;
        let depth_at = |p: usize| gpu.depth_at(p);
        {
            let mut enc = self.device.create_command_encoder(&Default::default());
            for i in 0..2 {
                let clear_to = |view, color| {
                    Some(wgpu::RenderPassColorAttachment {
                        view,
                        depth_slice: None,
                        resolve_target: None,
                        ops: wgpu::Operations {
                            load: wgpu::LoadOp::Clear(color),
                            store: wgpu::StoreOp::Store,
                        },
                    })
                };
                let _ = enc.begin_render_pass(&wgpu::RenderPassDescriptor {
                    label: Some("clear cache"),
                    color_attachments: &[
                        clear_to(&payload_v[i], gpu.payload_clear),
                        clear_to(&depth_copy_v[i], DEPTH_COPY_CLEAR),
                    ],
                    depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                        view: depth_at(i),
                        depth_ops: Some(wgpu::Operations {
                            load: wgpu::LoadOp::Clear(1.0),
                            store: wgpu::StoreOp::Store,
                        }),
                        stencil_ops: None,
                    }),
                    ..Default::default()
                });
            }
            self.queue.submit([enc.finish()]);
            self.wait()?;
            self.check_errors("clearing the cache")?;
        }

        Ok(())
    }
}

/// The texture format of a cache format.
fn cache_texture_format(format: CacheFormat) -> wgpu::TextureFormat {
    match format {
        CacheFormat::Rgba32float => wgpu::TextureFormat::Rgba32Float,
        CacheFormat::Rg32float => wgpu::TextureFormat::Rg32Float,
        CacheFormat::R32float => wgpu::TextureFormat::R32Float,
        CacheFormat::Rgba16float => wgpu::TextureFormat::Rgba16Float,
        CacheFormat::Rg16float => wgpu::TextureFormat::Rg16Float,
        CacheFormat::R16float => wgpu::TextureFormat::R16Float,
    }
}

/// The interfaces' shared objects ([`Renderer::variant_shaders`]).
struct VariantShaders {
    scene: Scene,
    /// The bind group the replay's vertex stage uses (free in every stage).
    vgroup: u32,
    /// The vertex stage, its WGSL (for the pipeline cache key) and module.
    vs_src: String,
    vs: wgpu::ShaderModule,
    /// Each pass's fragment module.
    fsm: Vec<wgpu::ShaderModule>,
    motion: Option<motion::MotionGpu>,
}

/// The targets, parameters buffer and samplers of a variant render
/// ([`Renderer::variant_targets`]).
struct VariantTargets {
    cache_format: wgpu::TextureFormat,
    /// A variant written before the depth copy: it reads the previous depth buffer.
    legacy_depth: bool,
    /// The payloads, depth copies, depth buffers and classification depth, held while the
    /// render's objects are made (their views are what is used).
    _textures: (
        [wgpu::Texture; 2],
        [wgpu::Texture; 2],
        Vec<wgpu::Texture>,
        wgpu::Texture,
    ),
    payload_v: Vec<wgpu::TextureView>,
    depth_copy_v: Vec<wgpu::TextureView>,
    depth_v: Vec<wgpu::TextureView>,
    color: wgpu::Texture,
    color_view: wgpu::TextureView,
    cls: wgpu::Texture,
    cls_view: wgpu::TextureView,
    cls_depth_view: wgpu::TextureView,
    params: wgpu::Buffer,
    point_sampler: wgpu::Sampler,
    linear_sampler: wgpu::Sampler,
}

impl VariantTargets {
    /// The depth buffer of the frame of parity `p`.
    fn depth_at(&self, p: usize) -> &wgpu::TextureView {
        &self.depth_v[p % self.depth_v.len()]
    }
}

/// The GPU objects of a variant render ([`Renderer::variant_gpu`]).
pub(in crate::render) struct VariantGpu {
    pub(in crate::render) scene: Scene,
    /// The bind group the replay's vertex stage uses (free in every stage).
    pub(in crate::render) vgroup: u32,
    /// The payload and the depth copy of each parity (the depth copy unused where the payload
    /// holds the depth).
    pub(in crate::render) payload_v: Vec<wgpu::TextureView>,
    pub(in crate::render) depth_copy_v: Vec<wgpu::TextureView>,
    /// One depth buffer, or two that alternate for a variant written before the depth copy.
    pub(in crate::render) depth_v: Vec<wgpu::TextureView>,
    pub(in crate::render) color: wgpu::Texture,
    pub(in crate::render) color_view: wgpu::TextureView,
    pub(in crate::render) cls: wgpu::Texture,
    pub(in crate::render) cls_view: wgpu::TextureView,
    pub(in crate::render) cls_depth_view: wgpu::TextureView,
    pub(in crate::render) params: wgpu::Buffer,
    /// Per parity: each pass's bindings and the classification entry's.
    pub(in crate::render) binds: Vec<(Vec<Bindings>, Bindings)>,
    pub(in crate::render) pipes: Vec<Pipe>,
    /// The classification pipeline, when it is rendered.
    pub(in crate::render) pc: Option<Pipe>,
    /// The session's background.
    pub(in crate::render) clear: wgpu::Color,
    /// What the payload is cleared to: 0, and the far plane in the depth channel if it has one.
    pub(in crate::render) payload_clear: wgpu::Color,
    /// No pass clears the frame (`--frame-load load`): the host clears it to the background.
    pub(in crate::render) host_clears_frame: bool,
    /// The first pass loads the depth (`--depth-load load`): the host clears it (there is no
    /// other geometry in a replay).
    pub(in crate::render) host_clears_depth: bool,
    /// The motion vectors' texture and pass, for a variant that reads them.
    pub(in crate::render) motion: Option<motion::MotionGpu>,
}

impl VariantGpu {
    /// The depth buffer of the frame of parity `p`.
    pub(super) fn depth_at(&self, p: usize) -> &wgpu::TextureView {
        &self.depth_v[p % self.depth_v.len()]
    }
}
