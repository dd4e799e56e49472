//! [`VariantResources`]: a variant on a device — its textures, samplers, params buffer, bind groups
//! and pipelines — and [`VariantResources::record`], a frame recorded into the application's
//! command encoder.

use std::collections::BTreeMap;
use std::sync::Arc;

use crate::RuntimeError;
use crate::build::{PassGpu, Texture, build_pass, checked, sampler, textures};
use crate::plan::{Added, Attachment, ColorLoad, PassPlan, Plan};
pub use crate::setup::{Setup, VertexStage};
use crate::shared::{Shared, SharedGroup};

mod classify;

/// The application's targets for one frame.
#[derive(Debug, Clone, Copy)]
pub struct FrameTargets<'a> {
    /// The color target (the manifest's `frame`): of [`Setup::color_format`] and the frame's size.
    pub color: &'a wgpu::TextureView,
    /// The depth target: of the manifest's depth format (`depth32float` in what reproj writes)
    /// and the frame's size, with `RENDER_ATTACHMENT` usage. The first pass clears it and the
    /// passes leave the scene's depth in it.
    pub depth: &'a wgpu::TextureView,
    /// The application's clear color: what a pass whose frame load is `clear` with `null` clears to.
    pub clear_color: wgpu::Color,
}

/// What changes from frame to frame.
#[derive(Debug, Clone, Copy, Default)]
pub struct FrameInputs<'a> {
    /// The refresh period Δn this frame (1 or more): the `delta_n` parameter's value, from
    /// [`crate::Variant::scheduled_delta_n`] say. `None`: the manifest's.
    pub delta_n: Option<u32>,
    /// Start over (a camera cut, a teleport): this frame is frame 0 again, every pixel is
    /// recomputed and nothing of the previous frames is read.
    pub restart: bool,
    /// The application's frame-wide bind groups, by group index, set before the draw callback
    /// runs (the original shader's resources). Per-object groups are set in the callback.
    pub bind_groups: &'a [(u32, &'a wgpu::BindGroup)],
    /// Timestamp queries (at least 2 × [`crate::Variant::render_pass_count`] of them): render
    /// pass `r` writes `2r` at its beginning and `2r + 1` at its end (passes that share their
    /// targets share a render pass, [`crate::Variant::render_passes`]).
    pub timestamps: Option<&'a wgpu::QuerySet>,
    /// Occlusion queries (at least [`crate::Variant::pass_count`] of them): pass `i` counts the
    /// samples it draws into query `i` — in a `3pass` variant the pixels that reused the cache
    /// (pass 1), that recomputed the node (pass 2) and every pixel shaded (pass 3); in a `2pass`
    /// one the hits and the misses. The hit rate of a frame, measured where it is drawn.
    pub occlusion: Option<&'a wgpu::QuerySet>,
    /// The frame index the passes see (the `clock` parameter, which phases their refresh
    /// schedule). `None`: the frames counted since the last restart ([`VariantResources::frame`]).
    /// Which textures are read and written follows that count either way.
    pub clock: Option<u32>,
    /// Record every pass in a render pass of its own, even where passes could share one
    /// ([`crate::Variant::render_passes`]): [`FrameInputs::timestamps`] then time each pass apart
    /// (`2i` and `2i + 1` for pass `i`). Costs a store and reload of the targets between them.
    pub separate_passes: bool,
}

/// A variant on a device, for one frame size: textures (payload and depth-copy ping-pong),
/// samplers, the params buffer, bind groups, pipelines, and the frame clock.
#[derive(Debug)]
pub struct VariantResources {
    plan: Arc<Plan>,
    size: [u32; 2],
    color_format: wgpu::TextureFormat,
    /// Indexed as the plan's textures; `None` for the depth attachment (the application's).
    textures: Vec<Option<Texture>>,
    samplers: Vec<wgpu::Sampler>,
    params: wgpu::Buffer,
    passes: Vec<PassGpu>,
    /// The application's motion vectors ([`Setup::motion`]).
    motion: Option<wgpu::TextureView>,
    /// The application's bindings of a shared group ([`Setup::shared`]).
    shared: Shared,
    /// The index of the next frame (0: nothing to reuse).
    frame: u32,
    /// The textures are new: clear them before the next frame reads them.
    fresh: bool,
}

impl VariantResources {
    pub(crate) fn new(
        device: &wgpu::Device,
        plan: Arc<Plan>,
        setup: &Setup<'_>,
    ) -> Result<VariantResources, RuntimeError> {
        let missing = plan.required_features - device.features();
        if !missing.is_empty() {
            let names: Vec<&str> = missing.iter().filter_map(|f| f.as_str()).collect();
            return Err(RuntimeError::MissingFeatures {
                missing: names.join(", "),
            });
        }
        check_size(setup.size)?;
        if setup.vertex.is_empty() {
            return Err(RuntimeError::usage("Setup::vertex", "no vertex stage"));
        }
        if plan.motion != setup.motion.is_some() {
            return Err(RuntimeError::usage(
                "Setup::motion",
                if plan.motion {
                    "is None, but the variant reads the motion vectors (manifest `reprojection: motion_vectors`): give their texture"
                } else {
                    "is given, but the variant reads no motion vectors (manifest `reprojection: vertex`)"
                },
            ));
        }
        let user: BTreeMap<u32, &wgpu::BindGroupLayout> =
            setup.bind_group_layouts.iter().copied().collect();
        if user.len() != setup.bind_group_layouts.len() {
            return Err(RuntimeError::usage(
                "Setup::bind_group_layouts",
                "gives a group twice",
            ));
        }
        if user.contains_key(&plan.group) {
            return Err(RuntimeError::usage(
                "Setup::bind_group_layouts",
                format!(
                    "group {} is the variant's own group (the manifest's `group`)",
                    plan.group
                ),
            ));
        }
        let (textures, samplers, params) =
            checked(device, "the variant's textures and buffers", || {
                let samplers = plan.samplers.iter().map(|s| sampler(device, s)).collect();
                let params = device.create_buffer(&wgpu::BufferDescriptor {
                    label: Some("reproj_params"),
                    size: plan.params_size as u64,
                    usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
                    mapped_at_creation: false,
                });
                (textures(device, &plan, setup.size), samplers, params)
            })?;
        let shared = Shared::new(
            setup.shared.as_ref(),
            plan.group,
            plan.binding_base,
            &plan.passes,
        )?;
        let mut passes = Vec::new();
        for (i, p) in plan.passes.iter().enumerate() {
            let classify = setup.classification.filter(|_| i == 0);
            passes.push(build_pass(
                device,
                &plan,
                p,
                setup,
                &user,
                (&shared, classify),
            )?);
        }
        let mut r = VariantResources {
            plan,
            size: setup.size,
            color_format: setup.color_format,
            textures,
            samplers,
            params,
            passes,
            motion: setup.motion.cloned(),
            shared,
            frame: 0,
            fresh: true,
        };
        r.bind(device)?;
        Ok(r)
    }

    /// The frame size the textures have.
    pub fn size(&self) -> [u32; 2] {
        self.size
    }

    /// The index of the next frame [`VariantResources::record`] records: 0 after creating or
    /// resizing, counted from the last [`FrameInputs::restart`].
    pub fn frame(&self) -> u32 {
        self.frame
    }

    /// Reallocate the textures for a new frame size. The frame clock starts over: the next frame
    /// recomputes every pixel.
    pub fn resize(&mut self, device: &wgpu::Device, size: [u32; 2]) -> Result<(), RuntimeError> {
        check_size(size)?;
        self.textures = checked(device, "the variant's textures", || {
            textures(device, &self.plan, size)
        })?;
        self.size = size;
        self.frame = 0;
        self.fresh = true;
        self.bind(device)
    }

    /// Give the motion-vector texture again (after the application made a new one, on a resize):
    /// the bind groups are rebuilt. An error for a variant that reads no motion vectors.
    pub fn set_motion(
        &mut self,
        device: &wgpu::Device,
        motion: &wgpu::TextureView,
    ) -> Result<(), RuntimeError> {
        if !self.plan.motion {
            return Err(RuntimeError::usage(
                "set_motion",
                "the variant reads no motion vectors (manifest `reprojection: vertex`)",
            ));
        }
        self.motion = Some(motion.clone());
        self.bind(device)
    }

    /// Give the application's bindings of the shared group again (after it made new resources):
    /// the bind groups are rebuilt. The layout entries must be those given at creation. An error
    /// for a variant whose group is its own.
    pub fn set_shared(
        &mut self,
        device: &wgpu::Device,
        shared: &SharedGroup<'_>,
    ) -> Result<(), RuntimeError> {
        let new = Shared::new(
            Some(shared),
            self.plan.group,
            self.plan.binding_base,
            &self.plan.passes,
        )?;
        if new.layout != self.shared.layout {
            return Err(RuntimeError::usage(
                "set_shared",
                "gives other layout entries than `Setup::shared` did (the pipelines were made with those)",
            ));
        }
        self.shared = new;
        self.bind(device)
    }

    /// (Re)build the runtime's bind groups for every pass and ping-pong entry.
    fn bind(&mut self, device: &wgpu::Device) -> Result<(), RuntimeError> {
        let mut all = Vec::new();
        for (p, gp) in self.plan.passes.iter().zip(&self.passes) {
            let layouts = &gp.layouts;
            all.push(checked(device, &p.label, || {
                (0..self.plan.ping_pong)
                    .map(|k| {
                        layouts
                            .iter()
                            .map(|(g, layout)| {
                                let entries = self.entries(p, *g, k);
                                let group = device.create_bind_group(&wgpu::BindGroupDescriptor {
                                    label: Some(&p.label),
                                    layout,
                                    entries: &entries,
                                });
                                (*g, group)
                            })
                            .collect()
                    })
                    .collect()
            })?);
        }
        for (gp, groups) in self.passes.iter_mut().zip(all) {
            gp.groups = groups;
        }
        Ok(())
    }

    /// The entries of pass `p`'s bind group `g` on ping-pong entry `k`.
    fn entries(&self, p: &PassPlan, g: u32, k: usize) -> Vec<wgpu::BindGroupEntry<'_>> {
        let own = self.shared.entries_for(p).filter(|_| g == self.plan.group);
        p.added
            .iter()
            .filter(|b| b.group == g)
            .map(|b| wgpu::BindGroupEntry {
                binding: b.binding,
                resource: match &b.resource {
                    Added::Params => self.params.as_entire_binding(),
                    Added::Texture(ts) => wgpu::BindingResource::TextureView(
                        // `Plan::new` refuses a manifest whose passes sample the depth
                        // attachment, the one texture the runtime does not own.
                        &self.textures[ts[k]]
                            .as_ref()
                            .expect("only the depth attachment is not the runtime's")
                            .view,
                    ),
                    Added::Sampler(s) => wgpu::BindingResource::Sampler(&self.samplers[*s]),
                    Added::Motion => wgpu::BindingResource::TextureView(
                        self.motion
                            .as_ref()
                            .expect("`new` refuses a variant that reads motion without them"),
                    ),
                },
            })
            .chain(own)
            .collect()
    }

    /// Record one frame into `encoder`: write its `reproj_params` (through `queue`, so submit the
    /// encoder before recording the next frame), then each pass in order with its attachments and
    /// load/store operations, the application's `bind_groups` and the runtime's, calling `draw`
    /// to draw the application's geometry with the pass's pipelines (one per [`Setup::vertex`]
    /// stage, in that order). Passes that draw into the same targets, the later loading them all,
    /// share one render pass ([`crate::Variant::render_passes`]): `draw` is then called once per
    /// pass within it. Advances the frame clock and so the ping-pong.
    pub fn record<F>(
        &mut self,
        queue: &wgpu::Queue,
        encoder: &mut wgpu::CommandEncoder,
        targets: &FrameTargets<'_>,
        inputs: &FrameInputs<'_>,
        mut draw: F,
    ) -> Result<(), RuntimeError>
    where
        F: FnMut(&mut wgpu::RenderPass<'_>, &[wgpu::RenderPipeline]),
    {
        self.check_targets(targets)?;
        for (g, _) in inputs.bind_groups {
            if *g == self.plan.group {
                return Err(RuntimeError::usage(
                    "FrameInputs::bind_groups",
                    format!("group {g} is the variant's own group"),
                ));
            }
        }
        if inputs.delta_n.is_some() && !self.plan.has_delta_n() {
            return Err(RuntimeError::usage(
                "FrameInputs::delta_n",
                "the manifest's params have no `delta_n` field",
            ));
        }
        if inputs.restart {
            self.frame = 0;
        }
        if self.fresh {
            self.clear_textures(encoder);
            self.fresh = false;
        }
        let frame = self.frame;
        queue.write_buffer(
            &self.params,
            0,
            &self.plan.params_bytes(frame, inputs.clock, inputs.delta_n),
        );
        let k = frame as usize % self.plan.ping_pong;
        let singles: Vec<std::ops::Range<usize>>;
        let render_passes = if inputs.separate_passes {
            singles = (0..self.plan.passes.len()).map(|i| i..i + 1).collect();
            &singles
        } else {
            &self.plan.render_passes
        };
        for (r, passes) in render_passes.iter().enumerate() {
            // Loaded as the first pass loads, stored as the last stores.
            let (first, last) = (
                &self.plan.passes[passes.start],
                &self.plan.passes[passes.end - 1],
            );
            let mut colors = self.color_attachments(first, k, targets);
            for c in &last.colors {
                if let Some(Some(a)) = colors.get_mut(c.location as usize) {
                    a.ops.store = store(c.store);
                }
            }
            let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
                label: Some(&first.label),
                color_attachments: &colors,
                depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                    view: targets.depth,
                    depth_ops: Some(wgpu::Operations {
                        load: first
                            .depth
                            .clear
                            .map_or(wgpu::LoadOp::Load, wgpu::LoadOp::Clear),
                        store: store(last.depth.store),
                    }),
                    stencil_ops: None,
                }),
                timestamp_writes: inputs.timestamps.map(|query_set| {
                    wgpu::RenderPassTimestampWrites {
                        query_set,
                        beginning_of_pass_write_index: Some(2 * r as u32),
                        end_of_pass_write_index: Some(2 * r as u32 + 1),
                    }
                }),
                occlusion_query_set: inputs.occlusion,
                multiview_mask: None,
            });
            for i in passes.clone() {
                let gp = &self.passes[i];
                for (g, bg) in inputs.bind_groups {
                    pass.set_bind_group(*g, *bg, &[]);
                }
                for (g, bg) in &gp.groups[k] {
                    pass.set_bind_group(*g, bg, &[]);
                }
                if inputs.occlusion.is_some() {
                    pass.begin_occlusion_query(i as u32);
                }
                draw(&mut pass, &gp.pipelines);
                if inputs.occlusion.is_some() {
                    pass.end_occlusion_query();
                }
            }
        }
        // Past u32::MAX the clock goes on at the same ping-pong entry without meaning frame 0.
        let next = u64::from(frame) + 1;
        let len = self.plan.ping_pong as u64;
        self.frame = u32::try_from(next).unwrap_or((next % len + len) as u32);
        Ok(())
    }

    /// The color attachments of pass `p` on ping-pong entry `k`, by location.
    fn color_attachments<'a>(
        &'a self,
        p: &PassPlan,
        k: usize,
        targets: &FrameTargets<'a>,
    ) -> Vec<Option<wgpu::RenderPassColorAttachment<'a>>> {
        let mut colors: Vec<Option<wgpu::RenderPassColorAttachment<'a>>> = Vec::new();
        for c in &p.colors {
            let view = match &c.attachment {
                Attachment::Frame => targets.color,
                Attachment::Texture(ts) => match &self.textures[ts[k]] {
                    Some(t) => &t.view,
                    None => targets.depth,
                },
            };
            let load = match c.load {
                ColorLoad::Load => wgpu::LoadOp::Load,
                ColorLoad::Clear(value) => {
                    wgpu::LoadOp::Clear(value.unwrap_or(targets.clear_color))
                }
            };
            let at = c.location as usize;
            if colors.len() <= at {
                colors.resize(at + 1, None);
            }
            colors[at] = Some(wgpu::RenderPassColorAttachment {
                view,
                depth_slice: None,
                resolve_target: None,
                ops: wgpu::Operations {
                    load,
                    store: store(c.store),
                },
            });
        }
        colors
    }

    /// The targets are of the formats and size the variant was built for.
    fn check_targets(&self, targets: &FrameTargets<'_>) -> Result<(), RuntimeError> {
        let depth_format = self.plan.textures[self.plan.depth_texture].format;
        for (what, view, format) in [
            ("FrameTargets::color", targets.color, self.color_format),
            ("FrameTargets::depth", targets.depth, depth_format),
        ] {
            let t = view.texture();
            if t.format() != format {
                return Err(RuntimeError::usage(
                    what,
                    format!("is {:?}, the variant was built for {format:?}", t.format()),
                ));
            }
            let s = t.size();
            if [s.width, s.height] != self.size {
                return Err(RuntimeError::usage(
                    what,
                    format!(
                        "is {}×{}, the variant's textures are {}×{} (resize them)",
                        s.width, s.height, self.size[0], self.size[1]
                    ),
                ));
            }
            if !t.usage().contains(wgpu::TextureUsages::RENDER_ATTACHMENT) {
                return Err(RuntimeError::usage(what, "has no RENDER_ATTACHMENT usage"));
            }
        }
        Ok(())
    }

    /// Clear every render-attachment texture the runtime owns, before the first frame reads
    /// them: depth formats to the manifest's `conventions.depth_clear`, color formats to 0.
    /// (Frame 0 reads nothing anyway: its `steady` params make every pixel fresh.)
    fn clear_textures(&self, encoder: &mut wgpu::CommandEncoder) {
        for (t, tex) in self.plan.textures.iter().zip(&self.textures) {
            let Some(tex) = tex else { continue };
            if !t.usage.contains(wgpu::TextureUsages::RENDER_ATTACHMENT) {
                continue;
            }
            if t.format.is_depth_stencil_format() {
                encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
                    label: Some("reproj clear"),
                    depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                        view: &tex.view,
                        depth_ops: Some(wgpu::Operations {
                            load: wgpu::LoadOp::Clear(self.plan.depth_clear),
                            store: wgpu::StoreOp::Store,
                        }),
                        stencil_ops: None,
                    }),
                    ..Default::default()
                });
            } else {
                encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
                    label: Some("reproj clear"),
                    color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                        view: &tex.view,
                        depth_slice: None,
                        resolve_target: None,
                        ops: wgpu::Operations {
                            load: wgpu::LoadOp::Clear(wgpu::Color::TRANSPARENT),
                            store: wgpu::StoreOp::Store,
                        },
                    })],
                    ..Default::default()
                });
            }
        }
    }
}

fn store(s: bool) -> wgpu::StoreOp {
    if s {
        wgpu::StoreOp::Store
    } else {
        wgpu::StoreOp::Discard
    }
}

fn check_size(size: [u32; 2]) -> Result<(), RuntimeError> {
    if size.contains(&0) {
        return Err(RuntimeError::usage(
            "size",
            format!("{}×{} has no pixel", size[0], size[1]),
        ));
    }
    Ok(())
}
