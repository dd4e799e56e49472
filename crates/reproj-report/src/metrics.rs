//! The error metrics the report shows. Each source lists what it has in one small function; a
//! metric added to the profile or the replay is one line here and appears everywhere in the page
//! (the selection panel, the frames' captions and the table of measurements).

use reproj_metrics::RenderReport;
use reproj_models::profile::Measurement;
use serde::Serialize;

/// One metric's value, with how to print it.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Metric {
    /// Short name shown in the page (`error`, `PSNR`).
    pub name: &'static str,
    /// `None` where the source has no value (PSNR of identical frames).
    pub value: Option<f64>,
    /// Unit after the value (`dB`), or empty.
    pub unit: &'static str,
    /// Decimals to print.
    pub decimals: u32,
}

/// The metrics of one replay measured by `analyze` (a profile's measurement).
pub fn of_measurement(m: &Measurement) -> Vec<Metric> {
    vec![
        error(m.error),
        psnr(m.psnr),
        flip(m.flip.as_ref().map(|f| f.mean)),
        flip_worst(m.flip.as_ref().map(|f| f.worst.value)),
        ssim(m.ssim.as_ref().map(|f| f.mean)),
    ]
}

/// The metrics of one replay rendered by the report.
pub fn of_render(r: &RenderReport) -> Vec<Metric> {
    vec![
        error(r.error),
        psnr(Some(r.psnr)),
        flip(r.flip.as_ref().map(|f| f.mean)),
        flip_worst(r.flip.as_ref().map(|f| f.worst.value)),
        ssim(r.ssim.as_ref().map(|f| f.mean)),
    ]
}

/// A metric's value (`None` when missing or not finite), with how to print it.
fn metric(name: &'static str, value: Option<f64>, unit: &'static str, decimals: u32) -> Metric {
    Metric {
        name,
        value: value.filter(|v| v.is_finite()),
        unit,
        decimals,
    }
}

/// The paper's mean per-pixel L2 error.
fn error(value: f64) -> Metric {
    metric("error", Some(value), "", 5)
}

/// Mean ꟻLIP over the covered pixels (`docs/SCHEMAS.md`).
fn flip(value: Option<f64>) -> Metric {
    metric("ꟻLIP", value, "", 4)
}

/// ꟻLIP of the worst frame: a stale highlight or refresh speckle shows here first.
fn flip_worst(value: Option<f64>) -> Metric {
    metric("ꟻLIP worst frame", value, "", 4)
}

/// Mean SSIM over the covered pixels.
fn ssim(value: Option<f64>) -> Metric {
    metric("SSIM", value, "", 4)
}

fn psnr(value: Option<f64>) -> Metric {
    metric("PSNR", value, "dB", 2)
}
