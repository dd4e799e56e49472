//! Phase 3 of a variant render: the frame loop (passes, readback, records).

use super::*;
impl Renderer {
    /// The frame loop: per frame the passes (timed, counted), then the error reduction, the
    /// sampled frames' pixels and the classification read back in batches into `report`.
    #[allow(clippy::too_many_arguments)]
    pub(super) fn variant_frames(
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
                &self.reduce_kernel,
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
                    output::write_errmap(dir, f, w, h, &l2::pixel_errors(pixels, refr))?;
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
    pub(super) fn encode_variant_passes(
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
            host_clears_depth,
            motion,
            ..
        } = gpu;
        let (vgroup, clear) = (*vgroup, *clear);
        let b = &binds[cur];
        let clear_payload = wgpu::Color::TRANSPARENT;
        let mut enc = self.device.create_command_encoder(&Default::default());
        if let Some(mg) = motion {
            self.encode_motion(&mut enc, mg, scene, vgroup);
        }
        if *host_clears_depth {
            // `--depth-load load`: the passes test against the engine's depth, which starts the
            // frame cleared; a replay draws nothing else into it.
            let _ = enc.begin_render_pass(&wgpu::RenderPassDescriptor {
                label: Some("host clears the depth"),
                color_attachments: &[],
                depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                    view: gpu.depth_at(cur),
                    depth_ops: Some(wgpu::Operations {
                        load: wgpu::LoadOp::Clear(1.0),
                        store: wgpu::StoreOp::Store,
                    }),
                    stencil_ops: None,
                }),
                ..Default::default()
            });
        }
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
