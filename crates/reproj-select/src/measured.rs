//! What a profile measured, holding the models to it: the error predicted at a period kept at or
//! above the measured errors around it, the timing model's level calibrated by the interleaved
//! race against the original, and a node's [`NodeRecord`] built from its fits and both.

use reproj_models::predicted_frame_ms;
use serde::{Deserialize, Serialize};

use crate::NodeRecord;

/// What the measured errors say of the error at one Δn ([`respect_measurements`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum MeasuredBound {
    /// No measurement to go by.
    Unmeasured,
    /// Measured at this Δn (the larger, if measured twice).
    Exact(f64),
    /// Between two measured periods (Δn = 1 counts as measured at 0: it reproduces the
    /// original): `(Δn, error)` below and above, and the line between them at this Δn.
    Between {
        below: (u32, f64),
        above: (u32, f64),
        chord: f64,
    },
    /// Past the longest measured period: not predicted (the model would extrapolate).
    Beyond { longest: u32 },
}

/// Where `delta_n` lies among the measured errors.
pub fn respect_measurements(measured: &[(u32, f64)], delta_n: u32) -> MeasuredBound {
    let finite: Vec<(u32, f64)> = measured
        .iter()
        .copied()
        .filter(|(_, e)| e.is_finite())
        .collect();
    let Some(longest) = finite.iter().map(|m| m.0).max() else {
        return MeasuredBound::Unmeasured;
    };
    if delta_n > longest {
        return MeasuredBound::Beyond { longest };
    }
    // The worst measurement at a period (a period measured twice keeps the larger error).
    let at = |dn: u32| {
        finite
            .iter()
            .filter(|m| m.0 == dn)
            .map(|m| m.1)
            .fold(f64::NEG_INFINITY, f64::max)
    };
    if finite.iter().any(|m| m.0 == delta_n) {
        return MeasuredBound::Exact(at(delta_n));
    }
    let below = finite
        .iter()
        .map(|m| m.0)
        .filter(|&d| d < delta_n)
        .max()
        .map_or((1, 0.0), |d| (d, at(d)));
    let above = finite
        .iter()
        .map(|m| m.0)
        .filter(|&d| d > delta_n)
        .min()
        .expect("delta_n is below the longest");
    let above = (above, at(above));
    let t = f64::from(delta_n - below.0) / f64::from(above.0 - below.0);
    MeasuredBound::Between {
        below,
        above,
        chord: below.1 + t * (above.1 - below.1),
    }
}

/// The error predicted for `node` at `delta_n`, held to what the profile measured: at a measured
/// period never below the measurement; between two, never below the line between them nor below
/// the model scaled by how much it under-predicted those two neighbours; past the longest
/// measured period, none.
pub fn predicted_error(node: &NodeRecord, delta_n: u32) -> Option<f64> {
    let model = |dn: u32| node.error.predict(f64::from(dn));
    let m = model(delta_n)?;
    Some(match respect_measurements(&node.measured_errors, delta_n) {
        MeasuredBound::Unmeasured => m,
        MeasuredBound::Exact(e) => m.max(e),
        MeasuredBound::Between {
            below,
            above,
            chord,
        } => {
            // How far the model falls short of each measured neighbour (Δn = 1 is no check).
            let short = |(dn, e): (u32, f64)| match model(dn) {
                Some(p) if dn > 1 && p > 0.0 && e.is_finite() => e / p,
                _ => 1.0,
            };
            (m * short(below).max(short(above)).max(1.0)).max(chord)
        }
        MeasuredBound::Beyond { .. } => return None,
    })
}

/// The `(Δn, value)` pairs a node (or set) measured for `metric`.
pub fn measured_errors(
    measurements: &[reproj_models::profile::Measurement],
    metric: reproj_models::Metric,
) -> Vec<(u32, f64)> {
    measurements
        .iter()
        .filter_map(|m| Some((m.delta_n, m.value(metric)?)))
        .collect()
}

/// How interleaved measurements set a node's frame time. With one race, the timing model gives
/// the shape of the frame time over Δn (its ratio between two periods), the race its level, so
/// the predicted speedup at Δn is the measured one × t̂(Δn_measured) / t̂(Δn), with the measured
/// interval carried along. With a second race at another period ([`RaceLine`]) the races give the
/// shape too, and the replays' times are not used.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Calibration {
    /// The period the speedup was measured at.
    pub delta_n: u32,
    /// Factor on t̂: `original_ms / (measured speedup × t̂(delta_n))`.
    pub ms_scale: f64,
    /// The measured 95 % interval over the measured speedup (`[lo / s, hi / s]`).
    pub rel_ci95: [f64; 2],
    /// The frame time along two races, where the node was raced at a second period.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub line: Option<RaceLine>,
}

/// One race of a node's variant: the hit rate γ at its period, the frame time it implies (the
/// original's over the speedup) and its interval relative to the speedup.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct RacePoint {
    pub delta_n: u32,
    pub gamma: f64,
    pub ms: f64,
    pub rel_ci95: [f64; 2],
}

/// A node's frame time from two races at two periods: linear in the hit rate γ between them (a
/// frame's work is its hits' and its misses' — eq. 3 — and γ(Δn) is counted, not timed), the
/// interval interpolated between theirs. Beyond the two the line is extended, its interval the
/// nearer race's.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct RaceLine {
    pub points: [RacePoint; 2],
}

impl RaceLine {
    /// From two races, `None` where their hit rates are too close to tell a slope (or a figure
    /// is not finite).
    pub fn new(a: RacePoint, b: RacePoint) -> Option<RaceLine> {
        let finite = |p: &RacePoint| {
            p.gamma.is_finite()
                && p.ms.is_finite()
                && p.ms > 0.0
                && p.rel_ci95.iter().all(|r| r.is_finite() && *r > 0.0)
        };
        ((a.gamma - b.gamma).abs() > 1e-6 && finite(&a) && finite(&b)).then(|| {
            let mut points = [a, b];
            points.sort_by(|x, y| x.gamma.total_cmp(&y.gamma));
            RaceLine { points }
        })
    }

    /// Where γ lies between the two races: 0 at the first (lower γ), 1 at the second.
    fn at(&self, gamma: f64) -> f64 {
        let [a, b] = self.points;
        (gamma - a.gamma) / (b.gamma - a.gamma)
    }

    /// The frame time at hit rate `gamma`, ms; never below a tenth of the faster race's (a line
    /// extended far past its races is not a measurement).
    pub fn ms_at(&self, gamma: f64) -> f64 {
        let [a, b] = self.points;
        let t = self.at(gamma);
        (a.ms + t * (b.ms - a.ms)).max(0.1 * a.ms.min(b.ms))
    }

    /// The interval at `gamma`, relative to the speedup there.
    pub fn rel_ci95_at(&self, gamma: f64) -> [f64; 2] {
        let [a, b] = self.points;
        let t = self.at(gamma).clamp(0.0, 1.0);
        [0, 1].map(|i| a.rel_ci95[i] + t * (b.rel_ci95[i] - a.rel_ci95[i]))
    }
}

impl Calibration {
    /// From a speedup `speedup` [`ci95`] measured at `delta_n`, the original's time and the
    /// model's `t̂(delta_n)`; `None` unless every number is finite and positive.
    pub fn new(
        delta_n: u32,
        speedup: f64,
        ci95: [f64; 2],
        original_ms: f64,
        model_ms: f64,
    ) -> Option<Calibration> {
        let scale = original_ms / (speedup * model_ms);
        let rel = [ci95[0] / speedup, ci95[1] / speedup];
        (scale.is_finite() && scale > 0.0 && rel.iter().all(|r| r.is_finite() && *r > 0.0))
            .then_some(Calibration {
                delta_n,
                ms_scale: scale,
                rel_ci95: rel,
                line: None,
            })
    }
}

impl NodeRecord {
    /// The selector's view of `node` in `profile` with its error model for `metric`: its fits,
    /// its interleaved race ([`calibration`]) and its measured errors ([`measured_errors`]) — the
    /// one way `emit`, `report`, `compare` and the charts build it, so they choose alike. `None`
    /// when the profile has no model for `metric`.
    pub fn from_profile(
        profile: &reproj_models::Profile,
        node: &reproj_models::profile::NodeProfile,
        metric: reproj_models::Metric,
    ) -> Option<NodeRecord> {
        Some(NodeRecord {
            id: node.id,
            text: node.text.clone(),
            strategy: node.strategy.clone(),
            error: node.fit(metric)?.clone(),
            timing: node.timing_fit.clone(),
            mean_pixels: profile.original.mean_pixels,
            measured: calibration(profile, node),
            measured_errors: measured_errors(&node.measurements, metric),
        })
    }
}

/// The calibration of `node`'s timing model in `profile` by its strategy's interleaved race
/// against the original (`analyze`, profile version 7 on) — or, where the node kept a filter other
/// than the profile's, by that filter's race (`filter_probes`, version 9), since the strategy race
/// timed the profile's filter; likewise a block size kept by a block race (`block_probes`,
/// version 10); `None` for older profiles or a node whose race gave no estimate.
pub fn calibration(
    profile: &reproj_models::Profile,
    node: &reproj_models::profile::NodeProfile,
) -> Option<Calibration> {
    let filter = node.reconstruct_in(profile);
    let (delta_n, speedup, ci95) = if filter != profile.reconstruct {
        let probe = profile.filter_probes.iter().find(|p| {
            p.node == node.id
                && p.kept
                && p.strategy == node.strategy
                && p.reconstruct.as_deref() == Some(filter)
        })?;
        (
            probe.delta_n,
            probe.timed.speedup?,
            probe.timed.speedup_ci95?,
        )
    } else if let Some(probe) = profile.block_probes.iter().find(|p| {
        p.node == node.id && p.kept && p.strategy == node.strategy && Some(p.block) == node.block
    }) {
        // A block race's kept size (version 10): timed at the longest period as the strategy
        // race was, but with the block the node was profiled with.
        (
            probe.delta_n,
            probe.timed.speedup?,
            probe.timed.speedup_ci95?,
        )
    } else {
        let probe = profile
            .strategy_probes
            .iter()
            .find(|p| p.node == node.id && p.kept && p.strategy == node.strategy)?;
        (
            probe.delta_n,
            probe.timed.speedup?,
            probe.timed.speedup_ci95?,
        )
    };
    let model_ms = predicted_frame_ms(
        &node.timing_fit,
        &profile.hit_rate,
        f64::from(delta_n),
        profile.original.mean_pixels,
    )?;
    let mut c = Calibration::new(delta_n, speedup, ci95, profile.original.frame_ms, model_ms)?;
    // The same variant raced at a second period (profile version 13): the shape from the races.
    let original_ms = profile.original.frame_ms;
    let point = |delta_n: u32, speedup: f64, ci95: [f64; 2]| {
        Some(RacePoint {
            delta_n,
            gamma: profile.hit_rate.gamma(f64::from(delta_n))?,
            ms: original_ms / speedup,
            rel_ci95: [ci95[0] / speedup, ci95[1] / speedup],
        })
    };
    // (A kept filter's race timed another variant than the period probe's.)
    let probes = if filter == profile.reconstruct {
        profile.period_probes.as_slice()
    } else {
        &[]
    };
    c.line = probes
        .iter()
        .find(|p| {
            p.node == node.id
                && p.strategy == node.strategy
                && node.block.is_none_or(|b| b == p.block)
                && p.delta_n != delta_n
        })
        .and_then(|p| {
            let second = point(p.delta_n, p.timed.speedup?, p.timed.speedup_ci95?)?;
            RaceLine::new(point(delta_n, speedup, ci95)?, second)
        });
    Some(c)
}
