//! The models of reverse-reprojection caching (paper 002, §4.2-4.3), fitted to what a session replay
//! measured, so that the selector can predict error and frame time for any node and refresh period Δn
//! without rendering again.
//!
//! - [`fit_error`]: per node, `ε̂(Δn) = α (1 − e^(−λ (Δn − 1)))` by Nelder–Mead (eq. 2);
//! - [`fit_hit_rate`]: per shader and session, `γ(Δn) = µ (1 − 1/Δn)` in closed form (eq. 4);
//! - [`fit_timing`]: per node, `t = h·E[hit] + m·E[miss] + E[overhead]` by least squares (eq. 3),
//!   giving the per-pixel time `r̂(Δn) = γ·E[hit] + (1 − γ)·E[miss]` (eq. 5) and the frame time
//!   `t̂(Δn) = E[overhead] + M·r̂(Δn)`.
//!
//! Every fit is plain data (serde) that goes into the profile JSON. A fit never yields NaN or
//! infinity: one that cannot be made says why in its status and leaves its parameters `None` (or
//! finite but unusable, see each `is_usable`).

mod error_model;
mod hit_rate;
pub mod journal;
pub mod metric;
pub mod motion;
pub mod profile;
pub mod speedup;
mod stats;
mod timing;

pub use error_model::{
    ErrorFit, ErrorFitFailure, ErrorFitOptions, ErrorFitStatus, LAMBDA_MAX, LAMBDA_MIN, fit_error,
};
pub use hit_rate::{HitRateFit, HitRateFitFailure, HitRateStatus, fit_hit_rate};
pub use metric::Metric;
pub use profile::{PROFILE_KIND, PROFILE_VERSION, Profile, content_hash};
pub use timing::{
    FrameTiming, TimingFit, TimingFitFailure, TimingFitOptions, TimingParam, TimingStatus,
    TimingWarning, fit_timing, fit_timing_with_holdout, fit_timing_with_options,
};

/// Predicted frame time `t̂(Δn) = E[overhead] + M·r̂(Δn)` in milliseconds for a node with timing fit
/// `timing` at refresh period `delta_n`, with `mean_pixels` (M) shaded pixels per frame.
///
/// `None` when either fit is not usable or the inputs are not finite.
pub fn predicted_frame_ms(
    timing: &TimingFit,
    hit_rate: &HitRateFit,
    delta_n: f64,
    mean_pixels: f64,
) -> Option<f64> {
    let gamma = hit_rate.gamma(delta_n)?;
    timing.frame_ms(gamma, mean_pixels)
}
