//! The shape of a node's frame time over Δn, from races where the replays cannot be trusted with
//! it. A frame's work is its hits' and its misses' (eq. 3), so the replays' mean frame times lie
//! on a line in their miss rate — unless the clock moved between them: a GPU's does between
//! readback pauses (on the H200, marble's node 680 took 4.38 ms at Δn 2, 2.87 at 26, 3.88 at 30,
//! 1.72 at 50), and so does a shared CPU machine's. Where the replays stray from that line by more
//! than [`REPLAY_SPREAD`], the node's kept variant is raced against the original at a second
//! period, the shortest of the plan, beside its strategy race at the longest, and the selector
//! draws its frame time along the line between the two races ([`reproj_select::RaceLine`]).
//! Where they agree, the timing model fitted to them keeps the shape, the race the level, and no
//! race is spent (a quiet lavapipe: marble's replays stray 4–11 %).

use reproj_models::profile::{Measurement, StrategyProbe};

use crate::AnalyzeError;
use crate::replayer::{RaceEntry, RaceLength, Replayer, Subject, finite, timed_estimate};

/// How far replays may stray from a line in their miss rate (relative to the line) and still set
/// the shape of a node's frame time.
pub(super) const REPLAY_SPREAD: f64 = 0.15;

/// The largest relative distance of the replays' mean frame times from the least-squares line
/// through them in their miss rate; `None` with fewer than three usable replays (or no spread
/// of miss rates to draw a line through).
pub(super) fn replay_spread(measurements: &[Measurement]) -> Option<f64> {
    let points: Vec<(f64, f64)> = measurements
        .iter()
        .map(|m| (1.0 - m.hit_rate, m.frame_ms))
        .filter(|(x, y)| x.is_finite() && y.is_finite() && *y > 0.0)
        .collect();
    if points.len() < 3 {
        return None;
    }
    let n = points.len() as f64;
    let (mx, my) = (
        points.iter().map(|p| p.0).sum::<f64>() / n,
        points.iter().map(|p| p.1).sum::<f64>() / n,
    );
    let sxx: f64 = points.iter().map(|p| (p.0 - mx).powi(2)).sum();
    if sxx <= 1e-12 {
        return None;
    }
    let slope = points.iter().map(|p| (p.0 - mx) * (p.1 - my)).sum::<f64>() / sxx;
    points
        .iter()
        .map(|&(x, y)| {
            let line = my + slope * (x - mx);
            if line > 0.0 {
                (y / line - 1.0).abs()
            } else {
                f64::INFINITY
            }
        })
        .reduce(f64::max)
}

/// Where `measurements` (the node's replays) stray from their line by more than
/// [`REPLAY_SPREAD`], race the node's kept variant (`subject`'s, its pass sources and variant)
/// at the shortest period of `plan` (other than the longest, which its strategy race timed): its
/// probe, kept. None where the replays agree or the plan has no other period.
pub(super) fn race_second_period(
    rp: &mut Replayer<'_, '_>,
    subject: &Subject,
    (sources, variant): (&[String], &reproj_instance::Variant),
    measurements: &[Measurement],
    plan: &[(u32, bool)],
) -> Result<Option<StrategyProbe>, AnalyzeError> {
    let longest = rp.longest;
    let Some(delta_n) = plan.iter().map(|p| p.0).filter(|&d| d < longest).min() else {
        return Ok(None);
    };
    let spread = replay_spread(measurements);
    if spread.is_some_and(|s| s <= REPLAY_SPREAD) {
        return Ok(None);
    }
    let id = subject.node;
    rp.progress.note(&format!(
        "node {id}: its replays' frame times {}: its frame time over Δn follows two races (raced at Δn {delta_n} too)",
        spread.map_or_else(
            || "are too few to draw a line through".to_string(),
            |s| format!("stray up to {:.0} % from a line in their miss rate", 100.0 * s)
        )
    ));
    rp.progress.extend(1);
    let entry = RaceEntry {
        name: format!("{} Δn={delta_n}", subject.strategy),
        sources,
        variant,
        delta_n,
    };
    let report = rp.race_as(&format!("node {id}"), id, &[], &[entry], RaceLength::Period)?;
    rp.progress.step(&format!("node {id} race at Δn={delta_n}"));
    let e = report.estimate(0);
    let c = &report.candidates[0];
    Ok(Some(StrategyProbe {
        node: id,
        strategy: subject.strategy.name().into(),
        block: subject.block,
        delta_n,
        frame_ms: finite(e.map_or(c.median_ms.unwrap_or(0.0), |e| e.candidate_ms)),
        error: None,
        pass_ms: Vec::new(),
        kept: true,
        frames: None,
        original_ms: Some(finite(
            e.map_or(report.baseline.median_ms, |e| e.baseline_ms),
        )),
        timed: timed_estimate(e.as_ref()),
    }))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn at(delta_n: u32, hit_rate: f64, frame_ms: f64) -> Measurement {
        let mut m: Measurement = serde_json::from_value(serde_json::json!({
            "delta_n": delta_n, "error": 0.0, "psnr": null, "mse": null,
            "hit_rate": hit_rate, "frame_ms": frame_ms, "frames": []
        }))
        .unwrap();
        m.hit_rate = hit_rate;
        m
    }

    #[test]
    fn replays_on_a_line_in_their_miss_rate_agree_and_a_moving_clock_does_not() {
        // On a line: t = 2 + 6 · (1 − γ).
        let line: Vec<Measurement> = [(2, 0.5), (10, 0.9), (26, 0.96), (50, 0.98)]
            .iter()
            .map(|&(dn, g)| at(dn, g, 2.0 + 6.0 * (1.0 - g)))
            .collect();
        assert!(replay_spread(&line).unwrap() < 1e-12);
        // The H200's node 680: the clock moved between replays.
        let moved: Vec<Measurement> = [
            (2, 0.49, 4.38),
            (26, 0.95, 2.87),
            (30, 0.96, 3.88),
            (50, 0.98, 1.72),
        ]
        .iter()
        .map(|&(dn, g, t)| at(dn, g, t))
        .collect();
        assert!(replay_spread(&moved).unwrap() > REPLAY_SPREAD);
        // Two replays draw no line to check against.
        assert_eq!(replay_spread(&line[..2]), None);
    }
}
