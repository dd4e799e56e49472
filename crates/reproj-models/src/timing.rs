//! Timing model (paper §4.3, eq. 3 and 5): per frame `t = h·E[hit] + m·E[miss] + E[overhead]`.
//!
//! Fitted per node by linear least squares over the frames of a replay (h hits, m misses, t ms),
//! with an SVD of the column-equilibrated system and a rank check. Negative costs are clamped to 0
//! (with a warning) by refitting the others with that one fixed at 0.
//!
//! Rank deficiency is reported, never papered over with garbage:
//! - when the shaded pixel count `h + m` is the same in every frame (the paper's own validation
//!   setup, a model covering the viewport), the overhead cannot be told from the per-pixel costs;
//!   we then fix `E[overhead] = 0` and absorb it into the per-pixel costs (`overhead_absorbed`).
//!   Frame predictions at that pixel count are unaffected; the fit stays usable.
//! - otherwise each cost that the data determine (its unit vector lies in the row space of the
//!   system) is reported and the others are `None` (`undetermined`): e.g. all-hit frames leave
//!   E[miss] undetermined, identical hit counts leave E[hit] and E[overhead] undetermined. A fit
//!   with any cost undetermined is not usable for prediction.

use nalgebra::{DMatrix, DVector};
use serde::{Deserialize, Serialize};

use crate::stats::{finite_or, r_squared, rms_residual};

/// One replayed frame: hit and miss pixel counts (occlusion queries) and its time.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct FrameTiming {
    /// Pixels that reused the cache.
    pub hits: u64,
    /// Pixels that recomputed the node (miss or refresh).
    pub misses: u64,
    /// Frame time in milliseconds.
    pub time_ms: f64,
}

/// Options of [`fit_timing_with_options`].
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default)]
pub struct TimingFitOptions {
    /// Singular values below `rank_rtol` × the largest one (of the column-equilibrated system) count
    /// as zero. Also the relative spread of `h + m` under which the pixel count is constant.
    pub rank_rtol: f64,
}

impl Default for TimingFitOptions {
    fn default() -> Self {
        Self { rank_rtol: 1e-6 }
    }
}

/// One of the three timing costs.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum TimingParam {
    /// E[hit], ms per hit pixel.
    Hit,
    /// E[miss], ms per miss pixel.
    Miss,
    /// E[overhead], ms per frame.
    Overhead,
}

/// A non-fatal remark on a timing fit.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(tag = "kind", rename_all = "snake_case")]
pub enum TimingWarning {
    /// The least-squares cost was negative; it was set to 0 (and the others refitted when the
    /// system had full rank).
    NegativeClamped {
        /// Which cost.
        param: TimingParam,
        /// Its value before clamping.
        raw: f64,
    },
    /// Held-out frames were given but not evaluated.
    HoldoutSkipped {
        /// Why.
        reason: String,
    },
}

/// Why a timing fit failed.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, thiserror::Error)]
#[serde(tag = "kind", rename_all = "snake_case")]
pub enum TimingFitFailure {
    /// No frames.
    #[error("no frames")]
    Empty,
    /// Some frame time is NaN or infinite.
    #[error("{count} frame(s) with a NaN or infinite time")]
    NonFiniteInput {
        /// How many frames.
        count: usize,
    },
    /// A negative frame time.
    #[error("negative frame time {value} ms")]
    NegativeTime {
        /// The offending time.
        value: f64,
    },
    /// No frame shaded any pixel: per-pixel costs are meaningless.
    #[error("no shaded pixels in any frame")]
    NoShadedPixels,
}

/// Status of a [`TimingFit`].
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(tag = "status", rename_all = "snake_case")]
pub enum TimingStatus {
    /// Full rank: all three costs determined (see `warnings` for clamping).
    Ok,
    /// The system had rank < 3 (see the module docs for the fallback).
    RankDeficient {
        /// Numerical rank of the full system `[h m 1]`.
        rank: usize,
        /// `h + m` was constant: E[overhead] fixed at 0 and absorbed into the per-pixel costs.
        overhead_absorbed: bool,
        /// Costs the data do not determine (reported as `None`).
        undetermined: Vec<TimingParam>,
    },
    /// Not usable.
    Failed {
        /// Why.
        reason: TimingFitFailure,
    },
}

/// Fitted timing model of one node (or of the original shader).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct TimingFit {
    /// E[hit], ms per hit pixel (≥ 0).
    pub hit_ms: Option<f64>,
    /// E[miss], ms per miss pixel (≥ 0).
    pub miss_ms: Option<f64>,
    /// E[overhead], ms per frame (≥ 0).
    pub overhead_ms: Option<f64>,
    /// M: mean shaded pixels (h + m) per frame over the fitted frames.
    pub mean_pixels: Option<f64>,
    /// R² over the fitted frames.
    pub r2: Option<f64>,
    /// RMS residual over the fitted frames, ms.
    pub rms_residual_ms: Option<f64>,
    /// RMS prediction error over the held-out frames, ms.
    pub holdout_rms_ms: Option<f64>,
    /// Mean of |predicted − measured| / measured over the held-out frames with a positive time.
    pub holdout_mean_relative_error: Option<f64>,
    /// Frames fitted.
    pub n_frames: usize,
    /// Held-out frames evaluated.
    pub n_holdout: usize,
    /// Numerical rank of the system `[h m 1]`.
    pub rank: usize,
    /// Ok, rank deficient, or why not.
    pub status: TimingStatus,
    /// Non-fatal remarks (clamping, skipped hold-out).
    pub warnings: Vec<TimingWarning>,
}

impl TimingFit {
    /// A fit with given costs (e.g. synthetic, for tests or what-if analyses); status Ok.
    pub fn from_costs(hit_ms: f64, miss_ms: f64, overhead_ms: f64, mean_pixels: f64) -> Self {
        let f = |x: f64| x.is_finite().then_some(x);
        Self {
            hit_ms: f(hit_ms),
            miss_ms: f(miss_ms),
            overhead_ms: f(overhead_ms),
            mean_pixels: f(mean_pixels),
            r2: None,
            rms_residual_ms: None,
            holdout_rms_ms: None,
            holdout_mean_relative_error: None,
            n_frames: 0,
            n_holdout: 0,
            rank: 3,
            status: TimingStatus::Ok,
            warnings: Vec::new(),
        }
    }

    /// Whether the fit can predict: not failed and all three costs determined.
    pub fn is_usable(&self) -> bool {
        !matches!(self.status, TimingStatus::Failed { .. }) && self.costs().is_some()
    }

    /// `(E[hit], E[miss], E[overhead])` when all are determined and the fit did not fail.
    fn costs(&self) -> Option<(f64, f64, f64)> {
        if matches!(self.status, TimingStatus::Failed { .. }) {
            return None;
        }
        Some((self.hit_ms?, self.miss_ms?, self.overhead_ms?))
    }

    /// Per-pixel time `r̂ = γ·E[hit] + (1 − γ)·E[miss]` (eq. 5), ms, at hit rate `gamma`.
    pub fn per_pixel_ms(&self, gamma: f64) -> Option<f64> {
        let (h, m, _) = self.costs()?;
        let r = gamma * h + (1.0 - gamma) * m;
        r.is_finite().then_some(r)
    }

    /// Frame time `E[overhead] + M·r̂` in ms, at hit rate `gamma` with `mean_pixels` (M) pixels.
    pub fn frame_ms(&self, gamma: f64, mean_pixels: f64) -> Option<f64> {
        let (_, _, o) = self.costs()?;
        let t = o + mean_pixels * self.per_pixel_ms(gamma)?;
        t.is_finite().then_some(t)
    }

    /// Predicted time of a frame with the given counts (eq. 3), ms.
    pub fn predict_counts(&self, hits: u64, misses: u64) -> Option<f64> {
        let (h, m, o) = self.costs()?;
        let t = o + hits as f64 * h + misses as f64 * m;
        t.is_finite().then_some(t)
    }

    fn failed(n_frames: usize, reason: TimingFitFailure) -> Self {
        Self {
            hit_ms: None,
            miss_ms: None,
            overhead_ms: None,
            mean_pixels: None,
            r2: None,
            rms_residual_ms: None,
            holdout_rms_ms: None,
            holdout_mean_relative_error: None,
            n_frames,
            n_holdout: 0,
            rank: 0,
            status: TimingStatus::Failed { reason },
            warnings: Vec::new(),
        }
    }
}

/// Fit the timing model to all `frames` with default options.
pub fn fit_timing(frames: &[FrameTiming]) -> TimingFit {
    fit_timing_with_options(frames, &[], &TimingFitOptions::default())
}

/// Fit to `frames` and report the prediction error on `holdout` frames (not used in the fit).
pub fn fit_timing_with_holdout(frames: &[FrameTiming], holdout: &[FrameTiming]) -> TimingFit {
    fit_timing_with_options(frames, holdout, &TimingFitOptions::default())
}

/// Validate frames: `Err` with the failure, if any.
fn validate(frames: &[FrameTiming]) -> Result<(), TimingFitFailure> {
    if frames.is_empty() {
        return Err(TimingFitFailure::Empty);
    }
    let non_finite = frames.iter().filter(|f| !f.time_ms.is_finite()).count();
    if non_finite > 0 {
        return Err(TimingFitFailure::NonFiniteInput { count: non_finite });
    }
    if let Some(f) = frames.iter().find(|f| f.time_ms < 0.0) {
        return Err(TimingFitFailure::NegativeTime { value: f.time_ms });
    }
    Ok(())
}

/// Fit to `frames` with `opts`; `holdout` may be empty. Phases: the checks, the least-squares
/// system, the costs (by an active set at full rank, [`full_rank_costs`]; the determined ones
/// otherwise, [`rank_deficient_costs`]), then the quality of the fit.
pub fn fit_timing_with_options(
    frames: &[FrameTiming],
    holdout: &[FrameTiming],
    opts: &TimingFitOptions,
) -> TimingFit {
    let n = frames.len();
    if let Err(reason) = validate(frames) {
        return TimingFit::failed(n, reason);
    }
    let rtol = if opts.rank_rtol.is_finite() && opts.rank_rtol > 0.0 {
        opts.rank_rtol
    } else {
        TimingFitOptions::default().rank_rtol
    };
    let pixels: Vec<f64> = frames
        .iter()
        .map(|f| f.hits as f64 + f.misses as f64)
        .collect();
    let mean_pixels = pixels.iter().sum::<f64>() / n as f64;
    if mean_pixels <= 0.0 {
        return TimingFit::failed(n, TimingFitFailure::NoShadedPixels);
    }
    let system = System {
        cols: [
            frames.iter().map(|f| f.hits as f64).collect::<Vec<_>>(),
            frames.iter().map(|f| f.misses as f64).collect::<Vec<_>>(),
            vec![1.0; n],
        ],
        t: frames.iter().map(|f| f.time_ms).collect(),
        rtol,
    };
    let full = least_squares(&system.cols, &[0, 1, 2], &system.t, rtol);
    let full_rank = full.rank;
    let mut warnings = Vec::new();
    let (costs, status) = if full_rank == 3 {
        (
            full_rank_costs(&system, full, &mut warnings),
            TimingStatus::Ok,
        )
    } else {
        let (costs, overhead_absorbed) =
            rank_deficient_costs(&system, &pixels, full, &mut warnings);
        let undetermined = (0..3)
            .filter(|&j| costs.value[j].is_none())
            .map(|j| PARAMS[j])
            .collect();
        (
            costs,
            TimingStatus::RankDeficient {
                rank: full_rank,
                overhead_absorbed,
                undetermined,
            },
        )
    };
    let Costs { value, used } = costs;
    let t = &system.t;
    let fitted: Vec<f64> = frames
        .iter()
        .map(|f| used[2] + f.hits as f64 * used[0] + f.misses as f64 * used[1])
        .collect();
    let rank = match &status {
        TimingStatus::RankDeficient { rank, .. } => *rank,
        _ => 3,
    };
    let mut fit = TimingFit {
        hit_ms: value[0],
        miss_ms: value[1],
        overhead_ms: value[2],
        mean_pixels: Some(mean_pixels),
        r2: Some(r_squared(t, &fitted)),
        rms_residual_ms: Some(rms_residual(t, &fitted)),
        holdout_rms_ms: None,
        holdout_mean_relative_error: None,
        n_frames: n,
        n_holdout: 0,
        rank,
        status,
        warnings,
    };
    if !holdout.is_empty() {
        evaluate_holdout(&mut fit, holdout);
    }
    fit
}

/// The costs' columns, in [`PARAMS`] order.
const PARAMS: [TimingParam; 3] = [TimingParam::Hit, TimingParam::Miss, TimingParam::Overhead];

/// The least-squares system of a timing fit: the columns (hits, misses, a constant), the frame
/// times, and the rank tolerance.
struct System {
    cols: [Vec<f64>; 3],
    t: Vec<f64>,
    rtol: f64,
}

/// A fit's costs in [`PARAMS`] order: the reported values (`None`: undetermined) and the values
/// the fitted times are computed with.
struct Costs {
    value: [Option<f64>; 3],
    used: [f64; 3],
}

/// At full rank, by an active set (as in Lawson–Hanson NNLS): fix the most negative cost at 0
/// and refit the others, one at a time. With nearly collinear columns (pixel counts that barely
/// change between frames) several raw costs can come out negative together, and only the worst
/// is wrong: fixing all of them at once would throw away the per-pixel cost that is real.
fn full_rank_costs(system: &System, full: LsSolution, warnings: &mut Vec<TimingWarning>) -> Costs {
    let mut fixed = [false; 3];
    let mut sol = full;
    loop {
        let worst = sol
            .cols
            .iter()
            .zip(&sol.x)
            .filter(|(_, x)| **x < 0.0)
            .min_by(|a, b| a.1.total_cmp(b.1))
            .map(|(j, x)| (*j, *x));
        let Some((j, raw)) = worst else {
            break;
        };
        fixed[j] = true;
        warnings.push(TimingWarning::NegativeClamped {
            param: PARAMS[j],
            raw,
        });
        let free: Vec<usize> = (0..3).filter(|&j| !fixed[j]).collect();
        if free.is_empty() {
            sol = LsSolution::empty();
            break;
        }
        sol = least_squares(&system.cols, &free, &system.t, system.rtol);
    }
    let mut costs = Costs {
        value: [None; 3],
        used: [0.0; 3],
    };
    for j in 0..3 {
        let v = sol
            .cols
            .iter()
            .position(|&c| c == j)
            .map_or(0.0, |k| sol.x[k]);
        costs.value[j] = Some(v);
        costs.used[j] = v;
    }
    costs
}

/// Below full rank: the overhead absorbed (fixed at 0) when every frame shades the same number
/// of pixels, and only the costs the data determines reported (a negative one clamped at 0).
/// Also whether the overhead was absorbed.
fn rank_deficient_costs(
    system: &System,
    pixels: &[f64],
    full: LsSolution,
    warnings: &mut Vec<TimingWarning>,
) -> (Costs, bool) {
    let (lo, hi) = pixels
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), &p| {
            (lo.min(p), hi.max(p))
        });
    let constant_pixels = hi - lo <= system.rtol * hi;
    let (sol, overhead_absorbed) = if constant_pixels {
        (
            least_squares(&system.cols, &[0, 1], &system.t, system.rtol),
            true,
        )
    } else {
        (full, false)
    };
    let mut costs = Costs {
        value: [None; 3],
        used: [0.0; 3],
    };
    if overhead_absorbed {
        costs.value[2] = Some(0.0);
    }
    for (k, &j) in sol.cols.iter().enumerate() {
        costs.used[j] = sol.x[k];
        if sol.identifiable[k] {
            let v = sol.x[k];
            if v < 0.0 {
                warnings.push(TimingWarning::NegativeClamped {
                    param: PARAMS[j],
                    raw: v,
                });
                costs.value[j] = Some(0.0);
                costs.used[j] = 0.0;
            } else {
                costs.value[j] = Some(v);
            }
        }
    }
    (costs, overhead_absorbed)
}

/// Fill the hold-out fields of `fit` (or add a `HoldoutSkipped` warning).
fn evaluate_holdout(fit: &mut TimingFit, holdout: &[FrameTiming]) {
    if let Err(reason) = validate(holdout) {
        fit.warnings.push(TimingWarning::HoldoutSkipped {
            reason: format!("invalid held-out frames: {reason}"),
        });
        return;
    }
    if !fit.is_usable() {
        fit.warnings.push(TimingWarning::HoldoutSkipped {
            reason: "fit cannot predict (a cost is undetermined)".into(),
        });
        return;
    }
    let mut ss = 0.0;
    let mut rel = 0.0;
    let mut n_rel = 0usize;
    for f in holdout {
        let p = fit.predict_counts(f.hits, f.misses).unwrap_or(0.0);
        ss += (p - f.time_ms).powi(2);
        if f.time_ms > 0.0 {
            rel += (p - f.time_ms).abs() / f.time_ms;
            n_rel += 1;
        }
    }
    fit.n_holdout = holdout.len();
    fit.holdout_rms_ms = Some(finite_or((ss / holdout.len() as f64).sqrt(), 0.0));
    fit.holdout_mean_relative_error = (n_rel > 0)
        .then(|| rel / n_rel as f64)
        .filter(|r| r.is_finite());
}

/// Least-squares solution over a subset of the columns.
#[derive(Debug)]
struct LsSolution {
    /// Column indices solved for.
    cols: Vec<usize>,
    /// Minimum-norm solution, one per column in `cols`.
    x: Vec<f64>,
    /// Whether each value is determined by the data (unit vector in the row space).
    identifiable: Vec<bool>,
    /// Numerical rank.
    rank: usize,
}

impl LsSolution {
    fn empty() -> Self {
        Self {
            cols: Vec::new(),
            x: Vec::new(),
            identifiable: Vec::new(),
            rank: 0,
        }
    }
}

/// Minimum-norm least squares `A x ≈ t` over columns `which` of `cols`, by SVD of the
/// column-equilibrated matrix with relative rank tolerance `rtol`.
fn least_squares(cols: &[Vec<f64>], which: &[usize], t: &[f64], rtol: f64) -> LsSolution {
    let n = t.len();
    let k = which.len();
    if n == 0 || k == 0 {
        return LsSolution {
            cols: which.to_vec(),
            x: vec![0.0; k],
            identifiable: vec![false; k],
            rank: 0,
        };
    }
    let norms: Vec<f64> = which
        .iter()
        .map(|&j| {
            let s = cols[j].iter().map(|v| v * v).sum::<f64>().sqrt();
            if s > 0.0 && s.is_finite() { s } else { 1.0 }
        })
        .collect();
    let a = DMatrix::from_fn(n, k, |i, c| cols[which[c]][i] / norms[c]);
    let b = DVector::from_column_slice(t);
    let svd = a.svd(true, true);
    let (Some(u), Some(v_t)) = (svd.u.as_ref(), svd.v_t.as_ref()) else {
        return LsSolution {
            cols: which.to_vec(),
            x: vec![0.0; k],
            identifiable: vec![false; k],
            rank: 0,
        };
    };
    let s = &svd.singular_values;
    let smax = s.iter().copied().fold(0.0, f64::max);
    let mut xs = DVector::<f64>::zeros(k);
    let mut row_space = vec![0.0; k];
    let mut rank = 0;
    for i in 0..s.len() {
        if smax > 0.0 && s[i] > rtol * smax {
            rank += 1;
            let coef = u.column(i).dot(&b) / s[i];
            for c in 0..k {
                xs[c] += coef * v_t[(i, c)];
                row_space[c] += v_t[(i, c)] * v_t[(i, c)];
            }
        }
    }
    LsSolution {
        cols: which.to_vec(),
        x: (0..k).map(|c| finite_or(xs[c] / norms[c], 0.0)).collect(),
        identifiable: row_space.iter().map(|&r| r >= 1.0 - 1e-6).collect(),
        rank,
    }
}
