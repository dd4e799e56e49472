//! What `analyze` is asked to do: its options and their defaults (the paper's periods, the
//! perceptual and probe frame counts), the Δn sampling plan, and the checks on the periods.

use reproj_instance::{InstanceOptions, Strategy};
use reproj_models::profile::{Measurement, Shard};
use reproj_models::{ErrorFitOptions, fit_error};
use reproj_select::{DEFAULT_MAX_DELTA_N, DEFAULT_MIN_DELTA_N};

use crate::AnalyzeError;
use crate::journal::JournalOptions;
use crate::prune::PruneOptions;

mod extension;

pub use extension::{Extension, ExtensionStop, next_extension};

/// The paper's training periods (seeds 002 §4.2): seven spread evenly over
/// [`reproj_select::DELTA_N_RANGE`], both ends included (2, 10, …, 50).
pub const DEFAULT_TRAIN: [u32; 7] = {
    let (first, last) = (DEFAULT_MIN_DELTA_N, DEFAULT_MAX_DELTA_N);
    let step = (last - first) / 6;
    [
        first,
        first + step,
        first + 2 * step,
        first + 3 * step,
        first + 4 * step,
        first + 5 * step,
        last,
    ]
};
/// Periods used only to check the models.
pub const DEFAULT_HOLDOUT: [u32; 2] = [6, 30];
/// The stride `emit` and `report` use for a profile that does not record its own (profiles
/// before version 4 had no perceptual metrics).
pub const DEFAULT_PERCEPTUAL_STRIDE: u32 = 5;
/// Without [`AnalyzeOptions::perceptual_stride`], ꟻLIP and SSIM are computed on about this many
/// frames of each replay (every 10th frame of a 150-frame session). The mean of a metric over
/// 15 frames is what its model needs; more frames cost CPU time (ꟻLIP is about 60 ms per
/// 256×256 frame on one core, as much as rendering the frame several times on lavapipe).
pub const DEFAULT_PERCEPTUAL_FRAMES: u32 = 15;
/// How `analyze` times its races by default ([`AnalyzeOptions::race`]): blocks of 8 timed frames,
/// 8 rounds (each window of the session twice, once in each order), at most 4 s. A race decides
/// only where intervals separate, and a wide interval decides for the simpler strategy and against
/// setting a node aside, so a short race is enough; it costs about what the probe replays it
/// replaced did.
pub const DEFAULT_RACE: reproj_bench::BenchOptions = reproj_bench::BenchOptions {
    block_frames: 8,
    stop: reproj_models::speedup::StopRule {
        min_rounds: 8,
        max_rounds: 8,
        target_half_width: 0.05,
        max_seconds: 4.0,
    },
    max_frames: None,
    settle: Some(reproj_bench::DEFAULT_SETTLE),
};

/// Options of [`analyze`].
#[derive(Debug, Clone)]
pub struct AnalyzeOptions {
    pub delta_n_train: Vec<u32>,
    pub delta_n_holdout: Vec<u32>,
    /// Which nodes to profile when `nodes` is `None`.
    pub prune: PruneOptions,
    /// Profile exactly these node ids (the root is always added).
    pub nodes: Option<Vec<u32>>,
    /// Cache format, reconstruction and depth tolerance of every variant (its `strategy` and
    /// `block` are set per strategy from `strategies` and `block`). Its reconstruction is the
    /// base filter, and the only one without `race_filters`.
    pub instance: InstanceOptions,
    /// Per node, after its strategy is chosen, race Catmull-Rom against the base filter at equal
    /// error and keep the faster beyond doubt ([`crate::filters`]; `--reconstruct auto`). Off by
    /// default: on a CPU rasterizer it adds a replay and a race per node and rarely wins.
    pub race_filters: bool,
    /// Strategies to try. With several, each node is replayed in each at the longest training Δn
    /// and only the fastest is profiled further.
    pub strategies: Vec<Strategy>,
    /// Refresh block size k for every strategy (`None`: each strategy's default).
    pub block: Option<u32>,
    /// Per node, after its strategy is chosen, race a larger refresh block against the
    /// strategy's default at one period (the longest training Δn at most half the frames
    /// replayed) and keep it where it is more accurate and not slower beyond doubt
    /// (`crate::blocks`; `--block auto`). Off by default (one replay and one race per node);
    /// ignored where `block` is set.
    pub race_blocks: bool,
    /// Replay only the first N frames of the session.
    pub max_frames: Option<u32>,
    /// Record every finished replay here and reuse what an interrupted run recorded
    /// ([`crate::journal`]). `None`: no journal.
    pub journal: Option<JournalOptions>,
    /// Profile only this shard's part of the nodes ([`Shard`]; join with [`crate::merge()`]).
    pub shard: Option<Shard>,
    /// Compute the perceptual metrics (ꟻLIP, SSIM) of every replay on the frames `f` with
    /// `f % perceptual_stride == 0` (≥ 1): reading frames back and comparing them on the CPU
    /// costs time, the L2 error is reduced on the GPU for every frame. `None`: the stride that
    /// scores about [`DEFAULT_PERCEPTUAL_FRAMES`] frames of the replayed session.
    pub perceptual_stride: Option<u32>,
    /// At how many of the training periods each node is replayed.
    pub sampling: Sampling,
    /// The strategy races and set-aside decisions draw their windows from the session's first N
    /// frames. `None`: the whole session.
    pub probe_frames: Option<u32>,
    /// How the races are timed: each node's strategies (and each set) against the original at
    /// the longest training period, interleaved (`reproj-bench`).
    pub race: reproj_bench::BenchOptions,
    /// After the single nodes, search sets of nodes cached together ([`crate::sets`]). `None`:
    /// no set is formed (`--no-sets`).
    pub sets: Option<SetSearchOptions>,
    /// How far past the longest training period a node's replays may go ([`next_extension`]).
    pub extension: Extension,
    /// Before any node, race the root cached and never refreshed against the original: the most
    /// caching can give here, recorded in the profile; where even that cannot reach a useful
    /// speedup no node is replayed (`crate::analyze`'s ceiling).
    pub ceiling: bool,
}

/// Whether a measurement at `delta_n` belongs to the fits' training data: a training period, or
/// one past the longest of them ([`next_extension`]); the others are held out.
pub(crate) fn is_training(opts: &AnalyzeOptions, delta_n: u32) -> bool {
    opts.delta_n_train.contains(&delta_n)
        || opts
            .delta_n_train
            .iter()
            .max()
            .is_some_and(|&l| delta_n > l)
}

/// At how many of the training periods `analyze` replays each node.
///
/// The error model has two parameters, so three well-spread periods determine it; the others
/// only confirm it. [`Sampling::Adaptive`] replays a node at the longest, the shortest and the
/// middle training period and at the held-out periods, fits the error model to the three and,
/// while it misses a held-out measurement, replays the remaining training periods one at a
/// time, the one nearest the worst miss first, fitting again after each: a node whose error
/// follows the model costs four fewer replays in nine (marble: 9 → 5 per node), one whose curve
/// needs pinning near a held-out period usually one more (marble's nodes 680 and 697: 6, not 9).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Sampling {
    /// Every training period, as the paper did.
    Every,
    /// The remaining training periods only while the model fitted so far misses a held-out
    /// measurement by more than `tolerance` × the measured error + [`Sampling::ABS_TOLERANCE`].
    Adaptive { tolerance: f64 },
}

impl Sampling {
    /// Absolute slack of the held-out check, in error units: measured errors this small are
    /// within the replay's own noise.
    pub const ABS_TOLERANCE: f64 = 2e-4;
    /// Default relative slack of the held-out check.
    pub const DEFAULT_TOLERANCE: f64 = 0.15;
}

impl Default for Sampling {
    fn default() -> Self {
        Sampling::Adaptive {
            tolerance: Sampling::DEFAULT_TOLERANCE,
        }
    }
}

/// The order in which a node's periods are replayed: (Δn, whether it may be skipped).
/// `longest` comes first and is replayed by the caller; then the shortest and middle training
/// periods, the held-out ones, and the remaining training periods (skippable under
/// [`Sampling::Adaptive`]).
pub(crate) fn period_plan(opts: &AnalyzeOptions, longest: u32) -> Vec<(u32, bool)> {
    let mut train: Vec<u32> = opts.delta_n_train.clone();
    train.sort_unstable();
    train.dedup();
    let adaptive = matches!(opts.sampling, Sampling::Adaptive { .. });
    let core: Vec<u32> = if adaptive {
        let mut c = vec![train[0], train[train.len() / 2]];
        c.retain(|&d| d != longest);
        c.dedup();
        c
    } else {
        train.iter().copied().filter(|&d| d != longest).collect()
    };
    let mut plan: Vec<(u32, bool)> = core.iter().map(|&d| (d, false)).collect();
    plan.extend(
        opts.delta_n_holdout
            .iter()
            .filter(|d| !train.contains(d))
            .map(|&d| (d, false)),
    );
    plan.extend(
        train
            .iter()
            .filter(|d| **d != longest && !core.contains(d))
            .map(|&d| (d, true)),
    );
    plan
}

/// What the held-out check says of the training measurements so far ([`held_out_check`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) enum HeldOut {
    /// The model fitted to them predicts every held-out measurement within the tolerance.
    Holds,
    /// It misses; `worst`: the held-out period it misses by the most (relative to the
    /// tolerance there), `None` when the model could not be fitted at all.
    Misses { worst: Option<u32> },
    /// No check is possible: `Sampling::Every`, or no held-out measurement yet.
    Unchecked,
}

/// Fit the error model to the training measurements so far and check it at every held-out
/// measurement ([`Sampling::Adaptive`]: within `tolerance` × the measured error +
/// [`Sampling::ABS_TOLERANCE`]).
pub(crate) fn held_out_check(measurements: &[Measurement], opts: &AnalyzeOptions) -> HeldOut {
    let Sampling::Adaptive { tolerance } = opts.sampling else {
        return HeldOut::Unchecked;
    };
    let held: Vec<&Measurement> = measurements
        .iter()
        .filter(|m| !is_training(opts, m.delta_n))
        .collect();
    if held.is_empty() {
        return HeldOut::Unchecked;
    }
    let samples: Vec<(f64, f64)> = measurements
        .iter()
        .filter(|m| is_training(opts, m.delta_n))
        .map(|m| (m.delta_n as f64, m.error))
        .collect();
    let fit = fit_error(&samples, &ErrorFitOptions::default());
    if !fit.is_ok() {
        return HeldOut::Misses { worst: None };
    }
    // Each miss as a multiple of the tolerance at its period (above 1: missed).
    let misses = held.iter().map(|m| {
        let slack = tolerance * m.error + Sampling::ABS_TOLERANCE;
        let miss = fit
            .predict(m.delta_n as f64)
            .map_or(f64::INFINITY, |p| (p - m.error).abs() / slack);
        (m.delta_n, if miss.is_nan() { f64::INFINITY } else { miss })
    });
    match misses
        .filter(|&(_, miss)| miss > 1.0)
        .max_by(|a, b| a.1.total_cmp(&b.1))
    {
        None => HeldOut::Holds,
        Some((dn, _)) => HeldOut::Misses { worst: Some(dn) },
    }
}

/// Which of the `remaining` training periods to replay next while the model misses a held-out
/// measurement: the one nearest the period it misses most (the shorter of two equally near),
/// where the curve most needs pinning; the first remaining when it could not be fitted.
pub(crate) fn next_period(remaining: &[u32], worst: Option<u32>) -> Option<u32> {
    match worst {
        Some(w) => remaining
            .iter()
            .copied()
            .min_by_key(|&d| (d.abs_diff(w), d)),
        None => remaining.first().copied(),
    }
}

impl Default for AnalyzeOptions {
    fn default() -> Self {
        AnalyzeOptions {
            delta_n_train: DEFAULT_TRAIN.to_vec(),
            delta_n_holdout: DEFAULT_HOLDOUT.to_vec(),
            prune: PruneOptions::default(),
            nodes: None,
            instance: InstanceOptions::default(),
            race_filters: false,
            strategies: Strategy::ALL.to_vec(),
            block: None,
            race_blocks: false,
            max_frames: None,
            journal: None,
            shard: None,
            sampling: Sampling::default(),
            probe_frames: None,
            race: DEFAULT_RACE,
            perceptual_stride: None,
            sets: Some(SetSearchOptions::default()),
            extension: Extension::default(),
            ceiling: true,
        }
    }
}

/// The periods must be measurable: at least 2, each named once (training and held out apart),
/// and at most ten times the replayed frames (`frames`); a period longer than the session is
/// measured only in part, which the returned warning says.
pub(crate) fn check_periods(
    opts: &AnalyzeOptions,
    frames: u32,
) -> Result<Vec<String>, AnalyzeError> {
    if opts.perceptual_stride == Some(0) {
        return Err(AnalyzeError::Options(
            "the perceptual metrics' frame stride must be at least 1".into(),
        ));
    }
    if opts.delta_n_train.is_empty() {
        return Err(AnalyzeError::Options(
            "--delta-n needs at least one period".into(),
        ));
    }
    if let Some(bad) = opts
        .delta_n_train
        .iter()
        .chain(&opts.delta_n_holdout)
        .find(|&&d| d < 2)
    {
        return Err(AnalyzeError::Options(format!(
            "refresh periods must be at least 2 (Δn = 1 is the original shader), got {bad}"
        )));
    }
    let mut seen = std::collections::BTreeSet::new();
    for d in opts.delta_n_train.iter().chain(&opts.delta_n_holdout) {
        if !seen.insert(*d) {
            return Err(AnalyzeError::Options(format!(
                "refresh period {d} is named twice in --delta-n/--holdout (each period once)"
            )));
        }
    }
    let limit = frames.saturating_mul(MAX_PERIODS_PER_SESSION);
    if let Some(bad) = seen.iter().find(|&&d| d > limit) {
        return Err(AnalyzeError::Options(format!(
            "refresh period {bad} (--delta-n/--holdout) is more than {MAX_PERIODS_PER_SESSION} times the {frames} frames replayed: nothing would be measured of it; use periods up to {limit} or a longer session"
        )));
    }
    Ok(seen
        .iter()
        .filter(|&&d| d > frames)
        .map(|d| {
            format!(
                "refresh period {d} is longer than the {frames} frames replayed: most pixels are never refreshed in the session, so its error is measured only in part"
            )
        })
        .collect())
}

/// How many times longer than the replayed frames a refresh period may be.
const MAX_PERIODS_PER_SESSION: u32 = 10;

/// Options of [`crate::search_sets`] (`analyze --set-top`, `--set-replays`, `--set-max-nodes`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct SetSearchOptions {
    /// Pairs are formed among this many single nodes, the largest predicted savings.
    pub top: usize,
    /// Replay this many pairs, the fastest predicted.
    pub replays: usize,
    /// Grow the best measured set up to this many nodes (2: pairs only).
    pub max_nodes: usize,
}

impl Default for SetSearchOptions {
    fn default() -> Self {
        SetSearchOptions {
            top: 6,
            replays: 3,
            max_nodes: 3,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_training_periods_are_the_paper_s_and_span_the_range() {
        assert_eq!(DEFAULT_TRAIN, [2, 10, 18, 26, 34, 42, 50]);
    }

    fn opts(sampling: Sampling) -> AnalyzeOptions {
        AnalyzeOptions {
            sampling,
            ..Default::default()
        }
    }

    #[test]
    fn adaptive_sampling_replays_three_training_periods_then_the_held_out_ones() {
        let plan = period_plan(&opts(Sampling::default()), 50);
        assert_eq!(
            plan,
            [
                (2, false),
                (26, false),
                (6, false),
                (30, false),
                (10, true),
                (18, true),
                (34, true),
                (42, true)
            ]
        );
        let every = period_plan(&opts(Sampling::Every), 50);
        assert_eq!(
            every.iter().map(|p| p.0).collect::<Vec<_>>(),
            [2, 10, 18, 26, 34, 42, 6, 30]
        );
        assert!(every.iter().all(|p| !p.1));
    }

    /// A measurement at `dn` with error `e` (other fields are not looked at).
    fn m(dn: u32, e: f64) -> Measurement {
        serde_json::from_value(serde_json::json!({
            "delta_n": dn, "error": e, "psnr": null, "hit_rate": 0.9, "frame_ms": 1.0, "frames": []
        }))
        .unwrap()
    }

    /// A replay at `dn` with error `e`, hit rate `hit` and frame time `ms`.
    fn replay(dn: u32, e: f64, hit: f64, ms: f64) -> Measurement {
        serde_json::from_value(serde_json::json!({
            "delta_n": dn, "error": e, "psnr": null, "hit_rate": hit, "frame_ms": ms, "frames": []
        }))
        .unwrap()
    }

    #[test]
    fn periods_extend_only_while_a_longer_one_can_pay_under_the_loosest_budget() {
        let ext = Extension::default();
        // Marble on lavapipe at 256×256, Δn 50, 2.89× raced: 2.9 % at most to gain (the
        // variant's own passes dominate).
        let lavapipe = replay(50, 0.019, 0.969, 2.6);
        match next_extension(&lavapipe, 2.89, 150, &ext) {
            Err(ExtensionStop::Gain { gain }) => assert!((gain - 0.0286).abs() < 0.001, "{gain}"),
            other => panic!("{other:?}"),
        }
        // An expensive original over a cheap variant: refreshing is a real part of the frame.
        let expensive = replay(50, 0.003, 0.98, 2.0);
        assert_eq!(next_extension(&expensive, 10.0, 150, &ext), Ok(100));
        // Never past the replayed frames, nor past the longest allowed.
        let at_100 = replay(100, 0.004, 0.99, 1.9);
        assert_eq!(
            next_extension(&at_100, 10.0, 150, &ext),
            Err(ExtensionStop::Limit { limit: 150 })
        );
        let short = Extension {
            max_delta_n: 50,
            ..ext
        };
        assert_eq!(
            next_extension(&expensive, 10.0, 150, &short),
            Err(ExtensionStop::Limit { limit: 50 })
        );
        // An error already at the loosest budget (or not a number) stops it.
        let coarse = replay(50, 0.12, 0.98, 2.0);
        assert_eq!(
            next_extension(&coarse, 10.0, 150, &ext),
            Err(ExtensionStop::Error { error: 0.12 })
        );
        let mut nan = replay(50, 0.0, 0.98, 2.0);
        nan.error = f64::NAN;
        assert!(matches!(
            next_extension(&nan, 10.0, 150, &ext),
            Err(ExtensionStop::Error { .. })
        ));
        // A frame time of zero or a hit rate of zero gives no gain to speak of.
        let nothing = replay(50, 0.003, 0.0, 2.0);
        assert_eq!(
            next_extension(&nothing, 10.0, 150, &ext),
            Err(ExtensionStop::Gain { gain: 0.0 })
        );
        assert_eq!(
            next_extension(&expensive, f64::NAN, 150, &ext),
            Err(ExtensionStop::Gain { gain: 0.0 })
        );
        assert_eq!(
            next_extension(&expensive, 10.0, 150, &Extension::OFF).ok(),
            None
        );
    }

    #[test]
    fn periods_past_the_training_ones_train_the_fits() {
        let o = opts(Sampling::default());
        assert!(is_training(&o, 50) && is_training(&o, 100) && is_training(&o, 2));
        assert!(!is_training(&o, 30) && !is_training(&o, 6));
    }

    #[test]
    fn the_held_out_check_decides_whether_more_periods_are_replayed() {
        let o = opts(Sampling::default());
        let model = |dn: u32| 0.05 * (1.0 - (-0.08 * (dn as f64 - 1.0)).exp());
        let mut ms: Vec<Measurement> = [50, 2, 26, 6, 30].map(|d| m(d, model(d))).to_vec();
        assert_eq!(
            held_out_check(&ms, &o),
            HeldOut::Holds,
            "an exact exponential is predicted"
        );
        // A held-out error 40 % off the curve: replay more periods, near that one first.
        ms[4] = m(30, model(30) * 1.4);
        assert_eq!(held_out_check(&ms, &o), HeldOut::Misses { worst: Some(30) });
        // Both off: the worse miss (relative to its tolerance) names the period.
        ms[3] = m(6, model(6) * 1.2);
        assert_eq!(held_out_check(&ms, &o), HeldOut::Misses { worst: Some(30) });
        ms[3] = m(6, model(6) * 3.0);
        assert_eq!(held_out_check(&ms, &o), HeldOut::Misses { worst: Some(6) });
        // Two training periods cannot be fitted: a miss without a period.
        let two = [m(50, model(50)), m(2, model(2)), m(6, model(6))];
        assert_eq!(held_out_check(&two, &o), HeldOut::Misses { worst: None });
        // No held-out measurement, or `every`: no check.
        assert_eq!(held_out_check(&ms[..3], &o), HeldOut::Unchecked);
        ms[4] = m(30, model(30));
        assert_eq!(
            held_out_check(&ms, &opts(Sampling::Every)),
            HeldOut::Unchecked
        );
    }

    #[test]
    fn the_period_nearest_the_worst_miss_is_replayed_next() {
        let remaining = [10, 18, 34, 42];
        assert_eq!(next_period(&remaining, Some(6)), Some(10));
        assert_eq!(next_period(&remaining, Some(30)), Some(34));
        // Equally near: the shorter.
        assert_eq!(next_period(&[10, 18], Some(14)), Some(10));
        // No fit: in plan order.
        assert_eq!(next_period(&[34, 10], None), Some(34));
        assert_eq!(next_period(&[], Some(6)), None);
    }
}
