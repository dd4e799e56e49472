//! ꟻLIP and SSIM of frames on the host: [`Renderer::perceptual_of`] (what `compare` scores its
//! methods' frames with, where [`crate::PerceptualOn`] says), and [`Scorer`] on the CPU while a
//! frame loop goes on — for the sampled frames where the CPU scores them, and for replays that
//! read every frame back to write it as a PNG (it writes the ꟻLIP maps too). On the device a
//! scored replay scores its sampled frames where they are (`reduce/perceptual.rs`).
//!
//! On the CPU the perceptual metrics are the costliest work of a replay (ꟻLIP: about 26 ms per
//! 256×256 frame on one core). Both frame loops hand each sampled frame to a [`Scorer`], which
//! scores it on [`scoring_pool`]'s threads. Those run at the lowest
//! CPU priority, so on a CPU adapter (lavapipe) they take only the cycles the rasterizer leaves
//! idle and never slow a timed frame (`docs/notebook/analysis-time.md`, "Analysis time: the error
//! reduction and the scoring threads"); on a GPU they simply overlap the rendering. A loop's scope waits for the
//! last of its frames, so scoring never overlaps another render or a race.

use std::sync::mpsc;

use reproj_metrics::RenderReport;
use reproj_metrics::output;
use reproj_metrics::perceptual::{self, PerceptualError};

use super::{RenderOptions, Renderer};
use crate::error::ReplayError;
use crate::reduce::{GpuPerceptual, Reference};

impl Renderer {
    /// ꟻLIP and SSIM of each of `frames` against the reference frame of the same index (linear
    /// RGBA f32, `size` pixels, top row first), pooled over the pixels where that frame's
    /// `depth` < 1: the metrics a scored replay computes, where it computes them
    /// ([`crate::PerceptualOn`]), for frames the caller holds. On the device one frame at a time
    /// is uploaded and scored (only numbers come back); on the CPU the frames are scored side
    /// by side on the current rayon pool.
    pub fn perceptual_of(
        &self,
        frames: &[&[f32]],
        references: &[&[f32]],
        depth: &[&[f32]],
        [w, h]: [u32; 2],
    ) -> Result<Vec<PerceptualError>, ReplayError> {
        if frames.len() != references.len() || frames.len() != depth.len() {
            return Err(ReplayError::ReferenceMismatch {
                reference: format!(
                    "{} reference frames and {} depth images",
                    references.len(),
                    depth.len()
                ),
                session: format!("{} frames to score", frames.len()),
            });
        }
        if frames.is_empty() {
            return Ok(Vec::new());
        }
        let Some(kernel) = self.kernels().perceptual else {
            use rayon::prelude::*;
            let scored = frames
                .par_iter()
                .zip(references)
                .zip(depth)
                .map(|((frame, reference), depth)| {
                    let (p, _) = perceptual::compare_perceptual_split(
                        frame,
                        reference,
                        depth,
                        w,
                        h,
                        perceptual::FrameSplit::Whole,
                    );
                    p
                })
                .collect();
            return Ok(scored);
        };
        let scorer = GpuPerceptual::new(self, kernel.get(self)?, w, h, 1)?;
        let out = frames
            .iter()
            .zip(references)
            .zip(depth)
            .map(|((frame, reference), depth)| scorer.score(self, frame, reference, depth))
            .collect::<Result<Vec<_>, _>>()?;
        self.check_errors("scoring frames")?;
        Ok(out)
    }
}

/// The pool that scores sampled frames: one thread per core, each at the lowest CPU priority
/// (Linux: the `SCHED_IDLE` policy, else nice 19, for the thread). Made once.
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

/// Put the calling thread at the lowest CPU priority: `SCHED_IDLE`, under which a normal thread
/// that wakes preempts it at once, else nice 19 (on Linux both apply to the calling thread only).
/// Elsewhere, and where both fail, the thread keeps its priority.
#[allow(unsafe_code)]
fn lowest_priority() {
    #[cfg(target_os = "linux")]
    // SAFETY: sched_setscheduler reads the parameter through a pointer to a live local;
    // setpriority takes no pointers. Each changes this thread's scheduling or fails.
    unsafe {
        let param = libc::sched_param { sched_priority: 0 };
        if libc::sched_setscheduler(0, libc::SCHED_IDLE, &param) != 0 {
            libc::setpriority(libc::PRIO_PROCESS, 0, 19);
        }
    }
}

/// One frame's metrics and its ꟻLIP map.
type Scored = (u32, (PerceptualError, Vec<f32>));

/// The sampled frames of one frame loop, scored on [`scoring_pool`] inside the loop's
/// `in_place_scope`.
pub(super) struct Scorer<'r> {
    reference: &'r Reference,
    size: [u32; 2],
    tx: mpsc::Sender<Scored>,
    rx: mpsc::Receiver<Scored>,
    scored: Vec<Scored>,
    /// Frames handed over and not yet received.
    waiting: usize,
}

impl<'r> Scorer<'r> {
    /// For frames of `size` pixels, against `reference`.
    pub(super) fn new(reference: &'r Reference, size: [u32; 2]) -> Scorer<'r> {
        let (tx, rx) = mpsc::channel();
        Scorer {
            reference,
            size,
            tx,
            rx,
            scored: Vec::new(),
            waiting: 0,
        }
    }

    /// Score frame `f` (`pixels`: linear RGBA f32) on the pool. At most two frames per scoring
    /// thread wait (a 1080p frame is 33 MB): past that this waits for one to be scored.
    pub(super) fn spawn<'s>(&mut self, scope: &rayon::Scope<'s>, f: u32, pixels: Vec<f32>)
    where
        'r: 's,
    {
        let (tx, reference, [w, h]) = (self.tx.clone(), self.reference, self.size);
        scope.spawn(move |_| {
            let fi = f as usize;
            // The pool scores frames side by side, one per thread: each frame in one piece.
            let metrics = perceptual::compare_perceptual_split(
                &pixels,
                &reference.frames[fi],
                &reference.depth[fi],
                w,
                h,
                perceptual::FrameSplit::Whole,
            );
            // The receiver outlives the scope.
            let _ = tx.send((f, metrics));
        });
        self.waiting += 1;
        let most = 2 * scoring_pool().current_num_threads();
        while self.waiting > most
            && let Ok(done) = self.rx.recv()
        {
            self.scored.push(done);
            self.waiting -= 1;
        }
    }

    /// Every frame's metrics into its record of `report`, and the ꟻLIP maps written where
    /// frames are. Call once the loop's scope has ended (every frame is scored then).
    pub(super) fn record(
        self,
        report: &mut RenderReport,
        opts: &RenderOptions,
    ) -> Result<(), ReplayError> {
        let Scorer {
            tx,
            rx,
            mut scored,
            size: [w, h],
            ..
        } = self;
        drop(tx);
        scored.extend(rx);
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
