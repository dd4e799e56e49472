//! The plain loop behind the reference renders: one pass of the original per frame, its
//! targets and readback, and what comes back (the frames kept, or their errors against a
//! reference, scored on the GPU).

use std::collections::BTreeSet;

use reproj_front::Shader;

use crate::error::ReplayError;
use crate::jitter::Jitter;
use crate::reduce::{FrameErrors, GpuReference, Keeper};
use crate::vertex;
use reproj_metrics::l2;
use reproj_metrics::output;
use reproj_metrics::{FrameRecord, RenderReport};
use reproj_scene::reflect::{self, Interface};
use reproj_scene::session::Session;

use crate::render::*;

impl Renderer {
    /// The loop of [`Renderer::render_original_with`] and [`Renderer::render_scored`]: one pass
    /// of `shader` per frame; what comes back is `keep`'s. With [`Keep::Frames`], the frames,
    /// their depth and the GPU copy of both. In phases: checks, the pass
    /// ([`Renderer::plain_pass`]), its targets and readback ([`Renderer::plain_targets`]), the
    /// frame loop ([`Renderer::plain_frames`]; a scored render's error reduced on the GPU, its
    /// sampled frames' perceptual metrics computed where [`crate::PerceptualOn`] says: on the
    /// device, or on the CPU beside the loop), then their records.
    pub(super) fn render_plain(
        &self,
        shader: &Shader,
        entry_index: usize,
        session: &Session,
        opts: &RenderOptions,
        progress: &dyn FrameProgress,
        Plain { keep, jitter }: Plain<'_>,
    ) -> Result<(RenderReport, Option<KeptFrames>), ReplayError> {
        session.validate()?;
        let iface = reflect::reflect(&shader.module, &shader.info, entry_index)?;
        let frames = Self::frame_count(session, opts);
        let keeps = matches!(keep, Keep::Frames) && !opts.timing_only;
        self.check_size(session, frames, keeps)?;
        let first = Self::first_frame(session, opts)?;
        let pass = self.plain_pass(shader, iface, session, None)?;
        let targets = self.plain_targets(session, opts, keep, keeps, first, frames)?;
        let run = PlainRun {
            jitter,
            session,
            opts,
            first,
            frames,
            pass,
            targets,
        };
        let mut out = PlainOut {
            gpu: GpuReference::new(self),
            report: self.new_report("original", shader, &run.pass.iface.entry, session),
            to_score: Vec::new(),
            frames: Vec::with_capacity(frames as usize),
            depth: Vec::with_capacity(frames as usize),
        };
        if let Some(scorer) = self.plain_frames(&run, progress, &mut out)? {
            scorer.record(&mut out.report, opts)?;
        }
        out.report.summarize();
        let kept = matches!(keep, Keep::Frames).then_some((out.frames, out.depth, out.gpu));
        Ok((out.report, kept))
    }

    /// The shader's pass: the scene, the vertex and fragment stages, the bindings and the
    /// pipeline, the vertex transforms in the first bind group `iface` leaves free; with
    /// `prev_clip`, the vertex stage also writes the previous clip position as that output (for a
    /// motion pass).
    pub(in crate::render) fn plain_pass(
        &self,
        shader: &Shader,
        iface: Interface,
        session: &Session,
        prev_clip: Option<reflect::FragInput>,
    ) -> Result<PlainPass, ReplayError> {
        let used: BTreeSet<u32> = iface.groups().into_iter().collect();
        let vgroup = free_group(&used, self.device.limits().max_bind_groups)?;
        let scene = self.build_scene(session, &[&iface], None)?;
        let mut inputs = iface.inputs.clone();
        let prev_clip = prev_clip.map(|input| {
            let location = input.location;
            inputs.push(input);
            location
        });
        let vs_src = vertex::vertex_wgsl(vgroup, &inputs, &session.inputs, prev_clip)?;
        let vs = self.shader_module("replay vertex stage", &vs_src)?;
        let fs = self.shader_module(&shader.path.display().to_string(), &shader.source)?;
        let bindings = self.bindings("original", &iface, &scene)?;
        let pipe = self.pipeline(
            &PipelineSpec {
                label: "original",
                sources: [&vs_src, &shader.source],
                vs: &vs,
                fs: &fs,
                entry: &iface.entry,
                formats: &[Some(FRAME_FORMAT)],
                compare: wgpu::CompareFunction::Less,
                depth_write: true,
            },
            &bindings,
            &scene,
            vgroup,
        )?;
        Ok(PlainPass {
            iface,
            scene,
            vgroup,
            bindings,
            pipe,
            vs,
            vs_src,
        })
    }

    /// The frame's targets, the queries, and what comes back: with `keeps`, the frames and
    /// their depth (staged, and kept on the GPU); scored against a reference, its error
    /// reduction (and the sampled frames' pixels).
    fn plain_targets<'r>(
        &self,
        session: &Session,
        opts: &RenderOptions,
        keep: Keep<'r>,
        keeps: bool,
        first: u32,
        frames: u32,
    ) -> Result<PlainTargets<'r>, ReplayError> {
        let [w, h] = session.resolution;
        let scoring = match keep {
            Keep::ScoreAgainst(_) => true,
            Keep::Frames => false,
        };
        // The GPU reduction samples the frame: a scored render's target must be bindable.
        let color = self.target("frame color", w, h, FRAME_FORMAT, scoring);
        let color_view = color.create_view(&Default::default());
        let depth = self.target("depth", w, h, DEPTH_FORMAT, false);
        let depth_view = depth.create_view(&Default::default());
        let slots = self.batch_len(frames, Staging::slot_bytes(w, h, 16));
        let q = QueryKit::new(self, 1, 1, slots);
        let kept = keeps.then(|| {
            (
                Staging::new(self, "frame readback", w, h, 16, slots),
                Staging::new(self, "depth readback", w, h, 4, slots),
                Keeper::new(self, w, h),
            )
        });
        let errors = match keep {
            Keep::ScoreAgainst(reference) => Some((
                reference,
                FrameErrors::new(
                    self,
                    self.kernels(),
                    reference,
                    first + frames,
                    slots,
                    (false, opts.perceptual_stride),
                )?,
            )),
            Keep::Frames => None,
        };
        let clear = background_color(session);
        Ok(PlainTargets {
            color,
            color_view,
            depth,
            depth_view,
            slots,
            q,
            kept,
            errors,
            clear,
        })
    }

    /// The frame loop: each frame encoded and submitted into its slot of the batch, and the
    /// batch read back with one wait when it is full.
    fn plain_frames<'r>(
        &self,
        run: &PlainRun<'r>,
        progress: &dyn FrameProgress,
        out: &mut PlainOut,
    ) -> Result<Option<Scorer<'r>>, ReplayError> {
        let t = &run.targets;
        let mut rb_bufs = t.q.read_buffers();
        if let Some((frame_rb, depth_rb, _)) = &t.kept {
            rb_bufs.push(&frame_rb.buf);
            rb_bufs.push(&depth_rb.buf);
        }
        if let Some((_, e)) = &t.errors {
            rb_bufs.extend(e.read_buffers());
        }
        let end = run.first + run.frames;
        let mut batch = FrameBatch::new("", t.slots, end);
        // Sampled frames scored on the CPU are scored beside the loop (`score.rs`).
        let mut scorer = t
            .errors
            .as_ref()
            .map(|(reference, _)| Scorer::new(reference, run.session.resolution));
        scoring_pool().in_place_scope(|scope| -> Result<(), ReplayError> {
            for f in run.first..end {
                let slot = batch.slot();
                let (enc, rb) = self.encode_plain_frame(run, f, slot, &mut out.gpu)?;
                if !batch.submit(self, enc, rb, f)? {
                    continue;
                }
                // Read the batch back with one wait.
                batch.read_back(self, &rb_bufs, |slot, f, cpu_ms| {
                    self.plain_frame_back(run, slot, f, cpu_ms, out)?;
                    progress.frame(f - run.first + 1, run.frames);
                    Ok(())
                })?;
                if let Some(scorer) = &mut scorer {
                    for (f, pixels) in out.to_score.drain(..) {
                        scorer.spawn(scope, f, pixels);
                    }
                }
            }
            Ok(())
        })?;
        Ok(scorer)
    }

    /// Frame `f`'s commands: its uniforms written, then its pass (timed and counted into
    /// `slot`); and the readback: the frame kept (into `gpu`) and staged, or its error reduced.
    fn encode_plain_frame(
        &self,
        run: &PlainRun<'_>,
        f: u32,
        slot: u32,
        gpu: &mut GpuReference,
    ) -> Result<(wgpu::CommandEncoder, wgpu::CommandEncoder), ReplayError> {
        let (p, t) = (&run.pass, &run.targets);
        self.write_frame_uniforms(run.session, &p.scene, f, &run.jitter);
        let mut enc = self.device.create_command_encoder(&Default::default());
        {
            let mut pass = enc.begin_render_pass(&wgpu::RenderPassDescriptor {
                label: Some("original"),
                color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                    view: &t.color_view,
                    depth_slice: None,
                    resolve_target: None,
                    ops: wgpu::Operations {
                        load: wgpu::LoadOp::Clear(t.clear),
                        store: wgpu::StoreOp::Store,
                    },
                })],
                depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                    view: &t.depth_view,
                    depth_ops: Some(wgpu::Operations {
                        load: wgpu::LoadOp::Clear(1.0),
                        store: wgpu::StoreOp::Store,
                    }),
                    stencil_ops: None,
                }),
                timestamp_writes: t.q.writes(0),
                occlusion_query_set: Some(&t.q.occlusion),
                multiview_mask: None,
            });
            pass.begin_occlusion_query(0);
            self.draw(&mut pass, &p.pipe, &p.bindings, &p.scene, p.vgroup);
            pass.end_occlusion_query();
        }
        t.q.resolve(&mut enc, slot);
        let mut rb = self.device.create_command_encoder(&Default::default());
        if let Some((frame_rb, depth_rb, keeper)) = &t.kept {
            frame_rb.copy(&mut rb, &t.color, slot);
            let at = slot as u64 * depth_rb.slot_bytes;
            keeper.keep(self, &mut rb, &t.color, &t.depth, &depth_rb.buf, at, gpu);
        }
        if let Some((_, e)) = &t.errors {
            e.encode(self, &mut rb, &t.color, &t.color_view, f, slot)?;
        }
        Ok((enc, rb))
    }

    /// Frame `f`, back in `slot` (`cpu_ms` its CPU time): its record, its PNGs, its pixels for
    /// the perceptual metrics where sampled, and the frame and depth where kept.
    fn plain_frame_back(
        &self,
        run: &PlainRun<'_>,
        slot: u32,
        f: u32,
        cpu_ms: f64,
        out: &mut PlainOut,
    ) -> Result<(), ReplayError> {
        let (t, opts) = (&run.targets, run.opts);
        let [w, h] = run.session.resolution;
        let (pixels, depth): (Vec<f32>, Vec<f32>) = match &t.kept {
            Some((frame_rb, depth_rb, _)) => (
                bytemuck::pod_collect_to_vec(&frame_rb.image(slot)?),
                bytemuck::pod_collect_to_vec(&depth_rb.image(slot)?),
            ),
            None => (Vec::new(), Vec::new()),
        };
        let mut covered = depth.iter().filter(|&&d| d < 1.0).count() as u64;
        let mut nonfinite = pixels.chunks_exact(4).filter(|p| !l2::finite3(p)).count() as u64;
        // Scored: the error against the reference (its covered pixels) and, for the sampled
        // frames, the perceptual metrics.
        let mut errs = l2::FrameError::default();
        let mut scored = None;
        if let Some((reference, e)) = &t.errors {
            let back = e.read(slot, reference, f)?;
            // Pixels come back only for a sampled frame scored on the CPU.
            if let Some(px) = back.pixels {
                out.to_score.push((f, px));
            }
            (covered, nonfinite) = (back.error.covered, back.error.nonfinite);
            (errs, scored) = (back.error, back.perceptual);
        }
        let (occ, pass_ms, span) = t.q.read(slot)?;
        let frame_ms = span.unwrap_or(cpu_ms);
        if let Some(dir) = &opts.png_dir {
            output::write_frame(dir, f, w, h, &pixels)?;
            if opts.raw_frames {
                output::write_frame_raw(dir, f, &pixels)?;
            }
        }
        out.report.frames.push(FrameRecord {
            frame: f,
            frame_ms,
            cpu_ms,
            pass_ms,
            shaded: occ[0],
            hits: 0,
            recomputes: occ[0],
            hit_px: None,
            miss_px: None,
            refresh_px: None,
            hit_rate: 0.0,
            error: errs.error(),
            mse: errs.mse(),
            covered,
            psnr: errs.psnr(),
            max_abs_diff: errs.max_abs_diff,
            nonfinite,
            nonfinite_reference: errs.nonfinite_reference,
            flip: scored.map(|p| p.flip),
            ssim: scored.map(|p| p.ssim),
        });
        if t.kept.is_some() {
            out.frames.push(pixels);
            out.depth.push(depth);
        }
        Ok(())
    }
}

/// What [`Renderer::render_plain`] keeps of the frames.
#[derive(Clone, Copy)]
pub(super) enum Keep<'r> {
    /// The frames, their depth and their copy on the GPU: a [`Reference`].
    Frames,
    /// Nothing: each frame is scored against this reference instead.
    ScoreAgainst(&'r Reference),
}

/// What a plain render keeps, and where its samples sit in their pixels.
pub(super) struct Plain<'r> {
    pub(super) keep: Keep<'r>,
    pub(super) jitter: Jitter,
}

/// The frames, depths and GPU copy a [`Keep::Frames`] render keeps.
pub(super) type KeptFrames = (Vec<Vec<f32>>, Vec<Vec<f32>>, GpuReference);

/// The original's pass ([`Renderer::plain_pass`]).
pub(in crate::render) struct PlainPass {
    pub(in crate::render) iface: Interface,
    pub(in crate::render) scene: Scene,
    /// The bind group of the vertex transforms (one the shader leaves free).
    pub(in crate::render) vgroup: u32,
    pub(in crate::render) bindings: Bindings,
    pub(in crate::render) pipe: Pipe,
    /// The vertex stage and its source (a motion pass draws with it).
    pub(in crate::render) vs: wgpu::ShaderModule,
    pub(in crate::render) vs_src: String,
}

/// A plain render's targets, queries and readback ([`Renderer::plain_targets`]).
struct PlainTargets<'r> {
    color: wgpu::Texture,
    color_view: wgpu::TextureView,
    depth: wgpu::Texture,
    depth_view: wgpu::TextureView,
    /// Frames per readback batch.
    slots: u32,
    q: QueryKit,
    /// Frames kept ([`Keep::Frames`], not timing only): the frame and depth staging and the
    /// keeper of their GPU copies.
    kept: Option<(Staging, Staging, Keeper)>,
    /// Frames scored ([`Keep::ScoreAgainst`]): the reference and the error reduction.
    errors: Option<(&'r Reference, FrameErrors<'r>)>,
    /// The session's background.
    clear: wgpu::Color,
}

/// What the frame loop of a plain render reads.
struct PlainRun<'a> {
    /// Where each frame's samples sit in their pixels.
    jitter: Jitter,
    session: &'a Session,
    opts: &'a RenderOptions,
    first: u32,
    frames: u32,
    pass: PlainPass,
    targets: PlainTargets<'a>,
}

/// What a plain render gathers as its frames come back.
struct PlainOut {
    report: RenderReport,
    /// Sampled frames scored on the CPU, handed to the scorer after each batch.
    to_score: Vec<(u32, Vec<f32>)>,
    /// Kept frames and depths, and their copies on the GPU.
    frames: Vec<Vec<f32>>,
    depth: Vec<Vec<f32>>,
    gpu: GpuReference,
}
