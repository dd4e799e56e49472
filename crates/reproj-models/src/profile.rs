//! The profile: what `reproj analyze` measured and fitted, so that `reproj emit` never renders.
//!
//! Serialized as `NAME.profile.json`, schema `reproj.profile` version [`PROFILE_VERSION`]. It records
//! where the numbers come from (shader and session hashes, adapter, resolution, thread count), every
//! measurement (per node and Δn, with per-frame counts and times), every fit with its quality, and
//! the status of each node: usable, or set aside with the reason.

use reproj_metrics::{FrameValue, MetricSummary};
use serde::{Deserialize, Serialize};

use crate::{ErrorFit, FrameTiming, HitRateFit, Metric, TimingFit};

mod ceiling;
mod check;
mod input;
mod probes;
pub use ceiling::Ceiling;
pub use input::ShaderInputRecord;
pub use probes::{BlockProbe, FilterProbe, RaceProbe, StrategyProbe, Timed};

/// Version of the profile schema. Bump on any incompatible change.
/// Version 2: per-node `strategy` and `block`, and `strategy_probes`. Version 1 files still load
/// (every node is a 3pass node at the profile's block size).
/// Version 3: paths relative to the profile's directory, `ir_hash` of the shader.
/// Version 4: perceptual metrics — `perceptual_stride`; per measurement `error_worst`, `flip` and
/// `ssim`; per node `flip_fit` and `dssim_fit`; per held-out check `measured_flip` and
/// `predicted_flip`. Older files still load (without them: `emit --metric flip` asks to re-run
/// `analyze`).
/// Version 5: `unroll`.
/// Version 6: `sets`, node sets cached together in one payload and replayed (`analyze`'s greedy
/// set search). Older files still load without them.
/// Version 7: the strategy race and the set-aside rule timed interleaved (`reproj-bench`):
/// `strategy_probes` carry `speedup`, `speedup_ci95` and `rounds` (no `error`), `machine` says
/// whether the adapter is a CPU rasterizer, `timing_warnings`, `time.timing_s`.
/// Version 8: `motion`, how fast the session moves on screen (`reproj_models::motion`), so that
/// `emit` can carry the error models to a session of other motion.
/// Version 9: the reconstruction filter per node (`nodes[].reconstruct`, `analyze --reconstruct
/// auto` races bilinear against Catmull-Rom per node) and the races behind it (`filter_probes`).
/// The profile's `reconstruct` is the filter of its sets and of every node that names none (all
/// nodes of older profiles). Per measurement `frame_errors`, the L2 error of every replayed
/// frame, so that the motion exponent can be fitted across segments of one session.
/// Version 10: the refresh block size raced per node (`analyze --block auto`): `block_probes`,
/// and `nodes[].block` the kept size. Older files still load without them.
/// Version 11: `machine.driver`, the driver and its version (one adapter name covers drivers that
/// choose differently: lavapipe in Mesa 22.3 runs both sides of a branch, in Mesa 25 it skips the
/// side no lane takes, and `analyze` keeps `2pass` on the one and `fused` on the other). Older
/// files still load without it.
/// Version 12: `ceiling`, the most caching can give on the device (the root cached and never
/// refreshed, timed against the original before any node), and `analyze` stops there with no
/// node where even that cannot pay. Nodes may be measured past the longest training period
/// (`analyze --max-delta-n`). And `shader_input`, how the shader file was read (shader defs, a defs preset, import
/// paths, GLSL include folders), so that `emit`, `report` and `compare --profile` read the same
/// shader. Older files still load without any of them (read as by default).
/// Version 13: `machine.clock`, the device's clock as the first race found it (the original
/// rendered until two blocks agree before every race is timed), and `period_probes`, each node
/// raced at a second period so that the time side follows races, not replays.
/// Version 14: `ceiling.node` and `ceiling.payload`, the narrower node raced beside the root.
pub const PROFILE_VERSION: u32 = 14;

/// What [`reproj_io::read_json`] expects of a profile: any version up to this reproj's (older
/// profiles lack only optional fields).
pub const PROFILE_KIND: reproj_io::Kind = reproj_io::Kind {
    schema: "reproj.profile",
    versions: 1..=PROFILE_VERSION,
    hint: "re-run `reproj analyze` with this reproj",
};

/// A whole profile.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Profile {
    /// Always `"reproj.profile"`.
    pub schema: String,
    pub version: u32,
    pub shader: Source,
    pub entry: String,
    /// Loops of at most this many iterations were unrolled before the nodes were listed (0: none;
    /// version 5, 0 before). Node ids depend on it: `emit` normalizes the shader the same way.
    #[serde(default)]
    pub unroll: u32,
    /// How the shader file was read beyond its language (version 12; absent: as by default).
    /// Node ids and the IR hash depend on it: `emit` reads the shader the same way.
    #[serde(default, skip_serializing_if = "ShaderInputRecord::is_empty")]
    pub shader_input: ShaderInputRecord,
    pub session: Source,
    /// Where it was measured.
    pub machine: Machine,
    /// `[width, height]`.
    pub resolution: [u32; 2],
    /// Frames per replay.
    pub frames: u32,
    /// Δn used to fit the error models.
    pub delta_n_train: Vec<u32>,
    /// Δn used only to check the models.
    pub delta_n_holdout: Vec<u32>,
    /// ꟻLIP and SSIM were computed on the frames `f` with `f % perceptual_stride == 0` of every
    /// replay (`None`: not computed, profiles before version 4).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub perceptual_stride: Option<u32>,
    /// Refresh block size k and depth tolerance used for every variant.
    pub block: u32,
    pub depth_epsilon: f32,
    /// How the variants reconstructed the payload (`bilinear`, `nearest`, `catmull-rom`) and their
    /// cache format (`f32`, `f16` or a format's name): what `emit`, `report` and `compare` write
    /// and render, so that they run what was measured. The reconstruction is the sets' and that of
    /// every node without its own [`NodeProfile::reconstruct`] (version 9; before, every node's).
    /// Absent in older profiles: `bilinear`, `f32`.
    #[serde(default = "default_reconstruct")]
    pub reconstruct: String,
    #[serde(default = "default_cache_format")]
    pub cache_format: String,
    pub original: OriginalRecord,
    /// Hit-rate model, one per shader and session.
    pub hit_rate: HitRateFit,
    /// One entry per profiled node, in the strategy that measured fastest for it.
    pub nodes: Vec<NodeProfile>,
    /// Every strategy tried per node at the longest training Δn, and which one was kept.
    #[serde(default)]
    pub strategy_probes: Vec<StrategyProbe>,
    /// The reconstruction filters raced per node after its strategy was chosen (`analyze
    /// --reconstruct auto`, version 9; empty without the race).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub filter_probes: Vec<FilterProbe>,
    /// The refresh block sizes raced per node after its strategy was chosen (`analyze --block
    /// auto`, version 10; empty without the race).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub block_probes: Vec<BlockProbe>,
    /// Each profiled node's kept variant raced against the original at a second period, the
    /// shortest of the plan, so that its frame time over Δn follows two races (version 13; empty
    /// before).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub period_probes: Vec<StrategyProbe>,
    /// What the interleaved timing saw of the machine during the analysis (load, drift, wide
    /// intervals), once each; empty when it was quiet (version 7 on).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub timing_warnings: Vec<String>,
    /// Sets of nodes cached together in one payload and replayed, best first as the search met
    /// them (version 6; empty: none was formed, `--no-sets`, or an older profile).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub sets: Vec<SetProfile>,
    /// Wall-clock time of the analysis and where it went.
    pub time: AnalysisTime,
    /// Set on a shard's profile (`analyze --shard i/N`); `reproj merge` joins the N shards into
    /// one profile without it.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub shard: Option<Shard>,
    /// How fast the profiled session moves (version 8; `None` before, or when it could not be
    /// measured).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub motion: Option<crate::motion::Motion>,
    /// The most caching can give on the profiling device, measured before any node (version
    /// 12; `None` before, or where it could not be timed). Where even that cannot pay, no node
    /// was profiled and `emit` keeps the original, giving this as the reason.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub ceiling: Option<Ceiling>,
}

/// Which part of the work a shard did: the candidate nodes at positions `p` with
/// `p % count == index` (in id order).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub struct Shard {
    pub index: u32,
    pub count: u32,
}

impl std::str::FromStr for Shard {
    type Err = String;
    fn from_str(s: &str) -> Result<Shard, String> {
        let bad = || format!("`{s}` is not a shard: expected i/N with 0 ≤ i < N, e.g. 0/3");
        let (i, n) = s.split_once('/').ok_or_else(bad)?;
        let (index, count): (u32, u32) = (
            i.trim().parse().map_err(|_| bad())?,
            n.trim().parse().map_err(|_| bad())?,
        );
        if count == 0 || index >= count {
            return Err(bad());
        }
        Ok(Shard { index, count })
    }
}

/// A file the profile depends on.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Source {
    /// Path relative to the profile's directory (version 3; before: as given to `analyze`).
    pub path: String,
    /// FNV-1a 64 of the file's bytes, hex: [`content_hash`].
    pub hash: String,
    /// For the shader: FNV-1a 64 of its IR written back as WGSL by naga, so comments and
    /// formatting do not make a profile stale. `emit` checks this one when present.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub ir_hash: Option<String>,
}

/// The machine and adapter the measurements come from.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Machine {
    pub adapter: String,
    pub backend: String,
    /// `timestamp-queries` or `cpu-wall-clock`.
    pub timing_method: String,
    pub cpu_cores: u32,
    /// `LP_NUM_THREADS` when set (lavapipe's rasterizer threads).
    pub lp_num_threads: Option<String>,
    /// The adapter is a CPU rasterizer (lavapipe): its speed figures say nothing of a GPU's
    /// (version 7 on).
    #[serde(default)]
    pub cpu_rasterizer: bool,
    /// The driver and its version as the adapter reports them (`Mesa 22.3.6 (LLVM 15.0.6)` for
    /// lavapipe; version 11 on, absent before).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub driver: Option<String>,
    /// The device's clock before the analysis's first race: the original's settling blocks
    /// (`crate::speedup::Settling`; version 13 on, absent before and where nothing was raced).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub clock: Option<crate::speedup::Settling>,
}

impl Machine {
    /// How reports name the device: `adapter, driver` ([`device_name`]).
    pub fn device(&self) -> String {
        device_name(&self.adapter, self.driver.as_deref())
    }
}

/// `adapter, driver`, or the adapter alone where no driver is named (`llvmpipe (LLVM 15.0.6, 256
/// bits), Mesa 22.3.6 (LLVM 15.0.6)`): the adapter's name alone does not tell lavapipe in Mesa 22.3
/// from lavapipe in Mesa 25.
pub fn device_name(adapter: &str, driver: Option<&str>) -> String {
    match driver.map(str::trim).filter(|d| !d.is_empty()) {
        Some(d) => format!("{adapter}, {d}"),
        None => adapter.to_string(),
    }
}

/// The original shader's measurements.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct OriginalRecord {
    /// Mean frame time over frames 1.. (frame 0 is shader compilation).
    pub frame_ms: f64,
    /// Mean shaded pixels per frame (M).
    pub mean_pixels: f64,
    pub frame_times_ms: Vec<f64>,
    /// Pixels, over the session's frames, where the original itself renders a NaN or an
    /// infinity: no error can be measured there, so every measurement leaves them out. 0 (and
    /// absent) for a shader that behaves.
    #[serde(default, skip_serializing_if = "is_zero_u64")]
    pub nonfinite_pixels: u64,
}

fn default_reconstruct() -> String {
    "bilinear".into()
}

fn default_cache_format() -> String {
    "f32".into()
}

fn is_zero_u64(n: &u64) -> bool {
    *n == 0
}

/// One replay of one variant at one Δn.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Measurement {
    pub delta_n: u32,
    /// Mean over frames of the mean per-pixel L2 RGB distance to the original (over all pixels).
    pub error: f64,
    /// The frame with the largest L2 error (version 4).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub error_worst: Option<FrameValue>,
    /// ꟻLIP over the covered pixels, on the profile's `perceptual_stride` frames (version 4).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub flip: Option<MetricSummary>,
    /// SSIM over the covered pixels, on the same frames; its worst frame is the least similar
    /// (version 4).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub ssim: Option<MetricSummary>,
    /// Mean squared RGB error over the pixels the original covers, pooled over the frames
    /// (`docs/SCHEMAS.md`). `None` in profiles written before it was recorded.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub mse: Option<f64>,
    /// PSNR of `mse`, `10 log10(1 / mse)` dB (`None` when the variant is identical to the
    /// original). Profiles written before `mse` was recorded hold the mean of per-frame PSNRs
    /// over all pixels here.
    pub psnr: Option<f64>,
    /// Hits / shaded pixels over the session.
    pub hit_rate: f64,
    pub frame_ms: f64,
    /// Per frame (frame 0 excluded): hits, misses (incl. refreshes), time.
    pub frames: Vec<FrameTiming>,
    /// The L2 error of every replayed frame, frame 0 first (version 9; empty before): segments
    /// of one session of varying motion tell how the error follows motion.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub frame_errors: Vec<f64>,
}

/// Whether a node can be selected.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(tag = "status", rename_all = "kebab-case")]
pub enum NodeStatus {
    Ok,
    /// Set aside: a fit failed or a measurement was unusable.
    SetAside {
        reason: String,
    },
}

/// Models checked at Δn never used for fitting.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct HoldoutCheck {
    pub delta_n: u32,
    pub measured_error: f64,
    pub predicted_error: Option<f64>,
    pub measured_ms: f64,
    pub predicted_ms: Option<f64>,
    /// Mean ꟻLIP measured, and predicted by `flip_fit` (version 4).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub measured_flip: Option<f64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub predicted_flip: Option<f64>,
}

/// Everything about one node.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct NodeProfile {
    /// Node id (`reproj nodes`); the root is included with `root: true`.
    pub id: u32,
    pub root: bool,
    pub text: String,
    pub line: u32,
    pub col: u32,
    #[serde(rename = "type")]
    pub ty: String,
    pub cost: f64,
    pub overlap: f64,
    /// Variant strategy the measurements use (`3pass`, `2pass`, `fused`).
    #[serde(default = "three_pass")]
    pub strategy: String,
    /// Refresh block size k of the measurements (`None`: the profile's `block`).
    #[serde(default)]
    pub block: Option<u32>,
    /// How its variant reconstructs the payload (`bilinear`, `nearest`, `catmull-rom`; version 9).
    /// `None`: the profile's [`Profile::reconstruct`]. Read it with
    /// [`NodeProfile::reconstruct_in`].
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub reconstruct: Option<String>,
    pub measurements: Vec<Measurement>,
    /// The error model fitted to the L2 error (the paper's; decides whether the node is usable).
    pub error_fit: ErrorFit,
    /// The same model fitted to the mean ꟻLIP (version 4).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub flip_fit: Option<ErrorFit>,
    /// The same model fitted to the dissimilarity 1 − mean SSIM (version 4).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub dssim_fit: Option<ErrorFit>,
    pub timing_fit: TimingFit,
    pub holdout: Vec<HoldoutCheck>,
    #[serde(flatten)]
    pub status: NodeStatus,
}

/// A set of nodes cached together in one payload (`reproj instance --node 22,39`), replayed and
/// fitted like a single node (version 6).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SetProfile {
    /// The member node ids, in payload order.
    pub members: Vec<u32>,
    /// The members' source texts, in the same order.
    pub texts: Vec<String>,
    /// Variant strategy and refresh block size k of the measurements.
    pub strategy: String,
    pub block: u32,
    pub measurements: Vec<Measurement>,
    /// The set's error and time predicted from its members' single-node fits (`reproj-select`'s
    /// `combine`) at each measured Δn, beside what the replay measured.
    #[serde(default)]
    pub predicted: Vec<SetPredicted>,
    pub error_fit: ErrorFit,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub flip_fit: Option<ErrorFit>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub dssim_fit: Option<ErrorFit>,
    pub timing_fit: TimingFit,
    pub holdout: Vec<HoldoutCheck>,
    #[serde(flatten)]
    pub status: NodeStatus,
}

/// A set's combined prediction at one Δn (`None`: a member's fits could not predict it).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SetPredicted {
    pub delta_n: u32,
    pub error: Option<f64>,
    pub frame_ms: Option<f64>,
}

impl SetProfile {
    /// How reports name the set: the member ids joined by `+` (`"22+39"`).
    pub fn name(&self) -> String {
        self.members
            .iter()
            .map(u32::to_string)
            .collect::<Vec<_>>()
            .join("+")
    }

    /// The error model fitted to `metric` (`None`: not measured).
    pub fn fit(&self, metric: Metric) -> Option<&ErrorFit> {
        match metric {
            Metric::L2 => Some(&self.error_fit),
            Metric::Flip => self.flip_fit.as_ref(),
        }
    }

    /// The MSE at `delta_n`, interpolated as [`NodeProfile::mse_at`] does.
    pub fn mse_at(&self, delta_n: u32) -> Option<f64> {
        mse_at(&self.measurements, delta_n)
    }
}

impl Measurement {
    /// The measured value of `metric`: the mean over the replay's frames (`None`: not measured).
    pub fn value(&self, metric: Metric) -> Option<f64> {
        match metric {
            Metric::L2 => Some(self.error),
            Metric::Flip => self.flip.map(|s| s.mean),
        }
    }
}

impl NodeProfile {
    /// The reconstruction its measurements used: its own, else the profile's (`profile`'s
    /// [`Profile::reconstruct`]).
    pub fn reconstruct_in<'a>(&'a self, profile: &'a Profile) -> &'a str {
        self.reconstruct.as_deref().unwrap_or(&profile.reconstruct)
    }

    /// The error model fitted to `metric` (`None`: a profile without that metric).
    pub fn fit(&self, metric: Metric) -> Option<&ErrorFit> {
        match metric {
            Metric::L2 => Some(&self.error_fit),
            Metric::Flip => self.flip_fit.as_ref(),
        }
    }

    /// The MSE of caching this node at refresh period `delta_n`, from the measured MSEs
    /// interpolated linearly in Δn between the neighbouring measured periods; below the shortest
    /// measured period from 0 at Δn = 1 (every pixel refreshed every frame: the original).
    /// `None` above the longest measured period, or when no measurement recorded an MSE.
    pub fn mse_at(&self, delta_n: u32) -> Option<f64> {
        mse_at(&self.measurements, delta_n)
    }
}

/// The MSE at `delta_n` from measured MSEs, interpolated linearly between neighbouring periods
/// (see [`NodeProfile::mse_at`]).
fn mse_at(measurements: &[Measurement], delta_n: u32) -> Option<f64> {
    let mut points: Vec<(f64, f64)> = measurements
        .iter()
        .filter_map(|m| Some((f64::from(m.delta_n), m.mse.filter(|v| v.is_finite())?)))
        .collect();
    if points.is_empty() {
        return None;
    }
    points.push((1.0, 0.0));
    points.sort_by(|a, b| a.0.total_cmp(&b.0));
    let x = f64::from(delta_n.max(1));
    let i = points.partition_point(|p| p.0 < x);
    let (x1, y1) = *points.get(i)?;
    if x1 == x || i == 0 {
        return Some(y1);
    }
    let (x0, y0) = points[i - 1];
    Some(y0 + (y1 - y0) * (x - x0) / (x1 - x0))
}

fn three_pass() -> String {
    "3pass".into()
}

/// Where the analysis time went, in seconds.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, Default)]
pub struct AnalysisTime {
    pub total_s: f64,
    pub reference_s: f64,
    pub rendering_s: f64,
    pub readback_and_error_s: f64,
    pub fitting_s: f64,
    pub instancing_s: f64,
    /// The interleaved timing of the strategy races and set-aside decisions (version 7 on).
    #[serde(default)]
    pub timing_s: f64,
}

pub use reproj_io::content_hash;

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{ErrorFitOptions, fit_error, fit_timing};

    fn node_with(mses: &[(u32, Option<f64>)]) -> NodeProfile {
        NodeProfile {
            id: 1,
            root: false,
            text: "x".into(),
            line: 1,
            col: 1,
            ty: "f32".into(),
            cost: 1.0,
            overlap: 0.0,
            strategy: "3pass".into(),
            block: None,
            reconstruct: None,
            measurements: mses
                .iter()
                .map(|&(delta_n, mse)| Measurement {
                    delta_n,
                    error: 0.0,
                    error_worst: None,
                    flip: None,
                    ssim: None,
                    mse,
                    psnr: None,
                    hit_rate: 0.0,
                    frame_ms: 1.0,
                    frames: Vec::new(),
                    frame_errors: Vec::new(),
                })
                .collect(),
            error_fit: fit_error(&[], &ErrorFitOptions::default()),
            flip_fit: None,
            dssim_fit: None,
            timing_fit: fit_timing(&[]),
            holdout: Vec::new(),
            status: NodeStatus::Ok,
        }
    }

    #[test]
    fn mse_is_interpolated_between_measured_periods() {
        // Measured out of order, as `analyze` does (the longest period first).
        let n = node_with(&[(50, Some(0.005)), (2, Some(0.001)), (10, Some(0.003))]);
        assert_eq!(n.mse_at(10), Some(0.003));
        assert_eq!(n.mse_at(2), Some(0.001));
        assert!((n.mse_at(6).unwrap() - 0.002).abs() < 1e-15);
        assert!((n.mse_at(30).unwrap() - 0.004).abs() < 1e-15);
        assert_eq!(n.mse_at(1), Some(0.0));
        assert_eq!(n.mse_at(0), Some(0.0));
        assert_eq!(n.mse_at(51), None);
        // Old profiles: no MSE recorded.
        assert_eq!(node_with(&[(2, None), (10, None)]).mse_at(5), None);
    }

    #[test]
    fn measurements_without_mse_still_load() {
        let json =
            r#"{"delta_n":2,"error":0.01,"psnr":40.0,"hit_rate":0.5,"frame_ms":1.0,"frames":[]}"#;
        let m: Measurement = serde_json::from_str(json).unwrap();
        assert_eq!((m.delta_n, m.mse), (2, None));
        assert_eq!(
            (m.value(Metric::L2), m.value(Metric::Flip)),
            (Some(0.01), None)
        );
        assert_eq!((m.flip, m.ssim, m.error_worst), (None, None, None));
        let n = node_with(&[(2, None)]);
        assert!(n.fit(Metric::L2).is_some() && n.fit(Metric::Flip).is_none());
    }

    #[test]
    fn hash_is_stable() {
        assert_eq!(content_hash(b""), "cbf29ce484222325");
        assert_eq!(content_hash(b"a"), "af63dc4c8601ec8c");
        assert_ne!(content_hash(b"ab"), content_hash(b"ba"));
    }
}
