//! The variant loop: render a cached variant of any strategy and compare it with the reference.

use std::collections::{BTreeMap, BTreeSet};
use std::path::Path;

use reproj_front::Shader;
use reproj_instance::CacheFormat;

use crate::ReplayError;
use crate::metrics::{self, FrameRecord, RenderReport};
use crate::output;
use crate::perceptual;
use crate::reduce::{FrameErrors, PixelsBack};
use crate::reflect::{self, Interface};
use crate::session::Session;
use crate::vertex;
use rayon::prelude::*;

use reproj_instance::contract;

use super::*;

/// Hits, misses (recomputes, refreshes included) and shaded pixels of one frame.
pub(super) struct Counts {
    pub(super) hits: u64,
    pub(super) misses: u64,
    pub(super) shaded: u64,
}

/// The frame's counts from its occlusion queries (one per pass, in pass order) and, for the
/// fused strategy whose one pass cannot count hits apart, the classification map.
pub(super) fn counts_of(
    strategy: reproj_instance::Strategy,
    occ: &[u64],
    hit_px: Option<u64>,
) -> Counts {
    use reproj_instance::Strategy;
    let at = |i: usize| occ.get(i).copied().unwrap_or(0);
    match strategy {
        Strategy::ThreePass => Counts {
            hits: at(0),
            misses: at(1),
            shaded: at(2),
        },
        Strategy::TwoPass => Counts {
            hits: at(0),
            misses: at(1),
            shaded: at(0) + at(1),
        },
        Strategy::Fused => {
            let hits = hit_px.unwrap_or(0).min(at(0));
            Counts {
                hits,
                misses: at(0) - hits,
                shaded: at(0),
            }
        }
    }
}

impl Renderer {
    /// Render a cached variant of any strategy over the session (see `docs/PASSES.md`) and compare
    /// each frame with `reference` (from [`Renderer::render_original`] on the same session).
    ///
    /// Per frame, the manifest's passes in order, each with its color targets (frame color, current
    /// payload, current depth copy: cleared or loaded as listed) and depth state; then the current
    /// payload and depth copy become the previous ones. (A variant written before the depth copy
    /// reads the previous frame's depth buffer instead, which then alternates too.) Frame 0 runs with
    /// Δn = 1; `clock` is the frame index.
    pub fn render_variant(
        &self,
        shader: &Shader,
        session: &Session,
        variant: &VariantInput,
        reference: &Reference,
        opts: &RenderOptions,
    ) -> Result<RenderReport, ReplayError> {
        self.render_variant_with(shader, session, variant, reference, opts, &())
    }

    /// [`Renderer::render_variant`], telling `progress` as frames come back. In phases: the plan
    /// (checks, the passes' stages; nothing allocated), the GPU objects, the empty cache, the
    /// frame loop, the sampled frames' perceptual metrics.
    pub fn render_variant_with(
        &self,
        shader: &Shader,
        session: &Session,
        variant: &VariantInput,
        reference: &Reference,
        opts: &RenderOptions,
        progress: &dyn FrameProgress,
    ) -> Result<RenderReport, ReplayError> {
        let plan = self.plan_variant(shader, session, variant, reference, opts)?;
        let gpu = self.variant_gpu(session, variant, &plan)?;
        self.clear_variant_cache(&gpu)?;
        let m = &variant.manifest;
        let mut report = self.new_report("variant", shader, &m.entry, session);
        report.node = Some(m.node.id.clone());
        report.delta_n = Some(variant.delta_n);
        report.block = Some(variant.block);
        report.depth_epsilon = Some(variant.depth_epsilon);
        self.variant_frames(
            session,
            variant,
            reference,
            opts,
            progress,
            &plan,
            &gpu,
            &mut report,
        )?;
        report.summarize();
        Ok(report)
    }

    /// Check a variant render against its reference and the adapter, and make its passes'
    /// stages (their interfaces with the shader's own names): everything before a GPU object.
    fn plan_variant(
        &self,
        shader: &Shader,
        session: &Session,
        variant: &VariantInput,
        reference: &Reference,
        opts: &RenderOptions,
    ) -> Result<VariantPlan, ReplayError> {
        session.validate()?;
        let m = &variant.manifest;
        let [w, h] = session.resolution;
        let frames = Self::frame_count(session, opts);
        let first = Self::first_frame(session, opts)?;
        if reference.width != w
            || reference.height != h
            || (reference.frames.len() as u32) < first + frames
        {
            return Err(ReplayError::ReferenceMismatch {
                reference: format!(
                    "{} frames, {}×{}",
                    reference.frames.len(),
                    reference.width,
                    reference.height
                ),
                session: format!("{} frames, {w}×{h}", first + frames),
            });
        }
        if variant.delta_n == 0
            || variant.block == 0
            || variant.delta_n_per_frame.iter().flatten().any(|&d| d == 0)
        {
            return Err(ReplayError::Variant {
                message: "Δn and k must be at least 1".into(),
            });
        }
        let specs = pass_specs(m)?;
        if variant.sources.len() != m.passes.len() {
            return Err(ReplayError::Variant {
                message: format!(
                    "the manifest lists {} passes and {} modules were given",
                    m.passes.len(),
                    variant.sources.len()
                ),
            });
        }
        let mut stages = Vec::new();
        for (p, src) in m.passes.iter().zip(&variant.sources) {
            stages.push(self.make_stage(Path::new(&p.file), src.clone(), &p.entry)?);
        }
        // naga's WGSL writer renames identifiers that end in a digit (`sh0` becomes `sh0_`): take
        // the shader's own names back from the original module, by group/binding and field order.
        let original = reflect::reflect(
            &shader.module,
            &shader.info,
            shader
                .fragment_entry(Some(&m.entry))
                .map_err(|e| ReplayError::Variant {
                    message: e.to_string(),
                })?,
        )?;
        for st in &mut stages {
            restore_names(&mut st.iface, &original);
        }
        // The fused pass cannot count its hits with an occlusion query: classify every frame.
        let classify_stage = if opts.classify || m.strategy == reproj_instance::Strategy::Fused {
            let s1 = &stages[0].shader;
            match reflect::fragment_entry_index(&s1.module, CLASSIFY_ENTRY) {
                Some(ci) => Some(reflect::reflect(&s1.module, &s1.info, ci)?),
                None => None,
            }
        } else {
            None
        };
        if !m.cache_format.is_half()
            && m.reconstruct.filters()
            && !self
                .device
                .features()
                .contains(wgpu::Features::FLOAT32_FILTERABLE)
        {
            return Err(ReplayError::Unsupported {
                what: format!(
                    "{} has no float32-filterable feature, needed to filter a {} cache; use a 16-bit cache format or nearest reconstruction",
                    self.adapter_info.name,
                    m.cache_format.name()
                ),
            });
        }
        Ok(VariantPlan {
            frames,
            first,
            specs,
            stages,
            classify_stage,
        })
    }

    /// The GPU objects of a variant render: the scene, the stages' modules, the payload and depth
    /// copy ping-pong, the frame and classification targets, the samplers, each parity's bind
    /// groups and the passes' pipelines.
    fn variant_gpu(
        &self,
        session: &Session,
        variant: &VariantInput,
        plan: &VariantPlan,
    ) -> Result<VariantGpu, ReplayError> {
        let m = &variant.manifest;
        let [w, h] = session.resolution;
        let (specs, stages, classify_stage) = (&plan.specs, &plan.stages, &plan.classify_stage);
        let mut used: BTreeSet<u32> = [m.group].into_iter().collect();
        for s in stages {
            used.extend(s.iface.groups());
        }
        if let Some(c) = &classify_stage {
            used.extend(c.groups());
        }
        let vgroup = free_group(&used)?;
        let mut input_sets: Vec<&[reflect::FragInput]> =
            stages.iter().map(|s| s.iface.inputs.as_slice()).collect();
        if let Some(c) = &classify_stage {
            input_sets.push(&c.inputs);
        }
        let inputs = vertex::merge_inputs(&input_sets)?;
        let mut ifaces: Vec<&Interface> = stages.iter().map(|s| &s.iface).collect();
        if let Some(c) = &classify_stage {
            ifaces.push(c);
        }
        let scene = self.build_scene(session, &ifaces, Some(m.group))?;
        let vs_src = vertex::vertex_wgsl(
            vgroup,
            &inputs,
            &session.inputs,
            Some(m.vertex.prev_clip_location),
        )?;
        let vs = self.shader_module("replay vertex stage (variant)", &vs_src)?;
        let fsm: Vec<wgpu::ShaderModule> = stages
            .iter()
            .map(|s| self.shader_module(&s.shader.path.display().to_string(), &s.shader.source))
            .collect::<Result<_, _>>()?;

        let cache_format = match m.cache_format {
            CacheFormat::Rgba32float => wgpu::TextureFormat::Rgba32Float,
            CacheFormat::Rg32float => wgpu::TextureFormat::Rg32Float,
            CacheFormat::R32float => wgpu::TextureFormat::R32Float,
            CacheFormat::Rgba16float => wgpu::TextureFormat::Rgba16Float,
            CacheFormat::Rg16float => wgpu::TextureFormat::Rg16Float,
            CacheFormat::R16float => wgpu::TextureFormat::R16Float,
        };
        let payload = [
            self.target("payload A", w, h, cache_format, true),
            self.target("payload B", w, h, cache_format, true),
        ];
        let depth_copy = [
            self.target("depth copy A", w, h, DEPTH_COPY_FORMAT, true),
            self.target("depth copy B", w, h, DEPTH_COPY_FORMAT, true),
        ];
        // The lookup reads the depth copy; only a variant written before it (no depth copy target)
        // reads the previous depth buffer, which must then alternate like the payload.
        let legacy_depth = !specs.iter().any(|s| {
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
        // The depth buffer of the frame of parity `p`.
        let depth_at = |p: usize| &depth_v[p % depth_v.len()];
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
        // Bindings for each parity (cur = parity, prev = 1 − parity).
        let mut binds: Vec<(Vec<Bindings>, Bindings)> = Vec::new();
        for parity in 0..2usize {
            let added = AddedResources {
                params: &params,
                point_sampler: &point_sampler,
                linear_sampler: &linear_sampler,
                payload_half: m.cache_format.is_half(),
                prev_payload: &payload_v[1 - parity],
                prev_depth_copy: &depth_copy_v[1 - parity],
                prev_depth_buffer: legacy_depth.then(|| depth_at(1 - parity)),
                cur_payload: &payload_v[parity],
            };
            let mut per_pass = Vec::new();
            for (st, spec) in stages.iter().zip(specs) {
                per_pass.push(self.bindings(
                    &spec.label,
                    &st.iface,
                    &scene,
                    Some(m.group),
                    Some(&added),
                )?);
            }
            let bc = match &classify_stage {
                Some(c) => self.bindings(CLASSIFY_ENTRY, c, &scene, Some(m.group), Some(&added))?,
                None => Bindings {
                    layouts: BTreeMap::new(),
                    groups: BTreeMap::new(),
                    layout_keys: BTreeMap::new(),
                },
            };
            binds.push((per_pass, bc));
        }
        use wgpu::CompareFunction as Cf;
        let mut pipes = Vec::new();
        for (i, spec) in specs.iter().enumerate() {
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
                &spec.label,
                [&vs_src, &stages[i].shader.source],
                &vs,
                &fsm[i],
                &stages[i].iface.entry,
                &binds[0].0[i],
                &scene,
                vgroup,
                &formats,
                spec.compare,
                spec.depth_write,
            )?);
        }
        let pc = match &classify_stage {
            Some(_) => Some(self.pipeline(
                CLASSIFY_ENTRY,
                [&vs_src, &stages[0].shader.source],
                &vs,
                &fsm[0],
                CLASSIFY_ENTRY,
                &binds[0].1,
                &scene,
                vgroup,
                &[Some(CLASSIFY_FORMAT)],
                Cf::Less,
                true,
            )?),
            None => None,
        };

        let bg = session.background;
        let clear = wgpu::Color {
            r: bg[0] as f64,
            g: bg[1] as f64,
            b: bg[2] as f64,
            a: bg[3] as f64,
        };

        let host_clears_frame = !specs.iter().any(|s| {
            s.colors
                .iter()
                .flatten()
                .any(|(t, load)| *t == Attachment::Frame && !load)
        });
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
            host_clears_frame,
        })
    }

    /// Clear both parities' payload, depth copy and depth: the "previous" cache before the first
    /// frame (payload 0, depth 1).
    fn clear_variant_cache(&self, gpu: &VariantGpu) -> Result<(), ReplayError> {
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
                        clear_to(&payload_v[i], wgpu::Color::TRANSPARENT),
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

    /// The frame loop: per frame the passes (timed, counted), then the error reduction, the
    /// sampled frames' pixels and the classification read back in batches into `report`.
    #[allow(clippy::too_many_arguments)]
    fn variant_frames(
        &self,
        session: &Session,
        variant: &VariantInput,
        reference: &Reference,
        opts: &RenderOptions,
        progress: &dyn FrameProgress,
        plan: &VariantPlan,
        gpu: &VariantGpu,
        report: &mut RenderReport,
    ) -> Result<(), ReplayError> {
        let m = &variant.manifest;
        let [w, h] = session.resolution;
        let (frames, first, specs) = (plan.frames, plan.first, &plan.specs);
        let VariantGpu {
            scene,
            vgroup,
            color,
            color_view,
            cls,
            cls_view,
            cls_depth_view,
            params,
            binds,
            pc,
            ..
        } = gpu;
        let vgroup = *vgroup;
        let slots = self.batch_len(frames, Staging::slot_bytes(w, h, 16));
        let q = QueryKit::new(self, specs.len() as u32, slots);
        let back = match (&opts.png_dir, opts.perceptual_stride) {
            (Some(_), _) => PixelsBack::All,
            (None, Some(k)) => PixelsBack::Every(k.max(1)),
            (None, None) => PixelsBack::None,
        };
        let perceptual = |f: u32| {
            opts.perceptual_stride
                .is_some_and(|k| f.is_multiple_of(k.max(1)))
        };
        let errors = if opts.timing_only {
            None
        } else {
            Some(FrameErrors::new(
                self,
                reference,
                first + frames,
                slots,
                back,
            )?)
        };
        let cls_rb = pc
            .as_ref()
            .map(|_| Staging::new(self, "classify readback", w, h, 4, slots));
        let mut rb_bufs = q.read_buffers();
        if let Some(errors) = &errors {
            rb_bufs.extend(errors.read_buffers());
        }
        if let Some(c) = &cls_rb {
            rb_bufs.push(&c.buf);
        }
        let mut batch = FrameBatch::new("variant ", slots, first + frames);
        // Frames read back for ꟻLIP and SSIM, scored between batches once there is one per core.
        // The metrics are the costliest CPU work of a replay (ꟻLIP: about 26 ms per 256×256
        // frame on one core): they run on every core, but never while a timed frame is in flight
        // (on a CPU adapter they would otherwise slow the frames being measured).
        let mut to_score: Vec<(u32, Vec<f32>)> = Vec::new();
        for f in first..first + frames {
            let slot = batch.slot();
            let cur = (f % 2) as usize;
            let b = &binds[cur];
            self.write_frame_uniforms(session, scene, f);
            let mut p = contract::ReprojParams::for_frame(
                f,
                variant.delta_n_at(f),
                variant.block,
                variant.depth_epsilon,
            );
            if f == first {
                // The cache starts empty: the first frame refreshes everything.
                p.delta_n = 1;
            }
            self.queue.write_buffer(params, 0, bytemuck::bytes_of(&p));

            let enc = self.encode_variant_passes(gpu, specs, cur, &q, slot);

            // Readback (and the untimed classification pass).
            let render = enc;
            let mut enc = self.device.create_command_encoder(&Default::default());
            if let Some(errors) = &errors {
                errors.encode(self, &mut enc, color, color_view, f, slot)?;
            }
            if let (Some(pc), Some(cls_rb)) = (&pc, &cls_rb) {
                {
                    let mut pass = enc.begin_render_pass(&wgpu::RenderPassDescriptor {
                        label: Some(CLASSIFY_ENTRY),
                        color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                            view: cls_view,
                            depth_slice: None,
                            resolve_target: None,
                            ops: wgpu::Operations {
                                load: wgpu::LoadOp::Clear(wgpu::Color::TRANSPARENT),
                                store: wgpu::StoreOp::Store,
                            },
                        })],
                        depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                            view: cls_depth_view,
                            depth_ops: Some(wgpu::Operations {
                                load: wgpu::LoadOp::Clear(1.0),
                                store: wgpu::StoreOp::Store,
                            }),
                            stencil_ops: None,
                        }),
                        ..Default::default()
                    });
                    self.draw(&mut pass, pc, &b.1, scene, vgroup);
                }
                cls_rb.copy(&mut enc, cls, slot);
            }
            if !batch.submit(self, render, enc, f)? {
                continue;
            }

            // Read the batch back with one wait.
            batch.read_back(self, &rb_bufs, |slot, f, cpu_ms| {
                let (errs, pixels) = match &errors {
                    Some(errors) => errors.read(slot, reference, f)?,
                    None => (Default::default(), None),
                };
                let cls_px = match &cls_rb {
                    Some(c) => Some(c.image(slot)?),
                    None => None,
                };
                let (occ, pass_ms, span) = q.read(slot)?;

                let (mut hit_px, mut miss_px, mut refresh_px) = (None, None, None);
                if let Some(c) = &cls_px {
                    let (mut hi, mut mi, mut re) = (0u64, 0u64, 0u64);
                    for p in c.chunks_exact(4) {
                        if p[1] > 127 {
                            hi += 1;
                        } else if p[0] > 127 {
                            mi += 1;
                        } else if p[2] > 127 {
                            re += 1;
                        }
                    }
                    hit_px = Some(hi);
                    miss_px = Some(mi);
                    refresh_px = Some(re);
                }
                let counts = counts_of(m.strategy, &occ, hit_px);
                let hit_rate = match (hit_px, miss_px, refresh_px) {
                    (Some(hi), Some(mi), Some(re)) if hi + mi + re > 0 => {
                        hi as f64 / (hi + mi + re) as f64
                    }
                    _ if counts.shaded > 0 => (counts.hits as f64 / counts.shaded as f64).min(1.0),
                    _ => 0.0,
                };
                let frame_ms = span.unwrap_or(cpu_ms);
                if let Some(pixels) = pixels.as_ref().filter(|_| perceptual(f)) {
                    to_score.push((f, pixels.clone()));
                }
                if let (Some(dir), Some(pixels)) = (&opts.png_dir, &pixels) {
                    let refr = &reference.frames[f as usize];
                    output::write_frame(dir, f, w, h, pixels)?;
                    if opts.raw_frames {
                        output::write_frame_raw(dir, f, pixels)?;
                    }
                    output::write_errmap(dir, f, w, h, &metrics::pixel_errors(pixels, refr))?;
                    if let Some(c) = &cls_px {
                        output::write_hitmap(dir, f, w, h, c)?;
                    }
                }
                report.frames.push(FrameRecord {
                    frame: f,
                    frame_ms,
                    cpu_ms,
                    pass_ms,
                    shaded: counts.shaded,
                    hits: counts.hits,
                    recomputes: counts.misses,
                    hit_px,
                    miss_px,
                    refresh_px,
                    hit_rate,
                    error: errs.error(),
                    mse: errs.mse(),
                    covered: errs.covered,
                    psnr: errs.psnr(),
                    max_abs_diff: errs.max_abs_diff,
                    nonfinite: errs.nonfinite,
                    nonfinite_reference: errs.nonfinite_reference,
                    flip: None,
                    ssim: None,
                });
                progress.frame(f - first + 1, frames);
                Ok(())
            })?;
            // Score once there is a frame for every core (at 1080p a batch holds one frame and
            // one ꟻLIP takes most of a second), and whatever is left at the end.
            if to_score.len() >= rayon::current_num_threads() {
                score_perceptual(&mut to_score, report, reference, opts, [w, h])?;
            }
            // Swap happens through the parity of the next frame.
        }
        score_perceptual(&mut to_score, report, reference, opts, [w, h])
    }

    /// Record frame parity `cur`'s passes (the host's clear of the frame first where no pass
    /// clears it), each timed and counted by `q` into `slot`.
    fn encode_variant_passes(
        &self,
        gpu: &VariantGpu,
        specs: &[PassSpec],
        cur: usize,
        q: &QueryKit,
        slot: u32,
    ) -> wgpu::CommandEncoder {
        let VariantGpu {
            scene,
            vgroup,
            payload_v,
            depth_copy_v,
            color_view,
            binds,
            pipes,
            clear,
            host_clears_frame,
            ..
        } = gpu;
        let (vgroup, clear) = (*vgroup, *clear);
        let b = &binds[cur];
        let clear_payload = wgpu::Color::TRANSPARENT;
        let mut enc = self.device.create_command_encoder(&Default::default());
        if *host_clears_frame {
            // `--frame-load load`: the passes keep what the engine drew; here that is the
            // background, as the original shader's frame starts.
            let _ = enc.begin_render_pass(&wgpu::RenderPassDescriptor {
                label: Some("host clears the frame"),
                color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                    view: color_view,
                    depth_slice: None,
                    resolve_target: None,
                    ops: wgpu::Operations {
                        load: wgpu::LoadOp::Clear(clear),
                        store: wgpu::StoreOp::Store,
                    },
                })],
                ..Default::default()
            });
        }
        for (i, spec) in specs.iter().enumerate() {
            let colors: Vec<Option<wgpu::RenderPassColorAttachment<'_>>> = spec
                .colors
                .iter()
                .map(|c| {
                    c.map(|(t, load)| {
                        let (view, clear_to) = match t {
                            Attachment::Frame => (color_view, clear),
                            Attachment::Cache => (&payload_v[cur], clear_payload),
                            Attachment::DepthCopy => (&depth_copy_v[cur], DEPTH_COPY_CLEAR),
                        };
                        wgpu::RenderPassColorAttachment {
                            view,
                            depth_slice: None,
                            resolve_target: None,
                            ops: wgpu::Operations {
                                load: if load {
                                    wgpu::LoadOp::Load
                                } else {
                                    wgpu::LoadOp::Clear(clear_to)
                                },
                                store: wgpu::StoreOp::Store,
                            },
                        }
                    })
                })
                .collect();
            let mut pass = enc.begin_render_pass(&wgpu::RenderPassDescriptor {
                label: Some(&spec.label),
                color_attachments: &colors,
                depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                    view: gpu.depth_at(cur),
                    depth_ops: Some(wgpu::Operations {
                        load: if spec.depth_load {
                            wgpu::LoadOp::Load
                        } else {
                            wgpu::LoadOp::Clear(1.0)
                        },
                        store: wgpu::StoreOp::Store,
                    }),
                    stencil_ops: None,
                }),
                timestamp_writes: q.writes(i as u32),
                occlusion_query_set: Some(&q.occlusion),
                multiview_mask: None,
            });
            pass.begin_occlusion_query(i as u32);
            self.draw(&mut pass, &pipes[i], &b.0[i], scene, vgroup);
            pass.end_occlusion_query();
        }
        q.resolve(&mut enc, slot);
        enc
    }
}

/// What a variant render needs before any GPU object ([`Renderer::plan_variant`]).
struct VariantPlan {
    frames: u32,
    first: u32,
    /// Each pass's targets and depth state, in the manifest's order.
    specs: Vec<PassSpec>,
    /// Each pass's module and interface, in the same order.
    stages: Vec<Stage>,
    /// The first pass's classification entry point, when it is rendered each frame.
    classify_stage: Option<Interface>,
}

/// The GPU objects of a variant render ([`Renderer::variant_gpu`]).
struct VariantGpu {
    scene: Scene,
    /// The bind group the replay's vertex stage uses (free in every stage).
    vgroup: u32,
    /// The payload and the depth copy of each parity.
    payload_v: Vec<wgpu::TextureView>,
    depth_copy_v: Vec<wgpu::TextureView>,
    /// One depth buffer, or two that alternate for a variant written before the depth copy.
    depth_v: Vec<wgpu::TextureView>,
    color: wgpu::Texture,
    color_view: wgpu::TextureView,
    cls: wgpu::Texture,
    cls_view: wgpu::TextureView,
    cls_depth_view: wgpu::TextureView,
    params: wgpu::Buffer,
    /// Per parity: each pass's bindings and the classification entry's.
    binds: Vec<(Vec<Bindings>, Bindings)>,
    pipes: Vec<Pipe>,
    /// The classification pipeline, when it is rendered.
    pc: Option<Pipe>,
    /// The session's background.
    clear: wgpu::Color,
    /// No pass clears the frame (`--frame-load load`): the host clears it to the background.
    host_clears_frame: bool,
}

impl VariantGpu {
    /// The depth buffer of the frame of parity `p`.
    fn depth_at(&self, p: usize) -> &wgpu::TextureView {
        &self.depth_v[p % self.depth_v.len()]
    }
}

/// ꟻLIP and SSIM of the frames in `to_score` (drained), in parallel, into their records of
/// `report`, and their ꟻLIP maps written where frames are.
pub(super) fn score_perceptual(
    to_score: &mut Vec<(u32, Vec<f32>)>,
    report: &mut RenderReport,
    reference: &Reference,
    opts: &RenderOptions,
    [w, h]: [u32; 2],
) -> Result<(), ReplayError> {
    let scored: Vec<_> = to_score
        .par_drain(..)
        .map(|(f, pixels)| {
            let fi = f as usize;
            let (e, map) = perceptual::compare_perceptual(
                &pixels,
                &reference.frames[fi],
                &reference.depth[fi],
                w,
                h,
            );
            (f, e, map)
        })
        .collect();
    for (f, e, map) in scored {
        if let Some(r) = report.frames.iter_mut().rev().find(|r| r.frame == f) {
            (r.flip, r.ssim) = (Some(e.flip), Some(e.ssim));
        }
        if let Some(dir) = &opts.png_dir {
            output::write_flipmap(dir, f, w, h, &map)?;
        }
    }
    Ok(())
}
