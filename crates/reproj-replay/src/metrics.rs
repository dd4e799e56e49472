//! Image metrics and the render report.

use serde::{Deserialize, Serialize};

/// PSNR reported for identical frames (instead of +∞).
pub const PSNR_CAP: f64 = 100.0;

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
    /// PSNR in dB against the reference (capped at 100).
    pub psnr: f64,
    /// Largest per-channel absolute difference to the reference.
    pub max_abs_diff: f64,
}

/// Result of rendering a session: the original (reference) or a variant.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct RenderReport {
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
    /// Mean PSNR over all frames.
    pub psnr: f64,
    /// Mean hit rate over frames 1.. (0 for the original).
    pub hit_rate: f64,
    /// Mean frame time over frames 1.. (frame 0 pays shader compilation), ms.
    pub frame_ms: f64,
    /// Mean CPU submit+wait time over frames 1.., ms.
    pub cpu_ms: f64,
    pub frames: Vec<FrameRecord>,
}

/// Per-pixel L2 RGB distance, clamped to [0, 1] first; RGBA f32 inputs.
pub fn pixel_errors(a: &[f32], b: &[f32]) -> Vec<f32> {
    a.chunks_exact(4)
        .zip(b.chunks_exact(4))
        .map(|(p, q)| {
            let mut s = 0.0f32;
            for c in 0..3 {
                let d = p[c].clamp(0.0, 1.0) - q[c].clamp(0.0, 1.0);
                s += d * d;
            }
            s.sqrt()
        })
        .collect()
}

/// (mean L2 error, PSNR, max abs channel difference) of a frame against its reference.
pub fn compare(frame: &[f32], reference: &[f32]) -> (f64, f64, f64) {
    let mut sum = 0.0f64;
    let mut sq = 0.0f64;
    let mut maxd = 0.0f64;
    let n = frame.len() / 4;
    for (p, q) in frame.chunks_exact(4).zip(reference.chunks_exact(4)) {
        let mut s = 0.0f64;
        for c in 0..3 {
            let d = (p[c].clamp(0.0, 1.0) - q[c].clamp(0.0, 1.0)) as f64;
            s += d * d;
        }
        for c in 0..4 {
            let d = (p[c] - q[c]).abs() as f64;
            maxd = if d.is_nan() {
                f64::INFINITY
            } else {
                maxd.max(d)
            };
        }
        sum += s.sqrt();
        sq += s;
    }
    let n = n.max(1) as f64;
    let mse = sq / (3.0 * n);
    (sum / n, psnr(mse), maxd)
}

/// PSNR in dB for a peak of 1, capped at [`PSNR_CAP`].
pub fn psnr(mse: f64) -> f64 {
    if mse <= 0.0 {
        PSNR_CAP
    } else {
        (10.0 * (1.0 / mse).log10()).min(PSNR_CAP)
    }
}

/// Mean of `xs`, 0 when empty.
pub fn mean(xs: impl Iterator<Item = f64>) -> f64 {
    let (s, n) = xs.fold((0.0, 0usize), |(s, n), x| (s + x, n + 1));
    if n == 0 { 0.0 } else { s / n as f64 }
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
        self.psnr = mean(all.iter().map(|f| f.psnr));
        self.hit_rate = mean(after0.iter().map(|f| f.hit_rate));
        self.frame_ms = mean(after0.iter().map(|f| f.frame_ms));
        self.cpu_ms = mean(after0.iter().map(|f| f.cpu_ms));
    }
}
