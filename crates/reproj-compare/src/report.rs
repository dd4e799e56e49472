//! What `compare` reports (`compare.json`, schema [`crate::COMPARE_SCHEMA`], `docs/SCHEMAS.md`):
//! each method's result and scores, and the report around them.

use serde::{Deserialize, Serialize};

use crate::{crops, reproj, resize, simplify};

/// The errors of one method's frames against the original.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Scores {
    /// Mean per-pixel L2 RGB distance over all pixels and frames (the error budgets bound).
    pub error: f64,
    /// PSNR of the MSE pooled over the covered pixels of every frame (dB, capped at 100).
    pub psnr: f64,
    /// Mean ꟻLIP over the covered pixels of the frames on the perceptual stride.
    pub flip: Option<f64>,
    /// PSNR over the still and over the moving frames alone, where the session has both
    /// ([`crate::supersample::moving_frames`]; version 6 on).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub split: Option<Split>,
    /// The same figures against the supersampled reference (version 6 on).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub supersampled: Option<Against>,
}

/// PSNR over the still frames and over the moving frames (dB).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Split {
    pub still_psnr: f64,
    pub moving_psnr: f64,
}

/// A method's frames against the supersampled reference.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Against {
    /// PSNR over the covered pixels of every frame (dB).
    pub psnr: f64,
    /// Mean ꟻLIP on the perceptual stride.
    pub flip: Option<f64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub split: Option<Split>,
}

/// One method's result at (or as near as it got to) the target speedup.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct MethodResult {
    /// `resize`, `simplify` or `reproj`.
    pub method: String,
    /// Mean measured frame time over frames 1.., ms.
    pub frame_ms: f64,
    /// Original frame time / `frame_ms`, from the timing engine (`reproj-bench`): the reported
    /// figure comes from one run with every method's final candidate and the original
    /// interleaved (the searches' own tries are timed interleaved too, in shorter runs), and
    /// `frame_ms` is its median block time.
    pub speedup: f64,
    /// Its 95 % interval (version 2 on).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub speedup_ci95: Option<[f64; 2]>,
    /// Whether `speedup` is at least the target.
    pub reached_target: bool,
    #[serde(flatten)]
    pub scores: Scores,
    /// What was chosen, in words (the scale, the removed nodes, the node and Δn).
    pub setting: String,
}

/// `compare.json`: the comparison, as printed with `--json`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct CompareReport {
    /// Always [`crate::COMPARE_SCHEMA`].
    pub schema: String,
    /// [`crate::COMPARE_VERSION`].
    pub version: u32,
    pub shader: String,
    pub entry: String,
    pub session: String,
    /// Full resolution, `[width, height]`.
    pub resolution: [u32; 2],
    /// Frames rendered per replay.
    pub frames: u32,
    pub adapter: String,
    /// `timestamps` or `cpu`.
    pub timing: String,
    pub target_speedup: f64,
    /// The error budget the target speedup was derived from (reproj's predicted speedup under
    /// it), when the target was given as a budget.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub max_error: Option<f64>,
    /// The original's frame time, ms: the median of its interleaved blocks (version 2 on; before,
    /// the mean over frames 1.. of one replay).
    pub original_ms: f64,
    /// The machine the speeds come from (adapter, `LP_NUM_THREADS`, cores; a CPU rasterizer says
    /// so), version 2 on.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub measured_on: Option<String>,
    /// What the interleaved timing saw of the machine; empty when clean.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub timing_warnings: Vec<String>,
    /// One entry per method that ran: resize, simplify, then reproj.
    pub methods: Vec<MethodResult>,
    /// Samples per pixel of the supersampled reference (0: none; version 6 on).
    #[serde(default)]
    pub supersample: u32,
    /// The one-sample original against the supersampled reference: the floor every one-sample
    /// method starts from (version 6 on).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub original_vs_supersampled: Option<Against>,
    /// Frames where the camera or an object moved since the frame before, of `frames`
    /// (version 6 on).
    #[serde(default)]
    pub moving_frames: u32,
    /// What the reader should know of this comparison (a session without motion, …).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub notes: Vec<String>,
    pub resize: resize::ResizeDetail,
    /// The temporal upsampler's scale search (version 6 on; `None` when not compared).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub temporal: Option<resize::ResizeDetail>,
    pub simplify: simplify::SimplifyDetail,
    /// `None` without a profile.
    pub reproj: Option<reproj::ReprojDetail>,
    /// Where the crops were taken.
    pub crops: crops::CropRegion,
    /// Files written, in `write_outputs` order (empty until written).
    pub files: Vec<String>,
}
