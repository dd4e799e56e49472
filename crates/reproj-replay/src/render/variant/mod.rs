//! The variant loop: render a cached variant of any strategy and compare it with the reference.
//!
//! In phases, a file each: `plan.rs` (checks and the passes' stages, before any GPU object),
//! `gpu.rs` (targets, bindings, pipelines, the empty cache), `frames.rs` (the frame loop). The
//! sampled frames' ꟻLIP and SSIM are scored during the loop on low-priority threads
//! ([`scoring_pool`]).

use std::collections::BTreeSet;
use std::path::Path;

use reproj_front::Shader;
use reproj_instance::{CacheFormat, Reprojection};

use crate::error::ReplayError;
use crate::reduce::{FrameErrors, PixelsBack};
use crate::vertex;
use rayon::prelude::*;
use reproj_metrics::l2;
use reproj_metrics::output;
use reproj_metrics::perceptual;
use reproj_metrics::{FrameRecord, RenderReport};
use reproj_scene::reflect::{self, Interface};
use reproj_scene::session::Session;

use reproj_instance::contract;

use super::*;

mod frames;
mod gpu;
mod motion;
mod plan;

use frames::FrameLoop;
use gpu::VariantGpu;
use plan::VariantPlan;

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
    /// frame loop (the sampled frames' perceptual metrics scored beside it, on
    /// [`scoring_pool`]).
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
        let run = FrameLoop {
            session,
            variant,
            reference,
            opts,
            progress,
            plan: &plan,
            gpu: &gpu,
        };
        self.variant_frames(&run, &mut report)?;
        report.summarize();
        Ok(report)
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

/// The pool that scores sampled frames (ꟻLIP, SSIM) during a replay: one thread per core, each
/// at the lowest CPU priority (Linux: nice 19 for the thread), so that on a CPU adapter the
/// scoring takes the cycles the rasterizer leaves idle rather than the ones it needs. Made once.
pub(super) fn scoring_pool() -> &'static rayon::ThreadPool {
    static POOL: std::sync::OnceLock<rayon::ThreadPool> = std::sync::OnceLock::new();
    POOL.get_or_init(|| {
        rayon::ThreadPoolBuilder::new()
            .thread_name(|i| format!("reproj-score-{i}"))
            .start_handler(|_| lowest_priority())
            .build()
            // Building a pool fails only when no thread can be spawned at all.
            .unwrap_or_else(|e| panic!("cannot start the scoring threads: {e}"))
    })
}

/// Put the calling thread at the lowest CPU priority (on Linux `setpriority` with who = 0 applies
/// to the calling thread only). Elsewhere, and where it fails, the thread keeps its priority.
#[allow(unsafe_code)]
fn lowest_priority() {
    #[cfg(target_os = "linux")]
    // SAFETY: setpriority takes no pointers; it changes this thread's nice value or fails.
    unsafe {
        let param = libc::sched_param { sched_priority: 0 };
        if libc::sched_setscheduler(0, libc::SCHED_IDLE, &param) != 0 {
            libc::setpriority(libc::PRIO_PROCESS, 0, 19);
        }
    }
}

/// The scored frames into their records of `report`, and their ꟻLIP maps written where frames
/// are.
pub(super) fn record_perceptual(
    mut scored: Vec<(u32, (perceptual::PerceptualError, Vec<f32>))>,
    report: &mut RenderReport,
    opts: &RenderOptions,
    [w, h]: [u32; 2],
) -> Result<(), ReplayError> {
    scored.sort_by_key(|(f, _)| *f);
    for (f, (e, map)) in scored {
        if let Some(r) = report.frames.iter_mut().rev().find(|r| r.frame == f) {
            (r.flip, r.ssim) = (Some(e.flip), Some(e.ssim));
        }
        if let Some(dir) = &opts.png_dir {
            output::write_flipmap(dir, f, w, h, &map)?;
        }
    }
    Ok(())
}

#[cfg(all(test, target_os = "linux"))]
mod tests {
    /// The scoring threads run under `SCHED_IDLE` (the timed frames' threads keep the CPU).
    #[test]
    #[allow(unsafe_code)]
    fn scoring_threads_run_at_the_lowest_priority() {
        // SAFETY: sched_getscheduler takes no pointers; it reads the calling thread's policy.
        let policy = super::scoring_pool().install(|| unsafe { libc::sched_getscheduler(0) });
        assert_eq!(policy, libc::SCHED_IDLE);
        // SAFETY: as above, for the calling (test) thread, which is left as it was.
        let own = unsafe { libc::sched_getscheduler(0) };
        assert_ne!(own, libc::SCHED_IDLE);
    }
}
