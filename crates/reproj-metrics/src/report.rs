//! The render report: per-frame records and session summaries of error, PSNR, hit rate and frame
//! time (`reproj render --json`, schema in `docs/SCHEMAS.md`), and the per-metric summary (mean,
//! worst frame) the profile keeps. Built on [`crate::l2`].

use serde::{Deserialize, Serialize};

use crate::l2::{mean, mse, psnr};

/// How frame times were measured.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum TimingMethod {
    /// GPU timestamp queries at the start of the first pass and the end of the last.
    GpuTimestamps,
    /// CPU wall time around queue submit + wait for completion (adapter has no timestamp queries).
    CpuSubmitWait,
}

/// The adapter a result was measured on.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct AdapterReport {
    pub name: String,
    pub backend: String,
    pub device_type: String,
    pub driver: String,
    pub driver_info: String,
}

impl AdapterReport {
    /// A CPU rasterizer (lavapipe, llvmpipe): its frames are in host memory, and its speed
    /// figures say nothing of a GPU's.
    pub fn is_cpu_rasterizer(&self) -> bool {
        self.device_type.eq_ignore_ascii_case("cpu")
            || self.name.contains("llvmpipe")
            || self.name.contains("lavapipe")
    }
}

/// One frame's measurements.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct FrameRecord {
    pub frame: u32,
    /// Frame time in milliseconds by the report's timing method.
    pub frame_ms: f64,
    /// CPU wall time around submit + wait, always measured. With GPU timestamps frames are read
    /// back in batches (see `render`), and this is the batch's submit + wait time per frame.
    pub cpu_ms: f64,
    /// Per-pass GPU times (ms): one for the original, three for a variant; empty without
    /// timestamps.
    pub pass_ms: Vec<f64>,
    /// Fragments that passed the depth test in the shading pass (occlusion query): the shaded
    /// pixels (original: includes overdraw).
    pub shaded: u64,
    /// Variant: fragments kept by pass 1 (occlusion query), i.e. cache hits.
    pub hits: u64,
    /// Variant: fragments pass 2 recomputed (occlusion query): misses + refreshes.
    pub recomputes: u64,
    /// Variant with classification: visible pixels that hit, missed (off-screen or disoccluded) and
    /// were refreshed, from the `reproj_classify` map.
    pub hit_px: Option<u64>,
    pub miss_px: Option<u64>,
    pub refresh_px: Option<u64>,
    /// hits / shaded pixels (classification counts when available, else occlusion counts).
    pub hit_rate: f64,
    /// Mean per-pixel L2 RGB distance to the reference over all pixels.
    pub error: f64,
    /// Mean squared RGB difference to the reference over the covered pixels (each channel
    /// clamped to [0, 1]): squared error / (3 × `covered`); 0 when nothing is covered.
    #[serde(default)]
    pub mse: f64,
    /// Pixels where the reference frame has geometry (its depth < 1).
    #[serde(default)]
    pub covered: u64,
    /// PSNR of `mse` in dB, `10 log10(1 / mse)`, capped at 100.
    pub psnr: f64,
    /// Largest per-channel absolute difference to the reference.
    pub max_abs_diff: f64,
    /// Pixels whose RGB holds a NaN or an infinity where the reference's does not: the frame's
    /// error is NaN when any is (the original: all its non-finite pixels).
    #[serde(default, skip_serializing_if = "is_zero")]
    pub nonfinite: u64,
    /// Pixels whose reference RGB holds a NaN or an infinity: left out of every sum (no error
    /// can be measured against them).
    #[serde(default, skip_serializing_if = "is_zero")]
    pub nonfinite_reference: u64,
    /// Mean ꟻLIP error over the covered pixels ([`crate::perceptual`]); only on the frames the
    /// perceptual metrics were computed for (`RenderOptions::perceptual_stride`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub flip: Option<f64>,
    /// Mean SSIM over the covered pixels, on the same frames as `flip`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub ssim: Option<f64>,
}

fn is_zero(n: &u64) -> bool {
    *n == 0
}

/// One frame's value of a metric.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct FrameValue {
    pub frame: u32,
    pub value: f64,
}

/// A metric over the frames of a replay it was computed on: the mean, and the worst frame (the
/// largest error; for SSIM, a similarity, the smallest value), so that a temporal artifact one
/// mean hides (a stale highlight, a refresh pattern) shows.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct MetricSummary {
    pub mean: f64,
    pub worst: FrameValue,
    /// Frames it was computed on.
    pub frames: u32,
}

impl MetricSummary {
    /// The summary of `(frame, value)` pairs; the worst is the first frame with the largest value,
    /// or the smallest with `lower_is_worse`. `None` without values.
    pub fn of(values: impl Iterator<Item = (u32, f64)>, lower_is_worse: bool) -> Option<Self> {
        let mut sum = 0.0;
        let mut frames = 0u32;
        let mut worst: Option<FrameValue> = None;
        for (frame, value) in values {
            sum += value;
            frames += 1;
            let worse = worst.is_none_or(|w| {
                if lower_is_worse {
                    value < w.value
                } else {
                    value > w.value
                }
            });
            if worse {
                worst = Some(FrameValue { frame, value });
            }
        }
        Some(MetricSummary {
            mean: sum / f64::from(frames.max(1)),
            worst: worst?,
            frames,
        })
    }
}

/// Schema name of a [`RenderReport`] (`reproj render --json`).
pub const RENDER_REPORT_SCHEMA: &str = "reproj.render";
/// Version of the [`RenderReport`] schema. Bump on any incompatible change.
/// Version 2: `error_worst`, `flip` and `ssim` (and per frame `flip`, `ssim`).
pub const RENDER_REPORT_VERSION: u32 = 2;

fn render_report_schema() -> String {
    RENDER_REPORT_SCHEMA.into()
}

fn first_version() -> u32 {
    1
}

/// Result of rendering a session: the original (reference) or a variant. Printed by
/// `reproj render --json` (schema in `docs/SCHEMAS.md`).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct RenderReport {
    /// Always [`RENDER_REPORT_SCHEMA`] (absent before version 1: read as version 1).
    #[serde(default = "render_report_schema")]
    pub schema: String,
    #[serde(default = "first_version")]
    pub version: u32,
    /// `"original"` or `"variant"`.
    pub kind: String,
    pub shader: String,
    pub entry: String,
    pub session: String,
    pub resolution: [u32; 2],
    pub adapter: AdapterReport,
    pub timing: TimingMethod,
    /// Variant parameters (absent for the original).
    #[serde(skip_serializing_if = "Option::is_none", default)]
    pub node: Option<String>,
    #[serde(skip_serializing_if = "Option::is_none", default)]
    pub delta_n: Option<u32>,
    #[serde(skip_serializing_if = "Option::is_none", default)]
    pub block: Option<u32>,
    #[serde(skip_serializing_if = "Option::is_none", default)]
    pub depth_epsilon: Option<f32>,
    /// Mean error over all frames (0 for the original).
    pub error: f64,
    /// The frame with the largest error (absent before version 2 and without frames).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub error_worst: Option<FrameValue>,
    /// ꟻLIP over the covered pixels, over the frames it was computed on (variants with perceptual
    /// metrics only).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub flip: Option<MetricSummary>,
    /// SSIM over the covered pixels, on the same frames as `flip`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub ssim: Option<MetricSummary>,
    /// Mean squared RGB error over the covered pixels of all frames, pooled: total squared error
    /// / (3 × total covered pixels) (0 for the original).
    #[serde(default)]
    pub mse: f64,
    /// PSNR of `mse` (capped at 100): not a mean of the per-frame PSNRs.
    pub psnr: f64,
    /// Mean hit rate over frames 1.. (0 for the original).
    pub hit_rate: f64,
    /// Mean frame time over frames 1.. (frame 0 pays shader compilation), ms.
    pub frame_ms: f64,
    /// Mean CPU submit+wait time over frames 1.., ms.
    pub cpu_ms: f64,
    /// Pixels, over all frames, whose color is not finite (NaN or ±∞) where the reference's
    /// is; any makes a variant's `error` NaN. For the original: all its non-finite pixels.
    #[serde(default, skip_serializing_if = "is_zero")]
    pub nonfinite_pixels: u64,
    /// Pixels, over all frames, whose reference color is not finite: the original shader's own
    /// NaN or ∞, left out of the error (variants only).
    #[serde(default, skip_serializing_if = "is_zero")]
    pub nonfinite_reference_pixels: u64,
    pub frames: Vec<FrameRecord>,
}

impl RenderReport {
    /// Recompute the session means from `frames`.
    pub fn summarize(&mut self) {
        let all = &self.frames;
        let after0: Vec<&FrameRecord> = if all.len() > 1 {
            all[1..].iter().collect()
        } else {
            all.iter().collect()
        };
        self.error = mean(all.iter().map(|f| f.error));
        self.error_worst =
            MetricSummary::of(all.iter().map(|f| (f.frame, f.error)), false).map(|s| s.worst);
        self.flip = MetricSummary::of(all.iter().filter_map(|f| Some((f.frame, f.flip?))), false);
        self.ssim = MetricSummary::of(all.iter().filter_map(|f| Some((f.frame, f.ssim?))), true);
        // Pooled over the frames: each frame's squared error is its MSE × 3 × covered pixels.
        let sum_sq: f64 = all.iter().map(|f| f.mse * 3.0 * f.covered as f64).sum();
        let covered: u64 = all.iter().map(|f| f.covered).sum();
        self.mse = mse(sum_sq, covered);
        self.psnr = psnr(self.mse);
        self.hit_rate = mean(after0.iter().map(|f| f.hit_rate));
        self.frame_ms = mean(after0.iter().map(|f| f.frame_ms));
        self.cpu_ms = mean(after0.iter().map(|f| f.cpu_ms));
        self.nonfinite_pixels = all.iter().map(|f| f.nonfinite).sum();
        self.nonfinite_reference_pixels = all.iter().map(|f| f.nonfinite_reference).sum();
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn record(mse: f64, covered: u64, error: f64) -> FrameRecord {
        FrameRecord {
            frame: 0,
            frame_ms: 1.0,
            cpu_ms: 1.0,
            pass_ms: Vec::new(),
            shaded: covered,
            hits: 0,
            recomputes: 0,
            hit_px: None,
            miss_px: None,
            refresh_px: None,
            hit_rate: 0.0,
            error,
            mse,
            covered,
            psnr: psnr(mse),
            max_abs_diff: 0.0,
            nonfinite: 0,
            nonfinite_reference: 0,
            flip: None,
            ssim: None,
        }
    }

    #[test]
    fn session_psnr_pools_the_squared_error() {
        let mut report = RenderReport {
            schema: RENDER_REPORT_SCHEMA.into(),
            version: RENDER_REPORT_VERSION,
            kind: "variant".into(),
            shader: String::new(),
            entry: String::new(),
            session: String::new(),
            resolution: [2, 2],
            adapter: AdapterReport {
                name: String::new(),
                backend: String::new(),
                device_type: String::new(),
                driver: String::new(),
                driver_info: String::new(),
            },
            timing: TimingMethod::CpuSubmitWait,
            node: None,
            delta_n: None,
            block: None,
            depth_epsilon: None,
            error: 0.0,
            error_worst: None,
            flip: None,
            ssim: None,
            mse: 0.0,
            psnr: 0.0,
            hit_rate: 0.0,
            frame_ms: 0.0,
            nonfinite_pixels: 0,
            nonfinite_reference_pixels: 0,
            cpu_ms: 0.0,
            frames: vec![record(0.0, 100, 0.0), record(0.01, 300, 0.2)],
        };
        report.summarize();
        // 0.01 × 300 of the 400 covered pixels: 0.0075, not the mean of 100 dB and 20 dB.
        assert!((report.mse - 0.0075).abs() < 1e-15);
        assert!((report.psnr - 10.0 * (1.0 / 0.0075f64).log10()).abs() < 1e-12);
        assert!((report.error - 0.1).abs() < 1e-15);
        assert_eq!(
            report.error_worst,
            Some(FrameValue {
                frame: 0,
                value: 0.2
            })
        );
        assert_eq!((report.flip, report.ssim), (None, None));
    }

    #[test]
    fn summaries_keep_the_worst_frame() {
        let values = [(0, 0.0), (5, 0.3), (10, 0.1), (15, 0.3)];
        let s = MetricSummary::of(values.into_iter(), false).unwrap();
        assert_eq!(s.frames, 4);
        assert!((s.mean - 0.175).abs() < 1e-15);
        // Ties: the first.
        assert_eq!(
            s.worst,
            FrameValue {
                frame: 5,
                value: 0.3
            }
        );
        let s = MetricSummary::of(values.into_iter(), true).unwrap();
        assert_eq!(
            s.worst,
            FrameValue {
                frame: 0,
                value: 0.0
            }
        );
        assert_eq!(MetricSummary::of(std::iter::empty(), false), None);
    }

    #[test]
    fn older_frame_records_still_load() {
        let json = r#"{"frame":3,"frame_ms":1.0,"cpu_ms":1.0,"pass_ms":[],"shaded":10,"hits":0,
            "recomputes":10,"hit_px":null,"miss_px":null,"refresh_px":null,"hit_rate":0.0,
            "error":0.01,"psnr":40.0,"max_abs_diff":0.1}"#;
        let f: FrameRecord = serde_json::from_str(json).unwrap();
        assert_eq!((f.frame, f.mse, f.covered), (3, 0.0, 0));
    }
}
