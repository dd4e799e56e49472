//! Phase 3 of a variant render: the frame loop (per frame: encode, submit; per batch: read back,
//! record).

use super::*;

/// What a variant render's frame loop reads: the render's inputs, its plan and its GPU objects.
pub(super) struct FrameLoop<'a> {
    pub(super) session: &'a Session,
    pub(super) variant: &'a VariantInput,
    pub(super) reference: &'a Reference,
    pub(super) opts: &'a RenderOptions,
    pub(super) progress: &'a dyn FrameProgress,
    pub(super) plan: &'a VariantPlan,
    pub(super) gpu: &'a VariantGpu,
}

/// The frame loop's queries and readback ([`Renderer::variant_readback`]).
struct VariantReadback<'a> {
    /// Frames per readback batch.
    slots: u32,
    /// One occlusion query (and timestamp pair) per pass.
    q: QueryKit,
    /// The error reduction against the reference (and the frames' pixels where they come
    /// back); none when timing only.
    errors: Option<FrameErrors<'a>>,
    /// The classification maps, where the classification entry is rendered.
    cls_rb: Option<Staging>,
}

impl VariantReadback<'_> {
    /// The buffers mapped once per batch.
    fn read_buffers(&self) -> Vec<&wgpu::Buffer> {
        let mut rb_bufs = self.q.read_buffers();
        if let Some(errors) = &self.errors {
            rb_bufs.extend(errors.read_buffers());
        }
        if let Some(c) = &self.cls_rb {
            rb_bufs.push(&c.buf);
        }
        rb_bufs
    }
}

impl Renderer {
    /// The frame loop: per frame the passes (timed, counted), then the error reduction, the
    /// sampled frames' pixels and the classification read back in batches into `report`.
    pub(super) fn variant_frames(
        &self,
        run: &FrameLoop<'_>,
        report: &mut RenderReport,
    ) -> Result<(), ReplayError> {
        let (frames, first) = (run.plan.frames, run.plan.first);
        let (reference, opts) = (run.reference, run.opts);
        let size = run.session.resolution;
        let rb = self.variant_readback(run)?;
        let rb_bufs = rb.read_buffers();
        let mut batch = FrameBatch::new("variant ", rb.slots, first + frames);
        // Frames read back for ꟻLIP and SSIM are scored as they come back, beside the loop at
        // the lowest CPU priority (`score.rs`).
        let mut scorer = Scorer::new(reference, size);
        scoring_pool().in_place_scope(|scope| -> Result<(), ReplayError> {
            for f in first..first + frames {
                let slot = batch.slot();
                let (render, readback) = self.encode_variant_frame(run, &rb, f, slot)?;
                if !batch.submit(self, render, readback, f)? {
                    continue;
                }
                // Read the batch back with one wait.
                batch.read_back(self, &rb_bufs, |slot, f, cpu_ms| {
                    let (record, sampled) = self.variant_frame_back(run, &rb, slot, f, cpu_ms)?;
                    if let Some(pixels) = sampled {
                        scorer.spawn(scope, f, pixels);
                    }
                    report.frames.push(record);
                    run.progress.frame(f - first + 1, frames);
                    Ok(())
                })?;
                // Swap happens through the parity of the next frame.
            }
            Ok(())
        })?;
        scorer.record(report, opts)
    }

    /// The queries, the error reduction (unless timing only) and the classification staging,
    /// with a slot per frame of a batch.
    fn variant_readback<'a>(
        &self,
        run: &FrameLoop<'a>,
    ) -> Result<VariantReadback<'a>, ReplayError> {
        let (opts, plan) = (run.opts, run.plan);
        let [w, h] = run.session.resolution;
        let slots = self.batch_len(plan.frames, Staging::slot_bytes(w, h, 16));
        let q = QueryKit::new(
            self,
            plan.runtime.pass_count() as u32,
            plan.render_pass_count,
            slots,
        );
        let errors = if opts.timing_only {
            None
        } else {
            Some(FrameErrors::new(
                self,
                self.kernels(),
                run.reference,
                plan.first + plan.frames,
                slots,
                (opts.png_dir.is_some(), opts.perceptual_stride),
            )?)
        };
        let cls_rb = plan
            .classify_stage
            .as_ref()
            .map(|_| Staging::new(self, "classify readback", w, h, 4, slots));
        Ok(VariantReadback {
            slots,
            q,
            errors,
            cls_rb,
        })
    }

    /// Frame `f`'s commands, into `slot`: its uniforms written, its passes (the render, timed),
    /// then the readback (and the untimed classification pass).
    fn encode_variant_frame(
        &self,
        run: &FrameLoop<'_>,
        rb: &VariantReadback<'_>,
        f: u32,
        slot: u32,
    ) -> Result<(wgpu::CommandEncoder, wgpu::CommandEncoder), ReplayError> {
        let gpu = run.gpu;
        self.write_frame_uniforms(run.session, &gpu.scene, f, &crate::jitter::Jitter::None);
        let mut render = self.device.create_command_encoder(&Default::default());
        self.encode_variant_passes_into(&mut render, gpu, run.variant, (f, run.plan.first), &rb.q)?;
        rb.q.resolve(&mut render, slot);
        let mut enc = self.device.create_command_encoder(&Default::default());
        if let Some(errors) = &rb.errors {
            errors.encode(self, &mut enc, &gpu.color, &gpu.color_view, f, slot)?;
        }
        if let Some(cls_rb) = &rb.cls_rb {
            let runtime = gpu
                .runtime
                .lock()
                .unwrap_or_else(std::sync::PoisonError::into_inner);
            runtime
                .record_classification(
                    &mut enc,
                    (&gpu.cls_view, &gpu.cls_depth_view),
                    &gpu.scene_groups(),
                    |pass, pipelines| gpu.draw_objects(pass, pipelines),
                )
                .map_err(|e| runtime_error(&run.variant.label, e))?;
            cls_rb.copy(&mut enc, &gpu.cls, slot);
        }
        Ok((render, enc))
    }

    /// Frame `f`, back in `slot` (`cpu_ms` its CPU time): its record, with its PNGs written, and
    /// its pixels where it is sampled for the perceptual metrics on the CPU (every frame that
    /// comes back, for PNGs, and the sampled ones where [`crate::PerceptualOn`] says the CPU).
    fn variant_frame_back(
        &self,
        run: &FrameLoop<'_>,
        rb: &VariantReadback<'_>,
        slot: u32,
        f: u32,
        cpu_ms: f64,
    ) -> Result<(FrameRecord, Option<Vec<f32>>), ReplayError> {
        let opts = run.opts;
        let (errs, pixels, scored) = match &rb.errors {
            Some(errors) => {
                let back = errors.read(slot, run.reference, f)?;
                (back.error, back.pixels, back.perceptual)
            }
            None => (Default::default(), None, None),
        };
        let cls_px = match &rb.cls_rb {
            Some(c) => Some(c.image(slot)?),
            None => None,
        };
        let (occ, render_pass_ms, span) = rb.q.read(slot)?;
        // Per pass only where each pass has its own render pass (`VariantInput::pass_times`).
        let pass_ms = if run.plan.render_pass_count as usize == run.plan.runtime.pass_count() {
            render_pass_ms
        } else {
            Vec::new()
        };
        let (hit_px, miss_px, refresh_px) = match &cls_px {
            Some(c) => {
                let (hi, mi, re) = classified(c);
                (Some(hi), Some(mi), Some(re))
            }
            None => (None, None, None),
        };
        let counts = counts_of(run.variant.manifest.strategy, &occ, hit_px);
        let hit_rate = match (hit_px, miss_px, refresh_px) {
            (Some(hi), Some(mi), Some(re)) if hi + mi + re > 0 => hi as f64 / (hi + mi + re) as f64,
            _ if counts.shaded > 0 => (counts.hits as f64 / counts.shaded as f64).min(1.0),
            _ => 0.0,
        };
        let frame_ms = span.unwrap_or(cpu_ms);
        let perceptual = opts
            .perceptual_stride
            .is_some_and(|k| f.is_multiple_of(k.max(1)));
        let sampled = pixels.as_ref().filter(|_| perceptual).cloned();
        if let (Some(dir), Some(pixels)) = (&opts.png_dir, &pixels) {
            let [w, h] = run.session.resolution;
            let refr = &run.reference.frames[f as usize];
            output::write_frame(dir, f, w, h, pixels)?;
            if opts.raw_frames {
                output::write_frame_raw(dir, f, pixels)?;
            }
            output::write_errmap(dir, f, w, h, &l2::pixel_errors(pixels, refr))?;
            if let Some(c) = &cls_px {
                output::write_hitmap(dir, f, w, h, c)?;
            }
        }
        let record = FrameRecord {
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
            flip: scored.map(|p| p.flip),
            ssim: scored.map(|p| p.ssim),
        };
        Ok((record, sampled))
    }

    /// Record frame `f`'s passes of a render whose first frame is `first` (the cache starts
    /// over there): the motion pass where there is one, the host's clears (where no pass clears
    /// the frame or the first pass loads the depth), then the variant's passes as the runtime
    /// records them, each pass counted by `q`'s occlusion queries and each render pass timed
    /// (render pass `r` writes timestamps `2r` and `2r + 1`), left unresolved.
    pub(in crate::render) fn encode_variant_passes_into(
        &self,
        enc: &mut wgpu::CommandEncoder,
        gpu: &VariantGpu,
        variant: &VariantInput,
        (f, first): (u32, u32),
        q: &QueryKit,
    ) -> Result<(), ReplayError> {
        if let Some(mg) = &gpu.motion {
            self.encode_motion(enc, mg, &gpu.scene, gpu.vgroup);
        }
        self.encode_host_clears(enc, gpu);
        let mut runtime = gpu
            .runtime
            .lock()
            .unwrap_or_else(std::sync::PoisonError::into_inner);
        let groups = gpu.scene_groups();
        runtime
            .record(
                &self.queue,
                enc,
                &reproj_runtime::FrameTargets {
                    color: &gpu.color_view,
                    depth: &gpu.depth_view,
                    clear_color: gpu.clear,
                },
                &reproj_runtime::FrameInputs {
                    delta_n: Some(variant.delta_n_at(f)),
                    restart: f == first,
                    bind_groups: &groups,
                    timestamps: q.timestamps(),
                    occlusion: Some(&q.occlusion),
                    clock: Some(f),
                    separate_passes: variant.pass_times,
                },
                |pass, pipelines| gpu.draw_objects(pass, pipelines),
            )
            .map_err(|e| runtime_error(&variant.label, e))
    }

    /// The clears an engine's frame starts with, where the variant's passes load instead: the
    /// depth (the first pass loads it) and the frame (no pass clears it).
    fn encode_host_clears(&self, enc: &mut wgpu::CommandEncoder, gpu: &VariantGpu) {
        if gpu.host_clears_depth {
            // `--depth-load load`: the passes test against the engine's depth, which starts the
            // frame cleared; a replay draws nothing else into it.
            let _ = enc.begin_render_pass(&wgpu::RenderPassDescriptor {
                label: Some("host clears the depth"),
                color_attachments: &[],
                depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                    view: &gpu.depth_view,
                    depth_ops: Some(wgpu::Operations {
                        load: wgpu::LoadOp::Clear(1.0),
                        store: wgpu::StoreOp::Store,
                    }),
                    stencil_ops: None,
                }),
                ..Default::default()
            });
        }
        if gpu.host_clears_frame {
            // `--frame-load load`: the passes keep what the engine drew; here that is the
            // background, as the original shader's frame starts.
            let _ = enc.begin_render_pass(&wgpu::RenderPassDescriptor {
                label: Some("host clears the frame"),
                color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                    view: &gpu.color_view,
                    depth_slice: None,
                    resolve_target: None,
                    ops: wgpu::Operations {
                        load: wgpu::LoadOp::Clear(gpu.clear),
                        store: wgpu::StoreOp::Store,
                    },
                })],
                ..Default::default()
            });
        }
    }
}

/// Hit, miss and refresh pixels of a classification map (rgba8: green hit, else red miss, else
/// blue refresh).
fn classified(map: &[u8]) -> (u64, u64, u64) {
    let (mut hi, mut mi, mut re) = (0u64, 0u64, 0u64);
    for p in map.chunks_exact(4) {
        if p[1] > 127 {
            hi += 1;
        } else if p[0] > 127 {
            mi += 1;
        } else if p[2] > 127 {
            re += 1;
        }
    }
    (hi, mi, re)
}
