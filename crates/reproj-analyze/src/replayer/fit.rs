//! From replays to the profile: one replay of a variant read as a measurement, and a subject's
//! measurements fitted (error and timing models, the held-out check) into its status.

use std::time::Instant;

use reproj_metrics::{FrameValue, MetricSummary, RenderReport};
use reproj_models::profile::{AnalysisTime, HoldoutCheck, Measurement, NodeStatus};
use reproj_models::{
    ErrorFit, ErrorFitOptions, ErrorFitStatus, FrameTiming, TimingFit, TimingStatus, fit_error,
    fit_timing_with_holdout, predicted_frame_ms,
};
use reproj_replay::{RenderOptions, Renderer, VariantInput};

use super::{finite, mean};
use crate::input::AnalyzeInput;
use crate::journal::ReplayResult;
use crate::options::AnalyzeOptions;

/// The fits of one node's (or set's) replays and its status.
pub(crate) struct Fitted {
    pub(crate) error_fit: ErrorFit,
    pub(crate) flip_fit: Option<ErrorFit>,
    pub(crate) dssim_fit: Option<ErrorFit>,
    pub(crate) timing_fit: TimingFit,
    pub(crate) holdout: Vec<HoldoutCheck>,
    pub(crate) status: NodeStatus,
}

/// Fit the error models (L2, ꟻLIP, 1 − SSIM) to the measurements at the training periods and the
/// timing model to their frames, check both at the held-out periods, and say whether the result
/// is usable (`failure`: why the replays already set it aside).
pub(crate) fn fit_replays(
    measurements: &[Measurement],
    failure: Option<&str>,
    opts: &AnalyzeOptions,
    hit_rate: &reproj_models::HitRateFit,
    mean_pixels: f64,
) -> Fitted {
    let is_train = |m: &Measurement| crate::options::is_training(opts, m.delta_n);
    let train: Vec<&Measurement> = measurements.iter().filter(|m| is_train(m)).collect();
    let held: Vec<&Measurement> = measurements.iter().filter(|m| !is_train(m)).collect();
    let error_fit = fit_error(
        &train
            .iter()
            .map(|m| (m.delta_n as f64, m.error))
            .collect::<Vec<_>>(),
        &ErrorFitOptions::default(),
    );
    let flip_fit = fit_metric(&train, |m| m.flip.map(|s| s.mean));
    let dssim_fit = fit_metric(&train, |m| m.ssim.map(|s| 1.0 - s.mean));
    let frames = |ms: &[&Measurement]| -> Vec<FrameTiming> {
        ms.iter().flat_map(|m| m.frames.iter().copied()).collect()
    };
    let timing_fit = fit_timing_with_holdout(&frames(&train), &frames(&held));
    let holdout = held
        .iter()
        .map(|m| HoldoutCheck {
            delta_n: m.delta_n,
            measured_error: m.error,
            predicted_error: error_fit
                .predict(m.delta_n as f64)
                .filter(|v| v.is_finite()),
            measured_ms: m.frame_ms,
            predicted_ms: predicted_frame_ms(&timing_fit, hit_rate, m.delta_n as f64, mean_pixels)
                .filter(|v| v.is_finite()),
            measured_flip: m.flip.map(|s| s.mean),
            predicted_flip: flip_fit
                .as_ref()
                .and_then(|f| f.predict(m.delta_n as f64))
                .filter(|v| v.is_finite()),
        })
        .collect();
    let status = status(failure, &error_fit, &timing_fit);
    Fitted {
        error_fit,
        flip_fit,
        dssim_fit,
        timing_fit,
        holdout,
        status,
    }
}

/// Replay one variant at `delta_n`: its measurement and mean per-pass times (frame 0 excluded).
#[allow(clippy::too_many_arguments)]
pub(super) fn replay(
    renderer: &Renderer,
    input: &AnalyzeInput,
    sources: &[String],
    variant: &reproj_instance::Variant,
    delta_n: u32,
    reference: &reproj_replay::Reference,
    render_opts: &RenderOptions,
    time: &mut AnalysisTime,
) -> ReplayResult {
    let input_variant = VariantInput::new(sources.to_vec(), variant.manifest.clone(), delta_n);
    let t = Instant::now();
    let report = renderer
        .render_variant(
            input.shader,
            input.session,
            &input_variant,
            reference,
            render_opts,
        )
        .map_err(|e| e.to_string())?;
    let wall = t.elapsed().as_secs_f64();
    if let Some(first) = report.frames.iter().find(|f| f.nonfinite > 0) {
        // A NaN must never be scored as no error: such a variant cannot be chosen.
        return Err(format!(
            "its variant renders {} pixels that are NaN or infinite where the original is finite (Δn {delta_n}, first in frame {})",
            report.nonfinite_pixels, first.frame
        ));
    }
    if !report.error.is_finite() {
        return Err(format!(
            "its measured error is {} (Δn {delta_n})",
            report.error
        ));
    }
    let gpu: f64 = report.frames.iter().map(|f| f.frame_ms).sum::<f64>() / 1000.0;
    time.rendering_s += gpu.min(wall);
    time.readback_and_error_s += (wall - gpu).max(0.0);
    let frames: Vec<_> = report.frames.iter().skip(1).collect();
    let passes = frames.first().map_or(0, |f| f.pass_ms.len());
    let pass_ms = (0..passes)
        .map(|i| {
            finite(mean(
                frames
                    .iter()
                    .map(|f| f.pass_ms.get(i).copied().unwrap_or(0.0)),
            ))
        })
        .collect();
    Ok((measurement(delta_n, &report), pass_ms))
}

/// The error model fitted to one metric's means at the training periods; `None` when a
/// measurement lacks the metric.
fn fit_metric(
    train: &[&Measurement],
    value: impl Fn(&Measurement) -> Option<f64>,
) -> Option<ErrorFit> {
    let samples: Option<Vec<(f64, f64)>> = train
        .iter()
        .map(|m| Some((m.delta_n as f64, value(m)?)))
        .collect();
    Some(fit_error(&samples?, &ErrorFitOptions::default()))
}

fn measurement(delta_n: u32, report: &RenderReport) -> Measurement {
    let frames: Vec<FrameTiming> = report
        .frames
        .iter()
        .skip(1)
        .map(|f| FrameTiming {
            hits: f.hits,
            misses: f.recomputes,
            time_ms: finite(f.frame_ms),
        })
        .collect();
    Measurement {
        delta_n,
        error: finite(report.error),
        error_worst: report.error_worst.map(finite_frame),
        flip: report.flip.map(finite_summary),
        ssim: report.ssim.map(finite_summary),
        mse: report.mse.is_finite().then_some(report.mse),
        psnr: (report.psnr.is_finite() && report.psnr < reproj_metrics::PSNR_CAP)
            .then_some(report.psnr),
        hit_rate: finite(report.hit_rate),
        frame_ms: finite(report.frame_ms),
        frames,
        frame_errors: report.frames.iter().map(|f| finite(f.error)).collect(),
    }
}

/// The replay's worst frame as the profile keeps it: a value that is not finite becomes 0.
fn finite_frame(v: FrameValue) -> FrameValue {
    FrameValue {
        value: finite(v.value),
        ..v
    }
}

/// The replay's summary of a metric as the profile keeps it: no NaN or infinity.
fn finite_summary(s: MetricSummary) -> MetricSummary {
    MetricSummary {
        mean: finite(s.mean),
        worst: finite_frame(s.worst),
        ..s
    }
}

fn status(failure: Option<&str>, error: &ErrorFit, timing: &TimingFit) -> NodeStatus {
    if let Some(f) = failure {
        return NodeStatus::SetAside {
            reason: f.to_string(),
        };
    }
    if let ErrorFitStatus::Failed { reason } = &error.status {
        return NodeStatus::SetAside {
            reason: format!("error model: {reason}"),
        };
    }
    if !timing.is_usable() {
        let why = match &timing.status {
            TimingStatus::Failed { reason } => reason.to_string(),
            TimingStatus::RankDeficient { undetermined, .. } => {
                format!("rank-deficient timing system, undetermined: {undetermined:?}")
            }
            TimingStatus::Ok => "unusable".to_string(),
        };
        return NodeStatus::SetAside {
            reason: format!("timing model: {why}"),
        };
    }
    NodeStatus::Ok
}
