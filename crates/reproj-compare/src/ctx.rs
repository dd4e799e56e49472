//! What every method's renders share ([`Ctx`]): the renderer, the original's reference and its
//! timing baseline, and the renders, races and scores each search step calls.

use std::cell::RefCell;
use std::path::Path;

use reproj_analyze::Progress;
use reproj_front::Shader;
use reproj_metrics::PSNR_CAP;
use reproj_metrics::l2;
use reproj_models::speedup::SpeedupEstimate;
use reproj_replay::{Reference, RenderOptions, Renderer};
use reproj_scene::Session;

use crate::{Against, CompareError, Scores, Split};

/// Whether a try's race leaves it in doubt: its estimate misses the target by more than
/// `tolerance` while its interval reaches into the band the tolerance allows, so the race cannot
/// tell a try that is on target from one that is not (a search race of 8 rounds of 8 frames is
/// ±6–8 % wide on lavapipe, the tolerance ±5 %).
pub(crate) fn in_doubt(e: &SpeedupEstimate, target: f64, tolerance: f64) -> bool {
    let (lo, hi) = (target / (1.0 + tolerance), target * (1.0 + tolerance));
    let off = e.speedup < lo || e.speedup > hi;
    off && e.ci95[0] <= hi && e.ci95[1] >= lo
}

/// A try's `races` in files written before it: one.
pub(crate) fn one_race() -> u32 {
    1
}

/// What every method's renders share.
pub(crate) struct Ctx<'a> {
    pub(crate) renderer: &'a Renderer,
    /// The original, which every try is timed against.
    pub(crate) baseline: reproj_bench::Baseline<'a>,
    pub(crate) search_timing: &'a reproj_bench::BenchOptions,
    /// The searches' timing warnings, once each.
    pub(crate) timing_warnings: RefCell<Vec<String>>,
    pub(crate) session: &'a Session,
    pub(crate) reference: &'a Reference,
    /// The supersampled reference's frames ([`crate::supersample::reference`]), when made.
    pub(crate) supersampled: Option<&'a [Vec<f32>]>,
    /// Which frames move ([`crate::supersample::moving_frames`]).
    pub(crate) moving: &'a [bool],
    pub(crate) render_opts: &'a RenderOptions,
    pub(crate) stride: u32,
    pub(crate) target: f64,
    pub(crate) progress: &'a dyn Progress,
}

impl Ctx<'_> {
    /// Time `candidates` against the original, interleaved in one short run
    /// ([`CompareOptions::search_timing`]): each one's estimate, `None` where a candidate gave no
    /// finite figure. The searches steer on these, never on a replay's own mean.
    pub(crate) fn race(
        &self,
        candidates: &[reproj_bench::Candidate],
    ) -> Result<Vec<Option<SpeedupEstimate>>, CompareError> {
        let report = self.race_report(candidates)?;
        Ok((0..candidates.len()).map(|i| report.estimate(i)).collect())
    }

    /// A search try's race against the target: one short interleaved run, and a second whose
    /// rounds are pooled with the first's where the first cannot place the try ([`in_doubt`]):
    /// otherwise one race's noise moves the search (marble at 2×: reproj's Δn 12 measured 1.87×
    /// [1.52, 2.32] once and 2.17× the next run, and the first run stepped to Δn 18). The estimate
    /// (`None` without a finite figure) and how many races it pools.
    pub(crate) fn race_try(
        &self,
        candidate: reproj_bench::Candidate,
        tolerance: f64,
    ) -> Result<(Option<SpeedupEstimate>, u32), CompareError> {
        let candidates = [candidate];
        let first = self.race_report(&candidates)?;
        let timed = first.estimate(0);
        if !timed.is_some_and(|e| in_doubt(&e, self.target, tolerance)) {
            return Ok((timed, 1));
        }
        let again = self.race_report(&candidates)?;
        Ok((first.pooled_estimate(0, &again, 0).or(timed), 2))
    }

    /// [`Ctx::race`]'s run itself, whose rounds a second run of the same candidates can be
    /// pooled with ([`reproj_bench::BenchReport::pooled_estimate`]).
    pub(crate) fn race_report(
        &self,
        candidates: &[reproj_bench::Candidate],
    ) -> Result<reproj_bench::BenchReport, CompareError> {
        let report = reproj_bench::bench(
            self.renderer,
            self.baseline,
            self.session,
            candidates,
            self.search_timing,
            &mut |_| {},
        )?;
        let mut seen = self.timing_warnings.borrow_mut();
        for w in &report.warnings {
            reproj_bench::add_warning_once(&mut seen, w);
        }
        Ok(report)
    }

    /// A candidate that renders `shader` (entry 0) like the original, over `session` when given.
    pub(crate) fn shader_candidate(
        name: &str,
        shader: Shader,
        entry: usize,
        session: Option<Session>,
    ) -> reproj_bench::Candidate {
        reproj_bench::Candidate {
            name: name.into(),
            subject: reproj_bench::Subject::Shader {
                shader: Box::new(shader),
                entry,
                session: session.map(Box::new),
            },
        }
    }

    /// L2 error and PSNR of `frames` (full resolution) against the reference; ꟻLIP, the
    /// still/moving split and the same against the supersampled reference too when
    /// `perceptual` (a method's final frames).
    pub(crate) fn score(
        &self,
        frames: &[Vec<f32>],
        perceptual: bool,
    ) -> Result<Scores, CompareError> {
        let (one, error) = self.against(frames, &self.reference.frames, perceptual)?;
        Ok(Scores {
            error,
            psnr: one.psnr,
            flip: one.flip,
            split: one.split,
            supersampled: match (perceptual, self.supersampled) {
                (true, Some(ss)) => Some(self.against(frames, ss, true)?.0),
                _ => None,
            },
        })
    }

    /// The one-sample original against the supersampled reference, when there is one.
    pub(crate) fn original_vs_supersampled(&self) -> Result<Option<Against>, CompareError> {
        let Some(ss) = self.supersampled else {
            return Ok(None);
        };
        Ok(Some(self.against(&self.reference.frames, ss, true)?.0))
    }

    /// PSNR of `frames` against `refs` over the reference's covered pixels, pooled over every
    /// frame and (where the session has both) over the still and the moving frames; ꟻLIP on the
    /// perceptual stride when `perceptual`, computed where the renderer's scored replays compute
    /// it ([`Renderer::perceptual_of`]). Beside it, the mean per-pixel L2 error.
    fn against(
        &self,
        frames: &[Vec<f32>],
        refs: &[Vec<f32>],
        perceptual: bool,
    ) -> Result<(Against, f64), CompareError> {
        let depth = &self.reference.depth;
        let mut sum_error = 0.0;
        // [all, still, moving]: (sum of squares, covered pixels).
        let mut pools = [(0.0, 0u64); 3];
        for (f, frame) in frames.iter().enumerate() {
            let e = l2::compare(frame, &refs[f], &depth[f]);
            sum_error += e.error();
            let side = if self.moving.get(f).copied().unwrap_or(false) {
                2
            } else {
                1
            };
            for i in [0, side] {
                pools[i].0 += e.sum_sq;
                pools[i].1 += e.covered;
            }
        }
        let psnr = |(sum_sq, covered): (f64, u64)| {
            let p = l2::psnr(l2::mse(sum_sq, covered));
            if p.is_finite() { p } else { PSNR_CAP }
        };
        let still = self.moving.iter().filter(|&&m| !m).count();
        let moving = self.moving.len() - still;
        let split = (perceptual && still >= 2 && moving >= 1).then(|| Split {
            still_psnr: psnr(pools[1]),
            moving_psnr: psnr(pools[2]),
        });
        // ꟻLIP on every stride-th frame.
        let flips: Vec<f64> = if perceptual {
            let sampled: Vec<usize> = (0..frames.len())
                .filter(|&f| (f as u32).is_multiple_of(self.stride))
                .collect();
            let r = self.reference;
            self.renderer
                .perceptual_of(
                    &pick(frames, &sampled),
                    &pick(refs, &sampled),
                    &pick(depth, &sampled),
                    [r.width, r.height],
                )?
                .iter()
                .map(|p| p.flip)
                .collect()
        } else {
            Vec::new()
        };
        let against = Against {
            psnr: psnr(pools[0]),
            flip: (!flips.is_empty()).then(|| flips.iter().sum::<f64>() / flips.len() as f64),
            split,
        };
        Ok((against, sum_error / frames.len().max(1) as f64))
    }

    /// Render `shader` (a module reproj wrote, as WGSL) like the original: its frames and mean
    /// frame time.
    pub(crate) fn render_wgsl(
        &self,
        name: &str,
        wgsl: &str,
    ) -> Result<(Vec<Vec<f32>>, Shader), CompareError> {
        let shader = reproj_front::parse_shader(Path::new(name), wgsl.to_string())?;
        let frames = self.render_shader(&shader, 0, self.session)?;
        Ok((frames, shader))
    }

    /// The mean error of `wgsl` (a module reproj wrote) against the reference, scored on the GPU
    /// frame by frame without reading its frames back (what a search step needs), and the parsed
    /// shader.
    pub(crate) fn error_of_wgsl(
        &self,
        name: &str,
        wgsl: &str,
    ) -> Result<(f64, Shader), CompareError> {
        let shader = reproj_front::parse_shader(Path::new(name), wgsl.to_string())?;
        let opts = RenderOptions {
            perceptual_stride: None,
            ..self.render_opts.clone()
        };
        let report =
            self.renderer
                .render_scored(&shader, 0, self.session, self.reference, &opts)?;
        Ok((report.error, shader))
    }

    /// Render `shader` over `session`: its frames (their times are not used: see [`Ctx::race`]).
    pub(crate) fn render_shader(
        &self,
        shader: &Shader,
        entry: usize,
        session: &Session,
    ) -> Result<Vec<Vec<f32>>, CompareError> {
        let r = self
            .renderer
            .render_original(shader, entry, session, self.render_opts)?;
        Ok(r.frames)
    }
}

/// The images at `indices`, as slices.
fn pick<'a>(images: &'a [Vec<f32>], indices: &[usize]) -> Vec<&'a [f32]> {
    indices.iter().map(|&f| images[f].as_slice()).collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn estimate(speedup: f64, ci95: [f64; 2]) -> SpeedupEstimate {
        SpeedupEstimate {
            speedup,
            ci95,
            rounds: 8,
            outliers: 0,
            baseline_ms: 8.0,
            candidate_ms: 8.0 / speedup,
        }
    }

    /// Only a try off the target whose interval reaches into the tolerance band is raced again:
    /// one on target needs nothing more, one off beyond doubt steers at once.
    #[test]
    fn a_try_is_raced_again_only_when_its_race_cannot_place_it() {
        // Target 2×, ±5 %: the band is [1.905, 2.1].
        assert!(in_doubt(&estimate(1.87, [1.52, 2.32]), 2.0, 0.05));
        assert!(in_doubt(&estimate(2.2, [2.05, 2.35]), 2.0, 0.05));
        assert!(!in_doubt(&estimate(1.97, [1.80, 2.15]), 2.0, 0.05));
        assert!(!in_doubt(&estimate(1.6, [1.5, 1.7]), 2.0, 0.05));
        assert!(!in_doubt(&estimate(2.5, [2.3, 2.7]), 2.0, 0.05));
    }
}
