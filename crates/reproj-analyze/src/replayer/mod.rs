//! The replay machinery `analyze` shares between single nodes and sets of nodes: a [`Replayer`]
//! (renderer, reference, options, journal) that replays and races one subject (over its periods:
//! `crate::periods`), and [`fit_replays`], which turns the measurements into the profile's fitted
//! models and status.

use std::time::Instant;

use reproj_instance::Strategy;
use reproj_models::profile::{AnalysisTime, Measurement, Timed};
use reproj_models::speedup::SpeedupEstimate;
use reproj_replay::{RenderOptions, Renderer, VariantInput};

use crate::AnalyzeError;
use crate::input::{AnalyzeInput, Progress};
use crate::journal::{Journal, ReplayKey, ReplayResult};
use crate::options::AnalyzeOptions;

mod contest;
mod fit;

pub(crate) use contest::{Again, Duel};

use fit::replay;
pub(crate) use fit::{Fitted, fit_replays};

/// How long a race runs: [`AnalyzeOptions::race`] (short: it decides where intervals separate,
/// and a wide interval decides for the simpler candidate), or [`LONG_RACE`] for a race the short
/// one left undecided while the challenger led.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum RaceLength {
    Short,
    Long,
    /// As short, run again on one entry to settle a doubt the first race left (journaled apart).
    Again,
    /// A node's variant at its second period ([`PERIOD_RACE`]).
    Period,
}

/// The race of a node's variant at its second period: 8 rounds (each window twice, once in each
/// order) of 4 timed frames, at most 4 s. It sets the shape of the node's frame time over Δn,
/// not a decision, so half the frames of a deciding race do (marble on lavapipe: ~0.8 s a node).
pub(crate) const PERIOD_RACE: reproj_bench::BenchOptions = reproj_bench::BenchOptions {
    block_frames: 4,
    settle: None,
    ..crate::options::DEFAULT_RACE
};

/// A longer race: 16 to 48 rounds of 8 frames, until ±2 % or 12 s. On the H200 at 1080p, marble's
/// node 680 left Catmull-Rom at 2.39× [1.89, 3.03] against bilinear's 1.84× [1.78, 1.90] after the
/// short race's 8 rounds (docs/notebook/gpu-h200.md).
pub(crate) const LONG_RACE: reproj_bench::BenchOptions = reproj_bench::BenchOptions {
    block_frames: 8,
    stop: reproj_models::speedup::StopRule {
        min_rounds: 16,
        max_rounds: 48,
        target_half_width: 0.02,
        max_seconds: 12.0,
    },
    max_frames: None,
    settle: Some(reproj_bench::DEFAULT_SETTLE),
};

/// Why a non-root subject whose variant at the longest period is slower than the original beyond
/// doubt (its whole interleaved-timing interval below 1×) cannot pay off; `None` when it may.
pub(crate) fn too_slow(
    e: &SpeedupEstimate,
    root: bool,
    longest: u32,
    strategy: Strategy,
) -> Option<String> {
    if root || !e.surely_slower() {
        return None;
    }
    Some(format!(
        "slower than the original even at Δn = {longest}: {} ({strategy}, timed interleaved): it cannot pay off",
        e.display()
    ))
}

/// A race's report as a journal recorded it, when it is one for `names` (in order) and its
/// figures are timings: every speedup and interval bound finite and positive, the interval around
/// the estimate. Anything else is timed again.
fn journaled_race(v: &serde_json::Value, names: &[&str]) -> Option<reproj_bench::BenchReport> {
    let r: reproj_bench::BenchReport = serde_json::from_value(v.clone()).ok()?;
    let pos = |x: f64| x.is_finite() && x > 0.0;
    let ok = r.candidates.len() == names.len()
        && r.candidates.iter().zip(names).all(|(c, n)| {
            c.name == *n
                && match (c.speedup, c.speedup_ci95) {
                    (Some(s), Some([lo, hi])) => pos(s) && pos(lo) && lo <= s && s <= hi,
                    (None, None) => true,
                    _ => false,
                }
        });
    ok.then_some(r)
}

/// One variant in a race ([`Replayer::race`]), at its refresh period.
pub(crate) struct RaceEntry<'a> {
    pub(crate) name: String,
    pub(crate) sources: &'a [String],
    pub(crate) variant: &'a reproj_instance::Variant,
    pub(crate) delta_n: u32,
}

/// What every replay of one analysis shares: the renderer and the reference, the options, the
/// journal and the time tally. Single nodes and sets of nodes are replayed through it alike.
pub(crate) struct Replayer<'a, 'b> {
    pub(crate) renderer: &'a Renderer,
    pub(crate) input: &'a AnalyzeInput<'b>,
    pub(crate) reference: &'a reproj_replay::Reference,
    /// The options of a whole-session replay.
    pub(crate) render_opts: RenderOptions,
    pub(crate) opts: &'a AnalyzeOptions,
    pub(crate) progress: &'a dyn Progress,
    pub(crate) journal: Option<Journal>,
    pub(crate) time: AnalysisTime,
    /// The original's mean frame time over the whole session, ms.
    pub(crate) original_ms: f64,
    /// The longest training period (replayed first).
    pub(crate) longest: u32,
    /// Every timing warning of the analysis, once each (into the profile).
    pub(crate) timing_warnings: Vec<String>,
    /// The device's clock as the first race's settling found it (into the profile).
    pub(crate) clock: Option<reproj_bench::Settling>,
}

/// What [`Replayer::replay_plan`] replays: a node, or a set of nodes cached together.
pub(crate) struct Subject {
    /// The node (a set's first member).
    pub(crate) node: u32,
    /// A set's members in payload order; empty for a single node.
    pub(crate) set: Vec<u32>,
    /// How notes name it (`node 34`, `set 22+39`).
    pub(crate) who: String,
    pub(crate) text: String,
    pub(crate) root: bool,
    pub(crate) strategy: Strategy,
    pub(crate) block: u32,
    /// Its reconstruction filter when it is not the analysis's own (a filter race's kept
    /// challenger): it keys the journal's records.
    pub(crate) reconstruct: Option<reproj_instance::Reconstruct>,
    /// Its variant already raced the original ([`Replayer::race`]); otherwise
    /// [`Replayer::replay_plan`] races it at the longest period.
    pub(crate) raced: bool,
    /// Why the race sets it aside (slower than the original beyond doubt), applied once the
    /// longest period is replayed: the profile keeps that one measurement.
    pub(crate) verdict: Option<String>,
}

/// A challenger variant of a node, instanced and replayed at the longest period for a race
/// against the node's base ([`Replayer::challenger_at`]).
pub(crate) struct Challenger {
    pub(crate) sources: Vec<String>,
    pub(crate) variant: reproj_instance::Variant,
    pub(crate) measurement: Measurement,
}

impl Replayer<'_, '_> {
    /// Node `id` instanced with `inst` (a challenger to its base: another filter or block) and
    /// replayed at period `longest` (the filter race's is the longest training period, the block
    /// race's [`crate::blocks::race_period`]): two progress steps, and a third when it fails
    /// (`done`, the step that closes the race). `None` when it cannot be, said in a note naming
    /// `what` and the base the node `keeps`.
    #[allow(clippy::too_many_arguments)]
    pub(crate) fn challenger_at(
        &mut self,
        id: u32,
        sel: reproj_instance::NodeSelector,
        inst: &reproj_instance::InstanceOptions,
        longest: u32,
        what: &str,
        keeps: &str,
        done: &str,
    ) -> Result<Option<Challenger>, AnalyzeError> {
        let who = format!("node {id}");
        let t = Instant::now();
        let variant = reproj_instance::instance(
            self.input.shader,
            self.input.norm,
            self.input.table,
            sel,
            inst,
        );
        self.time.instancing_s += t.elapsed().as_secs_f64();
        self.progress.step(&format!("{who} {what} instanced"));
        let variant = match variant {
            Ok(v) => v,
            Err(e) => {
                self.progress.note(&format!(
                    "{who}: cannot instance {what}: {e}; keeps {keeps}"
                ));
                self.progress.step(&format!("{who} {what}"));
                self.progress.step(&format!("{who} {done}"));
                return Ok(None);
            }
        };
        let sources: Vec<String> = variant.passes.iter().map(|p| p.wgsl.clone()).collect();
        let key = ReplayKey {
            node: id,
            strategy: inst.strategy.name().into(),
            block: inst.block,
            delta_n: longest,
            frames: None,
            set: Vec::new(),
            // The journal keys a filter other than the analysis's own by its name.
            reconstruct: (inst.reconstruct != self.opts.instance.reconstruct)
                .then(|| inst.reconstruct.name().to_string()),
        };
        let replayed = self.replay(key, &sources, &variant, longest, None)?;
        self.progress.step(&format!("{who} {what} Δn={longest}"));
        match replayed {
            Ok((measurement, _)) => Ok(Some(Challenger {
                sources,
                variant,
                measurement,
            })),
            Err(e) => {
                self.progress.note(&format!(
                    "{who}: {what} replay failed at Δn={longest}: {e}; keeps {keeps}"
                ));
                self.progress.step(&format!("{who} {done}"));
                Ok(None)
            }
        }
    }

    /// Time `entries` (variants of `node`, or of the set `set`, each at its period: the longest
    /// one but in a filter race) against the original, interleaved (`reproj-bench`, under [`AnalyzeOptions::race`]): each one's
    /// speedup with its 95 % interval. Journaled: a resumed analysis reuses the report (its
    /// decisions stand) rather than timing again.
    pub(crate) fn race(
        &mut self,
        who: &str,
        node: u32,
        set: &[u32],
        entries: &[RaceEntry<'_>],
    ) -> Result<reproj_bench::BenchReport, AnalyzeError> {
        self.race_as(who, node, set, entries, RaceLength::Short)
    }

    /// [`Replayer::race`] of the given length (journaled apart from the short one).
    pub(crate) fn race_as(
        &mut self,
        who: &str,
        node: u32,
        set: &[u32],
        entries: &[RaceEntry<'_>],
        length: RaceLength,
    ) -> Result<reproj_bench::BenchReport, AnalyzeError> {
        let t = Instant::now();
        let candidates: Vec<reproj_bench::Candidate> = entries
            .iter()
            .map(|e| reproj_bench::Candidate {
                name: e.name.clone(),
                subject: reproj_bench::Subject::Variant(VariantInput::new(
                    e.sources.to_vec(),
                    e.variant.manifest.clone(),
                    e.delta_n,
                )),
            })
            .collect();
        let entry = self
            .input
            .shader
            .fragment_entry(Some(&self.input.norm.entry))?;
        let mut race = match length {
            RaceLength::Short | RaceLength::Again => self.opts.race,
            RaceLength::Long => LONG_RACE,
            RaceLength::Period => PERIOD_RACE,
        };
        // The device's clock settles once, before the analysis's first race: the replays between
        // races keep it busy (on the H200 only the first race met a clock still rising).
        if self.clock.is_some() {
            race.settle = None;
        }
        race.max_frames = match (self.opts.probe_frames, self.opts.max_frames) {
            (Some(a), Some(b)) => Some(a.min(b)),
            (a, b) => a.or(b),
        };
        let mut names: Vec<&str> = entries.iter().map(|e| e.name.as_str()).collect();
        // Keyed apart from the short race of the same entries.
        match length {
            RaceLength::Short => {}
            RaceLength::Long => names.push("long"),
            RaceLength::Again => names.push("again"),
            RaceLength::Period => names.push("period"),
        }
        let key = ReplayKey::race(node, set, &names, self.longest, race.max_frames);
        if let Some(report) = self
            .journal
            .as_ref()
            .and_then(|j| j.race(&key))
            .and_then(|v| journaled_race(v, &names[..entries.len()]))
        {
            if let Some(j) = &mut self.journal {
                j.reuse_race();
            }
            return Ok(report);
        }
        let report = reproj_bench::bench(
            self.renderer,
            reproj_bench::Baseline {
                shader: self.input.shader,
                entry,
                reference: self.reference,
            },
            self.input.session,
            &candidates,
            &race,
            &mut |_| {},
        )?;
        self.time.timing_s += t.elapsed().as_secs_f64();
        // A report always serializes (a non-finite figure becomes null and is timed again on
        // resuming: see `journaled_race`).
        if let Some(j) = &mut self.journal
            && let Ok(json) = serde_json::to_value(&report)
        {
            j.record_race(key, json)?;
        }
        if self.clock.is_none() {
            self.clock.clone_from(&report.settling);
        }
        for w in &report.warnings {
            // The same warning for every node says nothing more: once each. The first one
            // shows; all are in the profile.
            let first = self.timing_warnings.is_empty();
            if reproj_bench::add_warning_once(&mut self.timing_warnings, w) && first {
                self.progress.note(&format!("{who}: timing: {w}"));
            }
        }
        Ok(report)
    }

    /// Replay one variant at `delta_n` over the whole session (`render_opts`: `None`) or as
    /// `render_opts` says, or take the journal's record of that replay; a new replay is recorded.
    pub(crate) fn replay(
        &mut self,
        key: ReplayKey,
        sources: &[String],
        variant: &reproj_instance::Variant,
        delta_n: u32,
        render_opts: Option<&RenderOptions>,
    ) -> Result<ReplayResult, AnalyzeError> {
        let run = |time: &mut AnalysisTime| {
            replay(
                self.renderer,
                self.input,
                sources,
                variant,
                delta_n,
                self.reference,
                render_opts.unwrap_or(&self.render_opts),
                time,
            )
        };
        let Some(j) = &mut self.journal else {
            return Ok(run(&mut self.time));
        };
        if let Some(r) = j.get(&key) {
            return Ok(r);
        }
        let r = run(&mut self.time);
        j.record(key, &r)?;
        Ok(r)
    }
}

pub(crate) fn mean(it: impl Iterator<Item = f64>) -> f64 {
    let (s, n) = it.fold((0.0, 0usize), |(s, n), x| (s + x, n + 1));
    if n == 0 { 0.0 } else { s / n as f64 }
}

/// NaN and infinities never reach the profile.
pub(crate) fn finite(x: f64) -> f64 {
    if x.is_finite() { x } else { 0.0 }
}

/// What a race's report measured of its candidate `i`, as a probe records it (finite; all `None`
/// where the report has no such candidate).
pub(crate) fn timed_candidate(report: &reproj_bench::BenchReport, i: usize) -> Timed {
    let c = report.candidates.get(i);
    Timed {
        speedup: c.and_then(|c| c.speedup).map(finite),
        speedup_ci95: c
            .and_then(|c| c.speedup_ci95)
            .map(|[lo, hi]| [finite(lo), finite(hi)]),
        rounds: c.map(|c| c.rounds),
    }
}

/// A speedup estimate as a probe records it (finite; all `None` without one).
pub(crate) fn timed_estimate(e: Option<&SpeedupEstimate>) -> Timed {
    Timed {
        speedup: e.map(|e| finite(e.speedup)),
        speedup_ci95: e.map(|e| [finite(e.ci95[0]), finite(e.ci95[1])]),
        rounds: e.map(|e| e.rounds),
    }
}

/// The hit-rate model of a shader and session: one fit over every node's measurements at the
/// training periods (`analyze`, and `merge` over the joined shards).
pub(crate) fn fit_session_hit_rate<'a>(
    measurements: impl Iterator<Item = &'a Measurement>,
    train: &[u32],
) -> reproj_models::HitRateFit {
    let samples: Vec<(f64, f64)> = measurements
        .filter(|m| train.contains(&m.delta_n))
        .map(|m| (m.delta_n as f64, m.hit_rate))
        .collect();
    reproj_models::fit_hit_rate(&samples)
}

/// An estimate of `speedup` with the interval `[lo, hi]` over 8 rounds, for the decisions' tests.
#[cfg(test)]
pub(crate) fn test_estimate(speedup: f64, lo: f64, hi: f64) -> SpeedupEstimate {
    SpeedupEstimate {
        speedup,
        ci95: [lo, hi],
        rounds: 8,
        outliers: 0,
        baseline_ms: 6.0,
        candidate_ms: 6.0 / speedup,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn report(speedup: serde_json::Value, ci: serde_json::Value) -> serde_json::Value {
        serde_json::json!({
            "schema": "reproj.bench", "version": 1,
            "machine": {"adapter": "a", "device_type": "Cpu", "cpu_rasterizer": true,
                        "lp_num_threads": null, "cpus": 2},
            "block_frames": 8, "session_frames": 40, "rounds": 8, "seconds": 1.0,
            "others_cpu": null,
            "baseline": {"median_ms": 5.0, "blocks_ms": [5.0], "windows": [0]},
            "candidates": [{"name": "2pass", "median_ms": 2.5, "speedup": speedup,
                            "speedup_ci95": ci, "rounds": 8, "outliers": 0, "blocks_ms": [2.5]}],
            "warnings": []
        })
    }

    #[test]
    fn a_journaled_race_is_reused_only_when_it_is_this_race_and_its_figures_are_timings() {
        let good = report(serde_json::json!(2.0), serde_json::json!([1.9, 2.1]));
        assert!(journaled_race(&good, &["2pass"]).is_some());
        // Another race (other strategies), or figures that are not timings: timed again.
        assert!(journaled_race(&good, &["3pass"]).is_none());
        assert!(journaled_race(&good, &["2pass", "3pass"]).is_none());
        for (s, ci) in [
            (serde_json::json!(-2.0), serde_json::json!([-2.1, -1.9])),
            (serde_json::json!(2.0), serde_json::json!([2.1, 2.2])),
            (serde_json::json!(null), serde_json::json!([1.9, 2.1])),
        ] {
            assert!(journaled_race(&report(s, ci), &["2pass"]).is_none());
        }
        assert!(journaled_race(&serde_json::json!({"rounds": 8}), &["2pass"]).is_none());
    }
}
