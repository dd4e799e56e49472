//! The statistics of an interleaved timing: how fast a candidate is against a baseline, with a 95 %
//! interval, from blocks of frames measured alternately in one run.
//!
//! A single mean over one replay, compared with another replay taken at another moment, measures
//! the machine's load as much as the shader. So every speed figure reproj gives comes from *rounds*:
//! in each round the baseline and every candidate render the same window of the session, one block
//! each, in an order that alternates from round to round ([`round_order`]: ABBA over rounds), and
//! each round yields one paired ratio. The ratios are summarised per window by the Hodges–Lehmann
//! estimator of their logarithms (robust to a few disturbed rounds), with a Student-t interval on
//! their spread within windows; a run
//! stops when the interval is narrow enough or its time is spent ([`StopRule`]). What the statistics
//! cannot see — the baseline's own time moving, a wide interval — becomes a warning
//! ([`condition_warnings`]), never a silent figure.
//!
//! Everything here is pure (no GPU): the replay's bench driver feeds it frame times.

use serde::{Deserialize, Serialize};

/// Which subject renders in a slot of a round.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Subject {
    Baseline,
    /// The candidate at this index.
    Candidate(usize),
}

/// The order of the subjects in round `round` with `candidates` candidates: the baseline first
/// and the candidates in order, or the reverse, alternating between the successive visits of each
/// window ([`stratum`]), so that within every window each side runs first as often as the other
/// and a load that drifts linearly weighs on both sides of every pair alike.
pub fn round_order(round: u32, candidates: usize) -> Vec<Subject> {
    let mut order = vec![Subject::Baseline];
    order.extend((0..candidates).map(Subject::Candidate));
    if (round / WINDOWS) % 2 == 1 {
        order.reverse();
    }
    order
}

/// How many windows of the session the rounds cycle through ([`window_start`]).
pub const WINDOWS: u32 = 4;

/// The window (stratum) round `round` measures: the rounds cycle through [`WINDOWS`] windows.
pub fn stratum(round: u32) -> u32 {
    round % WINDOWS
}

/// The first frame of round `round`'s window of `block` frames in a session of `frames` frames.
/// The rounds cycle through [`WINDOWS`] fixed windows centred on the quarters of the session: a
/// speedup depends on what is on screen, so each window's ratios are compared only with that
/// window's (the estimate is stratified by window, [`estimate`]), and the session is covered.
pub fn window_start(round: u32, frames: u32, block: u32) -> u32 {
    let span = frames.saturating_sub(block);
    if span == 0 {
        return 0;
    }
    let centre = (2 * stratum(round) + 1) as f64 / (2 * WINDOWS) as f64;
    ((centre * f64::from(span)).round() as u32).min(span)
}

/// The figure of one block: the mean of its frame times after trimming the fastest and slowest
/// 20 % (a frame stalled by the machine weighs little, the content's own variation stays). Frames
/// that are not finite and positive are dropped; `None` when nothing is left.
pub fn block_ms(frame_ms: &[f64]) -> Option<f64> {
    let mut v: Vec<f64> = frame_ms
        .iter()
        .copied()
        .filter(|t| t.is_finite() && *t > 0.0)
        .collect();
    if v.is_empty() {
        return None;
    }
    v.sort_by(f64::total_cmp);
    let cut = v.len() / 5;
    let kept = &v[cut..v.len() - cut];
    Some(kept.iter().sum::<f64>() / kept.len() as f64)
}

/// When a run stops.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct StopRule {
    /// Never stop before this many rounds (an interval needs a few).
    pub min_rounds: u32,
    /// Never run more rounds than this.
    pub max_rounds: u32,
    /// Stop once every candidate's interval has at most this relative half-width (0.03: ±3 %).
    pub target_half_width: f64,
    /// Stop after this many seconds of measuring (checked between rounds).
    pub max_seconds: f64,
}

impl Default for StopRule {
    fn default() -> Self {
        StopRule {
            min_rounds: 8,
            max_rounds: 48,
            target_half_width: 0.03,
            max_seconds: 30.0,
        }
    }
}

impl StopRule {
    /// Whether a run that has done `rounds` rounds in `seconds`, with the candidates' current
    /// estimates, is done.
    pub fn done(&self, rounds: u32, seconds: f64, estimates: &[Option<SpeedupEstimate>]) -> bool {
        if rounds < self.min_rounds.max(1) {
            return false;
        }
        if rounds >= self.max_rounds || seconds >= self.max_seconds {
            return true;
        }
        estimates.iter().all(|e| {
            e.as_ref()
                .is_some_and(|e| e.half_width() <= self.target_half_width)
        })
    }
}

/// How long the baseline renders before a run is timed, so that the device's clock has settled: a
/// GPU idles at a low clock and raises it under load (an H200 from 345 MHz), and the first rounds
/// of a run that starts cold time the ramp, not the shaders.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Settle {
    /// Settled once two successive blocks of the baseline (on one window) are this close: 0.03 is
    /// within 3 % of each other.
    pub tolerance: f64,
    /// Give up after this many seconds (the run is timed anyway, with a warning).
    pub max_seconds: f64,
}

/// The settling every run does unless told otherwise.
pub const DEFAULT_SETTLE: Settle = Settle {
    tolerance: 0.03,
    max_seconds: 3.0,
};

impl Default for Settle {
    fn default() -> Self {
        DEFAULT_SETTLE
    }
}

/// What settling saw of the device before a run: its clock's behaviour, recorded with the run.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Settling {
    /// The baseline's figure per block (ms per frame, the same window each time), in order.
    pub blocks_ms: Vec<f64>,
    /// Seconds spent.
    pub seconds: f64,
    /// Whether the last two blocks agreed within the tolerance.
    pub settled: bool,
}

impl Settle {
    /// Whether `blocks` (figures so far, in order) have settled: the last two finite and within
    /// the tolerance of each other.
    pub fn reached(&self, blocks: &[f64]) -> bool {
        match blocks {
            [.., a, b] if a.is_finite() && b.is_finite() && *a > 0.0 && *b > 0.0 => {
                (b / a - 1.0).abs() <= self.tolerance
            }
            _ => false,
        }
    }
}

impl Settling {
    /// How much the baseline's figure moved from the first block to the last (their ratio), where
    /// both are finite.
    pub fn drift(&self) -> Option<f64> {
        let (first, last) = (self.blocks_ms.first()?, self.blocks_ms.last()?);
        (first.is_finite() && last.is_finite() && *first > 0.0).then(|| last / first)
    }

    /// The warning a run gets when the clock did not settle in time.
    pub fn warning(&self) -> Option<String> {
        if self.settled {
            return None;
        }
        let moved = match self.blocks_ms.as_slice() {
            [.., a, b] if *a > 0.0 => {
                format!("the original's last two blocks were {a:.3} and {b:.3} ms per frame")
            }
            _ => "too few blocks to tell".into(),
        };
        Some(format!(
            "the clock did not settle before timing: after {} blocks in {:.1} s {moved}; the first rounds may time a clock still moving",
            self.blocks_ms.len(),
            self.seconds
        ))
    }
}

/// A speedup (baseline time / candidate time: above 1 the candidate is faster) with its 95 %
/// interval, from paired block figures.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct SpeedupEstimate {
    /// Hodges–Lehmann estimate of the paired ratios (the median of the pairwise means of their
    /// logarithms, exponentiated).
    pub speedup: f64,
    /// Its 95 % interval (Student's t on the rounds' spread within their windows).
    pub ci95: [f64; 2],
    /// The rounds (pairs) it rests on.
    pub rounds: u32,
    /// Rounds whose ratio lies over 3.5 robust standard deviations from their window's median
    /// (they stay in the estimate, whose breakdown point is 29 %, but are counted).
    pub outliers: u32,
    /// Median block time of the baseline and of the candidate, ms per frame.
    pub baseline_ms: f64,
    pub candidate_ms: f64,
}

impl SpeedupEstimate {
    /// The interval's relative half-width: the larger distance from the estimate to an end,
    /// over the estimate (0.03 = ±3 %).
    pub fn half_width(&self) -> f64 {
        let [lo, hi] = self.ci95;
        ((hi - self.speedup).max(self.speedup - lo) / self.speedup).max(0.0)
    }

    /// The candidate is slower than the baseline beyond doubt: the whole interval below 1.
    pub fn surely_slower(&self) -> bool {
        self.ci95[1] < 1.0
    }

    /// The candidate is faster than the baseline beyond doubt: the whole interval above 1.
    pub fn surely_faster(&self) -> bool {
        self.ci95[0] > 1.0
    }

    /// `2.10× [2.05, 2.16]`.
    pub fn display(&self) -> String {
        format!(
            "{:.2}× [{:.2}, {:.2}]",
            self.speedup, self.ci95[0], self.ci95[1]
        )
    }
}

/// Whether two candidates' intervals separate (they do not overlap): only then is one of them
/// faster than the other.
pub fn separates(a: &SpeedupEstimate, b: &SpeedupEstimate) -> bool {
    a.ci95[0] > b.ci95[1] || b.ci95[0] > a.ci95[1]
}

/// The speedup of the candidate over the baseline from paired block figures: `baseline[i]` and
/// `candidate[i]` measured in the same round, on window `strata[i]` ([`stratum`]).
///
/// Per window, the Hodges–Lehmann estimate of the log ratios; the speedup is the geometric mean
/// of the windows' estimates (the session's windows weigh alike), and its interval comes from the
/// rounds' spread within their windows ([`t_interval`]) — so it measures the timing's noise, not
/// how the speedup differs across the session. Pairs with a figure that is not finite
/// and positive are dropped; `None` when no pair is left.
pub fn estimate(strata: &[u32], baseline: &[f64], candidate: &[f64]) -> Option<SpeedupEstimate> {
    let pairs: Vec<(u32, f64, f64)> = strata
        .iter()
        .zip(baseline.iter().zip(candidate))
        .map(|(&s, (&b, &c))| (s, b, c))
        .filter(|(_, b, c)| b.is_finite() && c.is_finite() && *b > 0.0 && *c > 0.0)
        .collect();
    if pairs.is_empty() {
        return None;
    }
    let groups = by_stratum(pairs.iter().map(|&(s, b, c)| (s, (b / c).ln())));
    let point = stratified_hl(&groups);
    let ci = t_interval(&groups, point);
    // Outliers: far from their window's median, in robust standard deviations of all residuals.
    let residuals: Vec<f64> = groups
        .iter()
        .flat_map(|g| {
            let m = median(g);
            g.iter().map(move |x| x - m)
        })
        .collect();
    let mad = 1.4826 * median(&residuals.iter().map(|x| x.abs()).collect::<Vec<_>>());
    let outliers = if mad > 0.0 {
        residuals.iter().filter(|x| x.abs() > 3.5 * mad).count() as u32
    } else {
        0
    };
    let bs: Vec<f64> = pairs.iter().map(|p| p.1).collect();
    let cs: Vec<f64> = pairs.iter().map(|p| p.2).collect();
    Some(SpeedupEstimate {
        speedup: point.exp(),
        ci95: [ci[0].min(point).exp(), ci[1].max(point).exp()],
        rounds: pairs.len() as u32,
        outliers,
        baseline_ms: median(&bs),
        candidate_ms: median(&cs),
    })
}

/// Values grouped by stratum, in stratum order.
fn by_stratum(values: impl Iterator<Item = (u32, f64)>) -> Vec<Vec<f64>> {
    let mut map: std::collections::BTreeMap<u32, Vec<f64>> = Default::default();
    for (s, v) in values {
        map.entry(s).or_default().push(v);
    }
    map.into_values().collect()
}

/// The mean over strata of each stratum's Hodges–Lehmann estimate.
fn stratified_hl(groups: &[Vec<f64>]) -> f64 {
    groups.iter().map(|g| hodges_lehmann(g)).sum::<f64>() / groups.len().max(1) as f64
}

/// The median of the pairwise means `(x_i + x_j) / 2`, `i ≤ j`.
pub fn hodges_lehmann(xs: &[f64]) -> f64 {
    let mut walsh = Vec::with_capacity(xs.len() * (xs.len() + 1) / 2);
    for i in 0..xs.len() {
        for j in i..xs.len() {
            walsh.push(0.5 * (xs[i] + xs[j]));
        }
    }
    median(&walsh)
}

/// The median (the mean of the two middle values for an even count); 0 for no values.
pub fn median(xs: &[f64]) -> f64 {
    if xs.is_empty() {
        return 0.0;
    }
    let mut v = xs.to_vec();
    v.sort_by(f64::total_cmp);
    let n = v.len();
    if n % 2 == 1 {
        v[n / 2]
    } else {
        0.5 * (v[n / 2 - 1] + v[n / 2])
    }
}

/// 95 % interval of the log speedup around `point`: Student's t on the pooled spread of the
/// rounds about their window's mean, `n − K` degrees of freedom (K windows); a stall inflates the
/// spread, so a disturbed run widens its interval rather than moving it. With one round per
/// window the spread across windows is used instead; with one round, no interval.
fn t_interval(groups: &[Vec<f64>], point: f64) -> [f64; 2] {
    let n: usize = groups.iter().map(Vec::len).sum();
    let k = groups.len();
    let (ss, df, se_factor) = if n > k {
        let ss: f64 = groups
            .iter()
            .map(|g| {
                let m = g.iter().sum::<f64>() / g.len() as f64;
                g.iter().map(|x| (x - m).powi(2)).sum::<f64>()
            })
            .sum();
        // Var of the mean of K window means: σ²/K² Σ 1/n_s.
        let f = groups
            .iter()
            .map(|g| 1.0 / g.len() as f64)
            .sum::<f64>()
            .sqrt()
            / k as f64;
        (ss, n - k, f)
    } else if n > 1 {
        let all: Vec<f64> = groups.iter().flatten().copied().collect();
        let m = all.iter().sum::<f64>() / n as f64;
        let ss = all.iter().map(|x| (x - m).powi(2)).sum::<f64>();
        (ss, n - 1, 1.0 / (n as f64).sqrt())
    } else {
        return [point, point];
    };
    let sd = (ss / df as f64).sqrt();
    let half = t_975(df) * sd * se_factor;
    if half.is_finite() {
        [point - half, point + half]
    } else {
        [point, point]
    }
}

/// The 97.5 % quantile of Student's t with `df` degrees of freedom.
fn t_975(df: usize) -> f64 {
    const T: [f64; 30] = [
        12.706, 4.303, 3.182, 2.776, 2.571, 2.447, 2.365, 2.306, 2.262, 2.228, 2.201, 2.179, 2.160,
        2.145, 2.131, 2.120, 2.110, 2.101, 2.093, 2.086, 2.080, 2.074, 2.069, 2.064, 2.060, 2.056,
        2.052, 2.048, 2.045, 2.042,
    ];
    match df {
        0 => f64::INFINITY,
        1..=30 => T[df - 1],
        _ => 1.960 + 2.4 / df as f64,
    }
}

/// What a run saw of its conditions besides the ratios.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct Conditions {
    /// Share of the machine's CPU time that other processes used while measuring (0–1), where
    /// the platform tells.
    pub others_cpu: Option<f64>,
}

/// Warnings about a run, in the manner of hyperfine: the baseline's own time moving between the
/// first and last third of the rounds (by more than 10 %) or spreading (robust coefficient of
/// variation over 10 %), each block compared with its window's median so that what is on screen
/// does not count; other processes busy (over 10 % of the CPU); and each candidate whose interval
/// is wider than ±10 %. `baseline` holds the baseline's block figures in round order, measured on
/// windows `strata`.
pub fn condition_warnings(
    strata: &[u32],
    baseline: &[f64],
    estimates: &[(String, Option<SpeedupEstimate>)],
    conditions: &Conditions,
) -> Vec<String> {
    let mut out = Vec::new();
    let rerun = "rerun on a quiet machine";
    if let Some(busy) = conditions.others_cpu.filter(|b| *b > 0.10) {
        out.push(format!(
            "other processes used {:.0} % of the CPU while measuring: a CPU rasterizer's ratios move with load; {rerun}",
            busy * 100.0
        ));
    }
    // Each block over its window's median: 1 when conditions held.
    let kept: Vec<(u32, f64)> = strata
        .iter()
        .zip(baseline)
        .map(|(&s, &b)| (s, b))
        .filter(|(_, b)| b.is_finite() && *b > 0.0)
        .collect();
    let mut medians: std::collections::BTreeMap<u32, Vec<f64>> = Default::default();
    for &(s, b) in &kept {
        medians.entry(s).or_default().push(b);
    }
    let rel: Vec<f64> = kept.iter().map(|(s, b)| b / median(&medians[s])).collect();
    if rel.len() >= 3 {
        let third = (rel.len() / 3).max(1);
        let first = median(&rel[..third]);
        let last = median(&rel[rel.len() - third..]);
        let drift = last / first;
        let mad = 1.4826 * median(&rel.iter().map(|x| (x - 1.0).abs()).collect::<Vec<_>>());
        if !(1.0 / 1.1..=1.1).contains(&drift) {
            out.push(format!(
                "conditions changed during the run: the baseline's own frame time moved by {:+.0} % from the first to the last third of the rounds; {rerun}",
                (drift - 1.0) * 100.0
            ));
        } else if mad > 0.10 {
            out.push(format!(
                "the baseline's own frame time varied by ±{:.0} % between rounds on the same frames; {rerun}",
                mad * 100.0
            ));
        }
    }
    for (name, e) in estimates {
        match e {
            Some(e) if e.half_width() > 0.10 => out.push(format!(
                "the machine was busy: {name} {}; {rerun}",
                e.display()
            )),
            Some(_) => {}
            None => out.push(format!("{name}: no usable timing (no finite frame time)")),
        }
    }
    out
}

#[cfg(test)]
mod tests;
