//! Segments of one session: a slower and a faster half of a session of uneven motion, each node
//! refitted on the half's per-frame errors (profile version 9), as two more profiles for the
//! motion exponent.

use reproj_models::motion::STATIC_PIXELS;
use reproj_select::NodeRecord;

/// One part of a profiled session's frames, as one more profile for the motion exponent: its mean
/// motion and each node's error model refitted on the part's own per-frame errors.
#[derive(Debug, Clone)]
pub struct Segment {
    pub motion: f64,
    pub nodes: Vec<NodeRecord>,
}

/// A node's record and its measurements' per-frame errors: (Δn, L2 error of each frame from 0).
pub type NodeFrames<'a> = (NodeRecord, Vec<(u32, &'a [f64])>);

/// Split one profile's replayed frames into a slower and a faster half by their motion
/// (`per_frame`, pixels per frame), leaving out the first `warmup` frames (the cache fills over
/// the first Δn frames), and refit each node on each half: per measured Δn, the mean of
/// `frame_errors` over the half's frames. `nodes`: each node's record with its measurements
/// (Δn, per-frame L2 errors from frame 0). Empty when the halves' motions differ by less than
/// [`reproj_models::motion::MIN_MOTION_RATIO`] (a session of even motion tells nothing) or
/// fewer than 4 frames remain.
pub fn segments(per_frame: &[f64], nodes: &[NodeFrames<'_>], warmup: usize) -> Vec<Segment> {
    let mut steady: Vec<usize> = (warmup.max(1)..per_frame.len())
        .filter(|&f| per_frame[f].is_finite())
        .collect();
    if steady.len() < 4 {
        return Vec::new();
    }
    steady.sort_by(|&a, &b| per_frame[a].total_cmp(&per_frame[b]));
    let (slow, fast) = steady.split_at(steady.len() / 2);
    let mean_motion =
        |fs: &[usize]| fs.iter().map(|&f| per_frame[f]).sum::<f64>() / fs.len() as f64;
    let (m_slow, m_fast) = (mean_motion(slow), mean_motion(fast));
    if !(m_slow >= STATIC_PIXELS && m_fast / m_slow >= reproj_models::motion::MIN_MOTION_RATIO) {
        return Vec::new();
    }
    [(m_slow, slow), (m_fast, fast)]
        .into_iter()
        .map(|(motion, frames)| Segment {
            motion,
            nodes: nodes
                .iter()
                .filter_map(|(record, measured)| {
                    let samples: Vec<(u32, f64)> = measured
                        .iter()
                        .filter_map(|&(dn, errors)| {
                            let v: Vec<f64> = frames
                                .iter()
                                .filter_map(|&f| errors.get(f).copied())
                                .filter(|e| e.is_finite())
                                .collect();
                            (v.len() * 2 >= frames.len())
                                .then(|| (dn, v.iter().sum::<f64>() / v.len() as f64))
                        })
                        .collect();
                    if samples.len() < 2 {
                        return None;
                    }
                    let fit_input: Vec<(f64, f64)> =
                        samples.iter().map(|&(d, e)| (f64::from(d), e)).collect();
                    Some(NodeRecord {
                        error: reproj_models::fit_error(
                            &fit_input,
                            &reproj_models::ErrorFitOptions::default(),
                        ),
                        measured_errors: samples,
                        ..record.clone()
                    })
                })
                .collect(),
        })
        .filter(|s| !s.nodes.is_empty())
        .collect()
}

/// [`segments`] of a profile for its records (the L2 error's: `frame_errors` are L2), with the
/// warm-up at the longest measured period (at most half the frames).
pub fn profile_segments(profile: &reproj_models::Profile, records: &[NodeRecord]) -> Vec<Segment> {
    let Some(motion) = &profile.motion else {
        return Vec::new();
    };
    let nodes: Vec<NodeFrames<'_>> = records
        .iter()
        .filter_map(|r| {
            let n = profile
                .nodes
                .iter()
                .find(|n| n.id == r.id && n.strategy == r.strategy)?;
            let measured: Vec<(u32, &[f64])> = n
                .measurements
                .iter()
                .filter(|m| !m.frame_errors.is_empty())
                .map(|m| (m.delta_n, &m.frame_errors[..]))
                .collect();
            (!measured.is_empty()).then(|| (r.clone(), measured))
        })
        .collect();
    let longest = nodes
        .iter()
        .flat_map(|(_, m)| m.iter().map(|p| p.0 as usize))
        .max()
        .unwrap_or(0);
    segments(
        &motion.per_frame,
        &nodes,
        longest.min(motion.per_frame.len() / 2),
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use reproj_models::motion::{ExponentSource, fit_exponent};
    use reproj_models::{ErrorFitOptions, TimingFit, fit_error};
    use reproj_select::motion::{Profiled, cross_predictions};

    /// A session whose second half moves three times as fast, its per-frame errors made with
    /// β = 1 (the cache ages with the distance moved): the two halves fit β near 1 from this one
    /// session; a session of even motion gives no segments.
    #[test]
    fn the_halves_of_one_session_of_uneven_motion_fit_the_exponent() {
        let error = |dn: u32, m: f64| 0.02 * (1.0 - (-0.05 * f64::from(dn - 1) * m).exp());
        let per_frame: Vec<f64> = (0..120).map(|f| if f < 60 { 1.0 } else { 3.0 }).collect();
        let periods = [2u32, 8, 16, 24, 32];
        let frame_errors: Vec<Vec<f64>> = periods
            .iter()
            .map(|&dn| per_frame.iter().map(|&m| error(dn, m)).collect())
            .collect();
        let whole: Vec<(f64, f64)> = periods
            .iter()
            .map(|&dn| (f64::from(dn), (error(dn, 1.0) + error(dn, 3.0)) / 2.0))
            .collect();
        let record = NodeRecord {
            id: 7,
            text: "n".into(),
            strategy: "3pass".into(),
            error: fit_error(&whole, &ErrorFitOptions::default()),
            timing: TimingFit::from_costs(1e-5, 2e-5, 0.5, 1000.0),
            mean_pixels: 1000.0,
            measured: None,
            measured_errors: whole.iter().map(|&(d, e)| (d as u32, e)).collect(),
        };
        let measured: Vec<(u32, &[f64])> = periods
            .iter()
            .zip(&frame_errors)
            .map(|(&dn, e)| (dn, &e[..]))
            .collect();
        let nodes = vec![(record.clone(), measured)];
        let segs = segments(&per_frame, &nodes, 1);
        assert_eq!(segs.len(), 2);
        assert!((segs[0].motion - 1.0).abs() < 1e-9 && (segs[1].motion - 3.0).abs() < 1e-9);
        let input: Vec<Profiled> = segs
            .iter()
            .map(|s| Profiled {
                motion: s.motion,
                nodes: &s.nodes,
            })
            .collect();
        let beta = fit_exponent(|b| cross_predictions(&input, b));
        assert_eq!(beta.source, ExponentSource::Fitted, "{beta:?}");
        assert!((beta.beta - 1.0).abs() <= 0.2, "{beta:?}");
        // Even motion: nothing to learn from halves.
        let even = vec![1.0; 120];
        assert!(segments(&even, &nodes, 32).is_empty());
        // Too few frames after the warm-up.
        assert!(segments(&per_frame, &nodes, 118).is_empty());
    }
}
