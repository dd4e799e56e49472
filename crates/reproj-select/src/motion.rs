//! A profile's records carried to a session of other motion (`reproj_models::motion`): the error
//! model time-warped, the measured errors moved to the periods they stand for there, and the
//! held-out predictions that choose the motion exponent β across profiles.

use reproj_models::ErrorFit;
use reproj_models::HitRateFit;
use reproj_models::motion::{MIN_MOTION_RATIO, STATIC_PIXELS, period_scale, warped_period};

use crate::{NodeRecord, SelectOptions, SetRecord, predicted_error, respect_measurements};

/// `fit` on a session whose motion ages the cache `r` times as fast: ε̂'(Δn) = ε̂(1 + (Δn − 1)·r),
/// that is λ·r for the exponential model.
pub fn warp_fit(fit: &ErrorFit, r: f64) -> ErrorFit {
    let mut out = fit.clone();
    if let Some(l) = out.lambda.as_mut() {
        *l *= r;
    }
    out
}

/// The measured `(Δn, error)` pairs as bounds on a session `r` times as fast: a measurement at
/// Δn stands for period `1 + (Δn − 1)/r` there, rounded down (the error is then claimed at a
/// period no longer than the one it stands for: the cautious side); pairs that land below Δn = 2
/// are dropped.
pub fn warp_measured(measured: &[(u32, f64)], r: f64) -> Vec<(u32, f64)> {
    let mut out: Vec<(u32, f64)> = Vec::new();
    for &(dn, e) in measured {
        // (An epsilon: r a rounding away from 1 must not move a period down by one.)
        let p = (warped_period(f64::from(dn), 1.0 / r) + 1e-9).floor();
        if !(p.is_finite() && p >= 2.0) {
            continue;
        }
        let p = p.min(f64::from(u32::MAX)) as u32;
        // Two measurements on one period: the larger error holds.
        match out.iter_mut().find(|(q, _)| *q == p) {
            Some(slot) => slot.1 = slot.1.max(e),
            None => out.push((p, e)),
        }
    }
    out
}

impl NodeRecord {
    /// This node on a session whose motion ages the cache `r` times as fast as the profiled one
    /// ([`warp_fit`], [`warp_measured`]). The timing model is kept: the speed on the new session
    /// is measured by `--verify`, not predicted.
    pub fn at_motion(&self, r: f64) -> NodeRecord {
        NodeRecord {
            error: warp_fit(&self.error, r),
            measured_errors: warp_measured(&self.measured_errors, r),
            ..self.clone()
        }
    }
}

impl SetRecord {
    /// The set on a session of other motion, as [`NodeRecord::at_motion`].
    pub fn at_motion(&self, r: f64) -> SetRecord {
        SetRecord {
            error: warp_fit(&self.error, r),
            measured_errors: warp_measured(&self.measured_errors, r),
            ..self.clone()
        }
    }
}

/// One profiled session for [`cross_predictions`]: its motion (pixels per frame) and records.
#[derive(Debug, Clone, Copy)]
pub struct Profiled<'a> {
    pub motion: f64,
    pub nodes: &'a [NodeRecord],
}

/// Held-out predictions at exponent `beta`: for every ordered pair of profiles whose motions
/// differ by at least [`MIN_MOTION_RATIO`], every node both measured with a usable error model,
/// and every period the second measured (Δn ≥ 2) within what the first covers once carried over,
/// the pair (the first's model carried to the second's motion, the second's measurement).
pub fn cross_predictions(profiles: &[Profiled<'_>], beta: f64) -> Vec<(f64, f64)> {
    let mut out = Vec::new();
    for a in profiles {
        for b in profiles {
            let ratio = (b.motion / a.motion).max(a.motion / b.motion);
            if !(ratio.is_finite() && ratio >= MIN_MOTION_RATIO) {
                continue;
            }
            let r = period_scale(a.motion, b.motion, beta);
            for na in a.nodes.iter().filter(|n| n.error.is_ok()) {
                let Some(nb) = b.nodes.iter().find(|n| n.id == na.id) else {
                    continue;
                };
                let carried = na.at_motion(r);
                for &(dn, measured) in nb.measured_errors.iter().filter(|(dn, _)| *dn >= 2) {
                    let covered = !matches!(
                        respect_measurements(&carried.measured_errors, dn),
                        crate::MeasuredBound::Beyond { .. }
                    );
                    if let (true, Some(p)) = (covered, carried.error.predict(f64::from(dn))) {
                        out.push((p, measured));
                    }
                }
            }
        }
    }
    out
}

/// Bands of a run-time schedule start at a quarter of the slowest profiled motion and grow by √2
/// until they pass twice the fastest; the last band (any faster: motion no profile saw) is
/// predicted at [`SCHEDULE_BEYOND`] times the fastest, the cautious side.
pub const SCHEDULE_BEYOND: f64 = 16.0;

/// The run-time Δn schedule of a chosen node (or set, [`SetRecord::as_node`]) from its records in
/// the profiled sessions, each with that session's motion (pixels per frame), and the motion
/// exponent `beta`: per band, its fastest motion (`None`: any faster) and the longest Δn in
/// `opts`' range whose error predicted at that motion — from each profile nearest in motion to
/// some motion of the band, carried there — holds `opts.max_error` (1 where none does: the
/// original's result).
/// Neighbouring bands with the same Δn are merged, and a faster band never gets a longer period
/// than a slower one. Empty when no profiled motion is a number above static.
pub fn schedule(
    records: &[(f64, &NodeRecord)],
    beta: f64,
    opts: &SelectOptions,
) -> Vec<(Option<f64>, u32)> {
    let records: Vec<(f64, &NodeRecord)> = records
        .iter()
        .copied()
        .filter(|(m, _)| m.is_finite() && *m >= reproj_models::motion::STATIC_PIXELS)
        .collect();
    let (Some(slowest), Some(fastest)) = (
        records.iter().map(|r| r.0).reduce(f64::min),
        records.iter().map(|r| r.0).reduce(f64::max),
    ) else {
        return Vec::new();
    };
    let nearest = |m: f64| -> (f64, &NodeRecord) {
        records
            .iter()
            .min_by(|a, b| (a.0 / m).ln().abs().total_cmp(&(b.0 / m).ln().abs()))
            .copied()
            .expect("one record at least")
    };
    // A band (lo, up] holds where every profile that is nearest to some motion in it — the ones
    // nearest its two ends and any inside it — predicts the budget at `up`, carried there: the
    // frames of the band are then within the budget whichever profile is nearest to them.
    let longest_in = |lo: f64, up: f64| -> u32 {
        let mut near: Vec<(f64, &NodeRecord)> = vec![nearest(lo), nearest(up)];
        near.extend(records.iter().filter(|r| r.0 > lo && r.0 < up).copied());
        let carried: Vec<NodeRecord> = near
            .iter()
            .map(|(profiled, record)| record.at_motion(period_scale(*profiled, up, beta)))
            .collect();
        (opts.min_delta_n.max(2)..=opts.max_delta_n)
            .rev()
            .find(|&dn| {
                carried
                    .iter()
                    .all(|c| predicted_error(c, dn).is_some_and(|e| opts.max_error.admits(e)))
            })
            .unwrap_or(1)
    };
    let mut bands: Vec<(Option<f64>, u32)> = Vec::new();
    let mut lo = STATIC_PIXELS;
    let mut m = slowest / 4.0;
    while m <= fastest * 2.0 {
        bands.push((Some(m), longest_in(lo, m)));
        lo = m;
        m *= std::f64::consts::SQRT_2;
    }
    bands.push((None, longest_in(lo, fastest * SCHEDULE_BEYOND)));
    for i in 1..bands.len() {
        bands[i].1 = bands[i].1.min(bands[i - 1].1);
    }
    let mut merged: Vec<(Option<f64>, u32)> = Vec::new();
    for b in bands {
        match merged.last_mut() {
            Some(last) if last.1 == b.1 => last.0 = b.0,
            _ => merged.push(b),
        }
    }
    merged
}

/// The Δn a schedule gives a frame of motion `pixels_per_frame`: the first band that reaches it,
/// the last band beyond (and for a motion that is not a number); `None` for an empty schedule.
/// The same rule as the manifest's `Params::delta_n_for`, which a host applies.
pub fn delta_n_in(schedule: &[(Option<f64>, u32)], pixels_per_frame: f64) -> Option<u32> {
    let last = schedule.last()?;
    if !pixels_per_frame.is_finite() {
        return Some(last.1);
    }
    Some(
        schedule
            .iter()
            .find(|b| b.0.is_none_or(|up| pixels_per_frame <= up))
            .unwrap_or(last)
            .1,
    )
}

/// One profiled session's view of a candidate of [`predict_adaptive`].
#[derive(Debug, Clone, Copy)]
pub struct ProfiledRecord<'a> {
    /// The session's motion, pixels per frame.
    pub motion: f64,
    /// The candidate's record there.
    pub record: &'a NodeRecord,
    /// That session's hit-rate fit.
    pub hit_rate: &'a HitRateFit,
    /// The original shader's frame time there, ms.
    pub original_ms: f64,
}

/// What a candidate's run-time schedule is predicted to do over a trace of per-frame motion.
#[derive(Debug, Clone, PartialEq)]
pub struct AdaptivePrediction {
    /// The schedule ([`schedule`]).
    pub schedule: Vec<(Option<f64>, u32)>,
    /// Δn of each frame of the trace.
    pub delta_n_per_frame: Vec<u32>,
    /// Mean predicted frame time over the trace, ms.
    pub predicted_ms: f64,
    /// Mean frame time of the original over the trace (each frame at the profile nearest in
    /// motion), ms.
    pub original_ms: f64,
    /// `original_ms / predicted_ms`.
    pub predicted_speedup: f64,
    /// The largest predicted error of one frame (0 at Δn 1, where every pixel is recomputed).
    pub worst_error: f64,
    /// The mean predicted error over the frames.
    pub mean_error: f64,
}

/// Predict a candidate under its run-time schedule over `trace` (each frame's on-screen motion,
/// pixels per frame): per frame, the Δn the schedule gives it, and the error and time predicted
/// from the profile nearest in motion (the error carried to the frame's motion with `beta`, the
/// time as profiled: speed is not carried). `None` when no profiled motion is usable (no
/// schedule), the trace is empty, or a prediction is not a number.
pub fn predict_adaptive(
    records: &[ProfiledRecord<'_>],
    beta: f64,
    trace: &[f64],
    opts: &SelectOptions,
) -> Option<AdaptivePrediction> {
    let with_motion: Vec<(f64, &NodeRecord)> =
        records.iter().map(|r| (r.motion, r.record)).collect();
    let schedule = schedule(&with_motion, beta, opts);
    if schedule.is_empty() || trace.is_empty() {
        return None;
    }
    let floor = |m: f64| {
        if m.is_finite() {
            m.max(STATIC_PIXELS)
        } else {
            f64::INFINITY
        }
    };
    let mut per_frame = Vec::with_capacity(trace.len());
    let (mut ms, mut original, mut worst, mut sum_error) = (0.0, 0.0, 0.0f64, 0.0);
    // A frame that does not move (the first frame has no previous one) is predicted as the
    // slowest band's fastest motion: what the schedule promised there (an error model carried
    // to no motion at all would not age, which says nothing).
    let slowest_band = schedule[0].0.unwrap_or(STATIC_PIXELS);
    for &m in trace {
        let dn = delta_n_in(&schedule, m)?;
        let m = if m.is_finite() && m < STATIC_PIXELS {
            slowest_band
        } else {
            m
        };
        let nearest = records
            .iter()
            .filter(|r| r.motion.is_finite() && r.motion >= STATIC_PIXELS)
            .min_by(|a, b| {
                (a.motion / floor(m))
                    .ln()
                    .abs()
                    .total_cmp(&(b.motion / floor(m)).ln().abs())
            })?;
        let error = if dn <= 1 {
            0.0
        } else {
            let carried = nearest
                .record
                .at_motion(period_scale(nearest.motion, m, beta));
            predicted_error(&carried, dn)?
        };
        let t = crate::predict(nearest.record, nearest.hit_rate, dn)?.predicted_ms;
        per_frame.push(dn);
        ms += t;
        original += nearest.original_ms;
        worst = worst.max(error);
        sum_error += error;
    }
    let n = trace.len() as f64;
    let (ms, original) = (ms / n, original / n);
    (ms.is_finite() && ms > 0.0 && original.is_finite() && original > 0.0).then(|| {
        AdaptivePrediction {
            schedule,
            delta_n_per_frame: per_frame,
            predicted_ms: ms,
            original_ms: original,
            predicted_speedup: original / ms,
            worst_error: worst,
            mean_error: sum_error / n,
        }
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use reproj_models::{ErrorFitOptions, fit_error};

    #[test]
    fn a_faster_session_moves_the_measurements_to_shorter_periods() {
        let m = [(2, 0.01), (10, 0.05), (26, 0.08), (50, 0.1)];
        // Twice as fast: Δn 10 stands for 1 + 9/2 = 5.5 → 5; Δn 2 → 1.5: dropped.
        assert_eq!(
            warp_measured(&m, 2.0),
            vec![(5, 0.05), (13, 0.08), (25, 0.1)]
        );
        // Half as fast: longer periods.
        assert_eq!(warp_measured(&m, 0.5)[0], (3, 0.01));
        // Collapsing onto one period keeps the larger error.
        assert_eq!(warp_measured(&[(3, 0.01), (4, 0.02)], 4.0), Vec::new());
        assert_eq!(
            warp_measured(&[(9, 0.01), (10, 0.02)], 4.0),
            vec![(3, 0.02)]
        );
    }

    #[test]
    fn the_schedule_shortens_the_period_as_motion_grows() {
        let samples: Vec<(f64, f64)> = [2.0, 8.0, 16.0, 24.0, 32.0]
            .iter()
            .map(|&d| (d, 0.02 * (1.0 - (-0.05f64 * (d - 1.0)).exp())))
            .collect();
        let error = fit_error(&samples, &ErrorFitOptions::default());
        let record = NodeRecord {
            id: 3,
            text: "n".into(),
            strategy: "3pass".into(),
            error,
            timing: reproj_models::TimingFit::from_costs(1e-5, 2e-5, 0.5, 1000.0),
            mean_pixels: 1000.0,
            measured: None,
            measured_errors: samples.iter().map(|&(d, e)| (d as u32, e)).collect(),
        };
        let opts = SelectOptions::new(crate::Budget::new(0.008).unwrap());
        let s = schedule(&[(2.0, &record)], 1.0, &opts);
        assert!(s.len() >= 3, "{s:?}");
        assert_eq!(s.last().unwrap().0, None);
        for w in s.windows(2) {
            assert!(w[0].1 > w[1].1, "periods shrink as motion grows: {s:?}");
            assert!(w[0].0.unwrap() < w[1].0.unwrap_or(f64::INFINITY));
        }
        // At the profiled motion the band's Δn is the longest the profile itself allows.
        let at_profiled = s
            .iter()
            .find(|b| b.0.is_none_or(|m| m >= 2.0 - 1e-9))
            .unwrap()
            .1;
        let direct = (2..=50)
            .rev()
            .find(|&dn| predicted_error(&record, dn).is_some_and(|e| e <= 0.008))
            .unwrap();
        assert_eq!(at_profiled, direct, "{s:?}");
        // Static: no schedule.
        assert!(schedule(&[(0.0, &record)], 1.0, &opts).is_empty());
        // A second profile at 8 px/frame, measured as if nothing changed with motion: the bands
        // near it follow that profile, no longer the first carried 4× or more.
        let two = schedule(&[(2.0, &record), (8.0, &record)], 1.0, &opts);
        let at = |s: &[(Option<f64>, u32)], m: f64| {
            s.iter().find(|b| b.0.is_none_or(|up| m <= up)).unwrap().1
        };
        for m in [4.0, 8.0, 11.0] {
            assert!(at(&two, m) >= at(&s, m), "{m}: {two:?} {s:?}");
        }
        assert!(at(&two, 8.0) > at(&s, 8.0), "{two:?} {s:?}");
    }

    #[test]
    fn the_warped_fit_predicts_the_profiled_error_at_the_warped_period() {
        let samples: Vec<(f64, f64)> = [2.0, 6.0, 10.0, 20.0, 30.0]
            .iter()
            .map(|&d| (d, 0.1 * (1.0 - (-0.07f64 * (d - 1.0)).exp())))
            .collect();
        let fit = fit_error(&samples, &ErrorFitOptions::default());
        assert!(fit.is_ok(), "{fit:?}");
        let w = warp_fit(&fit, 3.0);
        for dn in [2.0, 5.0, 9.0] {
            let a = w.predict(dn).unwrap();
            let b = fit.predict(warped_period(dn, 3.0)).unwrap();
            assert!((a - b).abs() < 1e-12, "{dn}: {a} {b}");
        }
    }

    #[test]
    fn an_adaptive_schedule_holds_every_frame_and_beats_the_fixed_period_that_holds_everywhere() {
        let samples: Vec<(f64, f64)> = [2.0, 8.0, 16.0, 24.0, 32.0]
            .iter()
            .map(|&d| (d, 0.02 * (1.0 - (-0.05f64 * (d - 1.0)).exp())))
            .collect();
        let record = NodeRecord {
            id: 3,
            text: "n".into(),
            strategy: "2pass".into(),
            error: fit_error(&samples, &ErrorFitOptions::default()),
            timing: reproj_models::TimingFit::from_costs(1e-5, 2e-5, 0.5, 1000.0),
            mean_pixels: 1000.0,
            measured: None,
            measured_errors: samples.iter().map(|&(d, e)| (d as u32, e)).collect(),
        };
        let hit = HitRateFit::from_mu(0.95);
        let original_ms = 0.05;
        let at = |motion| ProfiledRecord {
            motion,
            record: &record,
            hit_rate: &hit,
            original_ms,
        };
        let opts = SelectOptions::new(crate::Budget::new(0.008).unwrap());
        // Mostly slow (1 px/frame) with a burst of fast motion (8 px/frame).
        let trace: Vec<f64> = (0..72)
            .map(|f| if (30..42).contains(&f) { 8.0 } else { 1.0 })
            .collect();
        let p = predict_adaptive(&[at(1.0), at(8.0)], 1.0, &trace, &opts).unwrap();
        assert!(p.worst_error <= 0.008, "{p:?}");
        let slow = p.delta_n_per_frame[0];
        let fast = p.delta_n_per_frame[35];
        assert!(slow > fast, "{p:?}");
        // The fixed period that holds on both is the fast one's: the schedule is faster.
        let fixed = crate::predict(&record, &hit, fast).unwrap().predicted_ms;
        assert!(p.predicted_ms < fixed, "{} vs {fixed}", p.predicted_ms);
        assert!((p.predicted_speedup - original_ms / p.predicted_ms).abs() < 1e-12);
        // No usable motion, or no frames: no prediction.
        assert!(predict_adaptive(&[at(0.0)], 1.0, &trace, &opts).is_none());
        assert!(predict_adaptive(&[at(1.0)], 1.0, &[], &opts).is_none());
        assert_eq!(
            delta_n_in(&p.schedule, f64::NAN),
            p.schedule.last().map(|b| b.1)
        );
    }
}
