//! Error model (paper §4.2, eq. 2): `ε̂(Δn) = α (1 − e^(−λ (Δn − 1)))`, one (α, λ) per node.
//!
//! The measured error (mean per-pixel L2 RGB distance to the original, averaged over the session)
//! rises with Δn at an exponentially decaying rate. We fit α and λ by Nelder–Mead (argmin) in the
//! log-parameters `(ln(α/s), ln λ)`, s the largest measured error, which keeps α > 0 and λ > 0 and
//! makes the cost scale-free. λ is kept in `[LAMBDA_MIN, LAMBDA_MAX]`: a node whose error is already
//! saturated at the smallest Δn gets `λ = LAMBDA_MAX` (a step), one whose error grows linearly over
//! the sampled range gets `λ = LAMBDA_MIN` with a large α. Curves the model cannot describe (error
//! falling with Δn, an unexplained non-monotone pattern) are reported as failures.

use argmin::core::{CostFunction, Executor, State, TerminationReason};
use argmin::solver::neldermead::NelderMead;
use serde::{Deserialize, Serialize};

use crate::stats::{r_squared, rms_residual};

/// Smallest λ the fit reports (about a linear rise over Δn ≤ 50).
pub const LAMBDA_MIN: f64 = 1e-4;
/// Largest λ the fit reports (a step: ε̂(Δn) = α for every Δn ≥ 2).
pub const LAMBDA_MAX: f64 = 100.0;

/// Bounds of `ln(α / s)`, s = the largest measured error.
const LN_ALPHA_REL_MIN: f64 = -13.815_510_557_964_274; // ln 1e-6
const LN_ALPHA_REL_MAX: f64 = 13.815_510_557_964_274; // ln 1e6
/// Cost given to a parameter vector whose cost is not finite.
const NON_FINITE_PENALTY: f64 = 1e30;

/// Options of [`fit_error`].
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default)]
pub struct ErrorFitOptions {
    /// Nelder–Mead iteration limit per start.
    pub max_iters: u64,
    /// Convergence: standard deviation of the simplex's costs (cost = mean squared residual
    /// divided by the squared largest error).
    pub sd_tolerance: f64,
    /// Fewest distinct Δn > 1 needed (two parameters, so at least 2; 3 gives a check).
    pub min_distinct_delta_n: usize,
    /// A fit with R² below this *and* a relative RMS residual above `max_relative_rms` fails as
    /// not exponential.
    pub min_r2: f64,
    /// RMS residual relative to the mean measured error above which a low-R² fit fails.
    pub max_relative_rms: f64,
    /// The error falling with Δn by more than this fraction of the largest error (by the slope of a
    /// straight line fitted over the sampled range) fails as not exponential.
    pub max_relative_decrease: f64,
    /// Errors all at or below this are a node that never changes: α = 0, Ok.
    pub zero_tolerance: f64,
}

impl Default for ErrorFitOptions {
    fn default() -> Self {
        Self {
            max_iters: 2000,
            sd_tolerance: 1e-13,
            min_distinct_delta_n: 3,
            min_r2: 0.5,
            max_relative_rms: 0.1,
            max_relative_decrease: 0.25,
            zero_tolerance: 1e-12,
        }
    }
}

/// Why an error fit failed.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, thiserror::Error)]
#[serde(tag = "kind", rename_all = "snake_case")]
pub enum ErrorFitFailure {
    /// No samples.
    #[error("no error samples")]
    Empty,
    /// Some Δn or error is NaN or infinite.
    #[error("{count} sample(s) with a NaN or infinite Δn or error")]
    NonFiniteInput {
        /// How many samples were not finite.
        count: usize,
    },
    /// A Δn below 1.
    #[error("refresh period Δn = {value} is below 1")]
    InvalidDeltaN {
        /// The offending Δn.
        value: f64,
    },
    /// A negative error (an L2 distance cannot be).
    #[error("negative error {value}")]
    NegativeError {
        /// The offending error.
        value: f64,
    },
    /// Not enough distinct Δn > 1 to determine α and λ.
    #[error("only {found} distinct Δn > 1, need {required}")]
    TooFewDistinctDeltaN {
        /// Distinct Δn > 1 in the samples.
        found: usize,
        /// [`ErrorFitOptions::min_distinct_delta_n`].
        required: usize,
    },
    /// The error falls with Δn: not the exponential rise of eq. 2.
    #[error(
        "not exponential: error decreases with Δn (by {relative_decrease:.2} of its maximum over the range)"
    )]
    Decreasing {
        /// Drop over the sampled range relative to the largest error.
        relative_decrease: f64,
    },
    /// The model does not explain the data (low R² and large residual).
    #[error("not exponential: R² = {r2:.3}, RMS residual {relative_rms:.3} of the mean error")]
    PoorFit {
        /// R² of the best fit.
        r2: f64,
        /// RMS residual relative to the mean measured error.
        relative_rms: f64,
    },
    /// Nelder–Mead hit its iteration limit (after one restart).
    #[error("Nelder–Mead did not converge in {iterations} iterations")]
    DidNotConverge {
        /// Iterations spent.
        iterations: u64,
    },
}

/// Status of an [`ErrorFit`].
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(tag = "status", rename_all = "snake_case")]
pub enum ErrorFitStatus {
    /// The fit is usable.
    Ok,
    /// The fit is not usable; the node is set aside.
    Failed {
        /// Why.
        reason: ErrorFitFailure,
    },
}

/// Fitted error model of one node.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ErrorFit {
    /// α: the error the node saturates at. `Some(0.0)` for a node that never changes.
    pub alpha: Option<f64>,
    /// λ: the rate of the rise, in `[LAMBDA_MIN, LAMBDA_MAX]`; `Some(0.0)` when α = 0 (undetermined
    /// and irrelevant).
    pub lambda: Option<f64>,
    /// R² of the fit over the samples.
    pub r2: Option<f64>,
    /// RMS residual, in error units.
    pub rms_residual: Option<f64>,
    /// Samples given.
    pub n_samples: usize,
    /// Nelder–Mead iterations spent (all starts).
    pub iterations: u64,
    /// Ok, or why not.
    pub status: ErrorFitStatus,
}

impl ErrorFit {
    /// Whether the status is Ok (and so the parameters are present and finite).
    pub fn is_ok(&self) -> bool {
        matches!(self.status, ErrorFitStatus::Ok)
    }

    /// ε̂(Δn) from the fitted parameters, when present (also for a failed fit that has them: check
    /// [`Self::is_ok`]). `None` for Δn < 1 or not finite.
    pub fn predict(&self, delta_n: f64) -> Option<f64> {
        let (alpha, lambda) = (self.alpha?, self.lambda?);
        if !delta_n.is_finite() || delta_n < 1.0 {
            return None;
        }
        let e = model(alpha, lambda, delta_n);
        e.is_finite().then_some(e)
    }

    /// A fit that failed before any parameter was computed.
    fn failed(n_samples: usize, reason: ErrorFitFailure) -> Self {
        Self {
            alpha: None,
            lambda: None,
            r2: None,
            rms_residual: None,
            n_samples,
            iterations: 0,
            status: ErrorFitStatus::Failed { reason },
        }
    }
}

/// Eq. 2.
fn model(alpha: f64, lambda: f64, delta_n: f64) -> f64 {
    alpha * (1.0 - (-lambda * (delta_n - 1.0)).exp())
}

/// Cost of `(ln(α/s), ln λ)`: mean squared residual over s², plus a quadratic penalty outside the
/// bounds (the model is evaluated at the clamped point).
#[derive(Debug)]
struct ErrorCost<'a> {
    samples: &'a [(f64, f64)],
    scale: f64,
}

impl ErrorCost<'_> {
    fn clamp(p: &[f64]) -> (f64, f64, f64) {
        let a = p[0].clamp(LN_ALPHA_REL_MIN, LN_ALPHA_REL_MAX);
        let b = p[1].clamp(LAMBDA_MIN.ln(), LAMBDA_MAX.ln());
        let penalty = (p[0] - a).powi(2) + (p[1] - b).powi(2);
        (
            a,
            b,
            if penalty.is_finite() {
                penalty
            } else {
                NON_FINITE_PENALTY
            },
        )
    }

    fn params(&self, p: &[f64]) -> (f64, f64) {
        let (a, b, _) = Self::clamp(p);
        (self.scale * a.exp(), b.exp())
    }

    fn eval(&self, p: &[f64]) -> f64 {
        let (a, b, penalty) = Self::clamp(p);
        let (alpha, lambda) = (self.scale * a.exp(), b.exp());
        let n = self.samples.len() as f64;
        let ss: f64 = self
            .samples
            .iter()
            .map(|&(dn, e)| ((model(alpha, lambda, dn) - e) / self.scale).powi(2))
            .sum();
        let c = ss / n + penalty;
        if c.is_finite() { c } else { NON_FINITE_PENALTY }
    }
}

impl CostFunction for ErrorCost<'_> {
    type Param = Vec<f64>;
    type Output = f64;

    fn cost(&self, p: &Self::Param) -> Result<Self::Output, argmin::core::Error> {
        Ok(self.eval(p))
    }
}

/// One Nelder–Mead run: (best params, best cost, converged, iterations).
fn nelder_mead(
    cost: &ErrorCost<'_>,
    start: [f64; 2],
    opts: &ErrorFitOptions,
) -> Option<(Vec<f64>, f64, bool, u64)> {
    let simplex = vec![
        start.to_vec(),
        vec![start[0] + 0.3, start[1]],
        vec![start[0], start[1] + 0.7],
    ];
    let solver = NelderMead::new(simplex)
        .with_sd_tolerance(opts.sd_tolerance.max(0.0))
        .ok()?;
    let problem = ErrorCost {
        samples: cost.samples,
        scale: cost.scale,
    };
    let res = Executor::new(problem, solver)
        .configure(|state| state.max_iters(opts.max_iters.max(1)))
        .run()
        .ok()?;
    let state = res.state();
    let best = state.get_best_param()?.clone();
    let best_cost = cost.eval(&best);
    let converged = matches!(
        state.get_termination_reason(),
        Some(TerminationReason::SolverConverged)
    );
    Some((best, best_cost, converged, state.get_iter()))
}

/// λ0 from the half-rise point: the Δn where the (per-Δn mean) error first reaches α0/2, linearly
/// interpolated from the previous sample (or from ε(1) = 0), solved in `1 − e^(−λ(Δn−1)) = 1/2`.
fn initial_lambda(samples: &[(f64, f64)], alpha0: f64) -> f64 {
    let mut by_dn: Vec<(f64, f64, usize)> = Vec::new();
    let mut sorted: Vec<(f64, f64)> = samples.iter().copied().filter(|s| s.0 > 1.0).collect();
    sorted.sort_by(|a, b| a.0.total_cmp(&b.0));
    for (dn, e) in sorted {
        match by_dn.last_mut() {
            Some(last) if (last.0 - dn).abs() <= 1e-9 => {
                last.1 += e;
                last.2 += 1;
            }
            _ => by_dn.push((dn, e, 1)),
        }
    }
    let half = alpha0 / 2.0;
    let mut prev = (1.0, 0.0);
    let mut dn_half = by_dn.last().map_or(2.0, |l| l.0);
    for &(dn, sum, count) in &by_dn {
        let e = sum / count as f64;
        if e >= half {
            let t = if e > prev.1 {
                ((half - prev.1) / (e - prev.1)).clamp(0.0, 1.0)
            } else {
                1.0
            };
            dn_half = prev.0 + t * (dn - prev.0);
            break;
        }
        prev = (dn, e);
    }
    let lambda0 = std::f64::consts::LN_2 / (dn_half - 1.0).max(1e-3);
    if lambda0.is_finite() {
        lambda0.clamp(LAMBDA_MIN, LAMBDA_MAX)
    } else {
        1.0
    }
}

/// Fit eq. 2 to `(Δn, error)` samples (several samples at one Δn are allowed).
///
/// Checks, in order: input (empty, non-finite, Δn < 1, negative error); all errors ≤
/// `zero_tolerance` → Ok with α = 0; too few distinct Δn > 1; then Nelder–Mead from three starts
/// (λ0 from the half-rise point, ×4, ÷4; α0 = largest error), restarting once from the best point
/// if it did not converge; then the quality checks (decreasing, poor fit, non-convergence).
pub fn fit_error(samples: &[(f64, f64)], opts: &ErrorFitOptions) -> ErrorFit {
    let n = samples.len();
    if n == 0 {
        return ErrorFit::failed(0, ErrorFitFailure::Empty);
    }
    let non_finite = samples
        .iter()
        .filter(|(dn, e)| !dn.is_finite() || !e.is_finite())
        .count();
    if non_finite > 0 {
        return ErrorFit::failed(n, ErrorFitFailure::NonFiniteInput { count: non_finite });
    }
    if let Some(&(dn, _)) = samples.iter().find(|s| s.0 < 1.0) {
        return ErrorFit::failed(n, ErrorFitFailure::InvalidDeltaN { value: dn });
    }
    if let Some(&(_, e)) = samples.iter().find(|s| s.1 < 0.0) {
        return ErrorFit::failed(n, ErrorFitFailure::NegativeError { value: e });
    }

    let observed: Vec<f64> = samples.iter().map(|s| s.1).collect();
    let scale = observed.iter().copied().fold(0.0, f64::max);
    if scale <= opts.zero_tolerance.max(0.0) {
        let fitted = vec![0.0; n];
        return ErrorFit {
            alpha: Some(0.0),
            lambda: Some(0.0),
            r2: Some(1.0),
            rms_residual: Some(rms_residual(&observed, &fitted)),
            n_samples: n,
            iterations: 0,
            status: ErrorFitStatus::Ok,
        };
    }

    let mut distinct: Vec<f64> = samples.iter().map(|s| s.0).filter(|&d| d > 1.0).collect();
    distinct.sort_by(f64::total_cmp);
    distinct.dedup_by(|a, b| (*a - *b).abs() <= 1e-9);
    let required = opts.min_distinct_delta_n.max(2);
    if distinct.len() < required {
        return ErrorFit::failed(
            n,
            ErrorFitFailure::TooFewDistinctDeltaN {
                found: distinct.len(),
                required,
            },
        );
    }

    let cost = ErrorCost { samples, scale };
    let lambda0 = initial_lambda(samples, scale);
    let mut iterations = 0;
    let mut best: Option<(Vec<f64>, f64, bool)> = None;
    for factor in [1.0, 4.0, 0.25] {
        let start = [0.0, (lambda0 * factor).clamp(LAMBDA_MIN, LAMBDA_MAX).ln()];
        if let Some((p, c, conv, it)) = nelder_mead(&cost, start, opts) {
            iterations += it;
            if best.as_ref().is_none_or(|b| c < b.1) {
                best = Some((p, c, conv));
            }
        }
    }
    if let Some((p, _, false)) = &best {
        let start = [p[0], p[1]];
        if let Some((p2, c2, conv2, it)) = nelder_mead(&cost, start, opts) {
            iterations += it;
            if conv2 || best.as_ref().is_some_and(|b| c2 <= b.1) {
                best = Some((p2, c2, conv2));
            }
        }
    }
    let Some((p, _, converged)) = best else {
        return ErrorFit {
            iterations,
            ..ErrorFit::failed(n, ErrorFitFailure::DidNotConverge { iterations })
        };
    };

    let (alpha, lambda) = cost.params(&p);
    let fitted: Vec<f64> = samples
        .iter()
        .map(|&(dn, _)| model(alpha, lambda, dn))
        .collect();
    let r2 = r_squared(&observed, &fitted);
    let rms = rms_residual(&observed, &fitted);
    let mean = observed.iter().sum::<f64>() / n as f64;

    let failure = if let Some(drop) =
        relative_decrease(samples, scale).filter(|&d| d > opts.max_relative_decrease)
    {
        Some(ErrorFitFailure::Decreasing {
            relative_decrease: drop,
        })
    } else if r2 < opts.min_r2 && rms > opts.max_relative_rms * mean {
        Some(ErrorFitFailure::PoorFit {
            r2,
            relative_rms: if mean > 0.0 { rms / mean } else { 0.0 },
        })
    } else if !converged {
        Some(ErrorFitFailure::DidNotConverge { iterations })
    } else {
        None
    };

    let finite = alpha.is_finite() && lambda.is_finite();
    ErrorFit {
        alpha: finite.then_some(alpha),
        lambda: finite.then_some(lambda),
        r2: Some(r2),
        rms_residual: Some(rms),
        n_samples: n,
        iterations,
        status: match failure {
            Some(reason) => ErrorFitStatus::Failed { reason },
            None if !finite => ErrorFitStatus::Failed {
                reason: ErrorFitFailure::DidNotConverge { iterations },
            },
            None => ErrorFitStatus::Ok,
        },
    }
}

/// Drop of a least-squares line over the sampled Δn > 1 range, relative to `scale`; `None` when
/// the line rises (or cannot be fitted).
fn relative_decrease(samples: &[(f64, f64)], scale: f64) -> Option<f64> {
    let pts: Vec<(f64, f64)> = samples.iter().copied().filter(|s| s.0 > 1.0).collect();
    let n = pts.len() as f64;
    if pts.len() < 2 || scale <= 0.0 {
        return None;
    }
    let mx = pts.iter().map(|p| p.0).sum::<f64>() / n;
    let my = pts.iter().map(|p| p.1).sum::<f64>() / n;
    let sxx: f64 = pts.iter().map(|p| (p.0 - mx).powi(2)).sum();
    let sxy: f64 = pts.iter().map(|p| (p.0 - mx) * (p.1 - my)).sum();
    if sxx <= 0.0 {
        return None;
    }
    let slope = sxy / sxx;
    let (lo, hi) = pts
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), p| {
            (lo.min(p.0), hi.max(p.0))
        });
    let drop = -slope * (hi - lo) / scale;
    (drop.is_finite() && drop > 0.0).then_some(drop)
}
