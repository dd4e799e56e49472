//! The periods a subject (a node, or a set) is replayed at, in order: the fixed ones of its plan,
//! then, under adaptive sampling, the remaining training periods one at a time while the error
//! model fitted so far misses a held-out measurement, the one nearest the worst miss first
//! (`crate::options`: `period_plan`, `held_out_check`, `next_period`).

use reproj_models::profile::Measurement;

use crate::AnalyzeError;
use crate::journal::ReplayKey;
use crate::options::{HeldOut, held_out_check, next_extension, next_period};
use crate::replayer::{RaceEntry, Replayer, Subject, too_slow};

/// Periods to replay at, in order: (Δn, skippable).
pub(crate) type Plan = Vec<(u32, bool)>;

impl Replayer<'_, '_> {
    /// The block race's period (`--block auto`), the periods a node is replayed at first (the
    /// longest, and the block race's) and the rest of `plan`.
    pub(crate) fn period_order(&self, plan: &[(u32, bool)]) -> (Option<u32>, Plan, Plan) {
        let (input, opts, longest) = (self.input, self.opts, self.longest);
        let race_dn = (opts.race_blocks && opts.block.is_none()).then(|| {
            let frames = opts
                .max_frames
                .map_or(input.session.frames, |m| m.min(input.session.frames));
            crate::blocks::race_period(&opts.delta_n_train, frames)
        });
        let mut first = vec![(longest, false)];
        let mut rest = plan.to_vec();
        if let Some(dn) = race_dn.filter(|&dn| dn != longest) {
            first.push((dn, false));
            rest.retain(|&(d, _)| d != dn);
        }
        (race_dn, first, rest)
    }

    /// Replay `subject`'s variant over the whole session at the periods of `plan` ((Δn,
    /// skippable)), appending to `measurements`: the fixed periods in order, then the skippable
    /// ones one at a time while the error model misses a held-out measurement, the one nearest the
    /// worst miss first ([`crate::options::Sampling::Adaptive`]: the rest are left out once it holds). A replay
    /// that fails, or one at the longest period no faster than the original (a non-root subject),
    /// sets `failure`; the remaining periods are then only counted for the progress bar.
    pub(crate) fn replay_plan(
        &mut self,
        subject: &Subject,
        sources: &[String],
        variant: &reproj_instance::Variant,
        plan: &[(u32, bool)],
        measurements: &mut Vec<Measurement>,
        failure: &mut Option<String>,
    ) -> Result<(), AnalyzeError> {
        let who = &subject.who;
        let mut verdict = subject.verdict.clone();
        let (fixed, mut pool): (Vec<_>, Vec<_>) = plan.iter().partition(|p| !p.1);
        let mut run = PeriodRun {
            subject,
            sources,
            variant,
            measurements,
            failure,
            verdict: &mut verdict,
        };
        for &(dn, _) in &fixed {
            self.replay_period(&mut run, dn)?;
        }
        let mut pool: Vec<u32> = pool.drain(..).map(|p| p.0).collect();
        while !pool.is_empty() {
            let next = if run.failure.is_some() {
                None
            } else {
                match held_out_check(run.measurements, self.opts) {
                    HeldOut::Holds => None,
                    HeldOut::Misses { worst } => next_period(&pool, worst),
                    HeldOut::Unchecked => pool.first().copied(),
                }
            };
            let Some(dn) = next else {
                for dn in pool.drain(..) {
                    if run.failure.is_some() {
                        self.progress.step(&format!("{who} Δn={dn}"));
                    } else {
                        self.progress.step(&format!(
                            "{who} Δn={dn} skipped: the error model predicts the held-out periods"
                        ));
                    }
                }
                break;
            };
            pool.retain(|&d| d != dn);
            self.replay_period(&mut run, dn)?;
        }
        Ok(())
    }

    /// Replay `subject` past the longest training period, doubling Δn while
    /// [`next_extension`] says a longer period can still pay (its error under the loosest
    /// budget, refreshing still a real part of its frame time), after [`Replayer::replay_plan`].
    /// Says where and why the periods stop once they went past the training ones.
    ///
    /// `raced`: the subject's speedup raced interleaved at the longest training period; a
    /// longer period's is that scaled by the replays' frame times (the original's replay
    /// where it was not raced).
    pub(crate) fn extend_periods(
        &mut self,
        raced: Option<f64>,
        subject: &Subject,
        sources: &[String],
        variant: &reproj_instance::Variant,
        measurements: &mut Vec<Measurement>,
        failure: &mut Option<String>,
    ) -> Result<(), AnalyzeError> {
        let frames = self.opts.max_frames.map_or(self.input.session.frames, |m| {
            m.min(self.input.session.frames)
        });
        let mut verdict = None;
        let mut run = PeriodRun {
            subject,
            sources,
            variant,
            measurements,
            failure,
            verdict: &mut verdict,
        };
        while run.failure.is_none() {
            let Some(last) = run
                .measurements
                .iter()
                .filter(|m| m.frame_ms.is_finite() && m.frame_ms > 0.0)
                .max_by_key(|m| m.delta_n)
            else {
                break;
            };
            let at_longest = run
                .measurements
                .iter()
                .find(|m| m.delta_n == self.longest)
                .map(|m| m.frame_ms);
            let speedup = match (raced, at_longest) {
                (Some(s), Some(ms)) => s * ms / last.frame_ms,
                _ => self.original_ms / last.frame_ms,
            };
            match next_extension(last, speedup, frames, &self.opts.extension) {
                Ok(dn) => {
                    self.progress.extend(1);
                    self.replay_period(&mut run, dn)?;
                }
                Err(stop) => {
                    if last.delta_n > self.longest {
                        self.progress.note(&format!(
                            "{}: periods extended to Δn = {}; stopped: {stop}",
                            subject.who, last.delta_n
                        ));
                    }
                    break;
                }
            }
        }
        Ok(())
    }

    /// One period of [`Replayer::replay_plan`]: the race at the longest period first (a non-root
    /// subject not yet raced), the replay, its measurement or its failure.
    fn replay_period(&mut self, run: &mut PeriodRun<'_, '_>, dn: u32) -> Result<(), AnalyzeError> {
        let subject = run.subject;
        let Subject {
            who,
            text,
            strategy,
            ..
        } = subject;
        if run.failure.is_some() {
            self.progress.step(&format!("{who} Δn={dn}"));
            return Ok(());
        }
        let key = ReplayKey {
            node: subject.node,
            strategy: strategy.name().into(),
            block: subject.block,
            delta_n: dn,
            frames: None,
            set: subject.set.clone(),
            reconstruct: subject.reconstruct.map(|r| r.name().to_string()),
        };
        if dn == self.longest && !subject.raced && !subject.root {
            let race = self.race(
                who,
                subject.node,
                &subject.set,
                &[RaceEntry {
                    name: who.clone(),
                    sources: run.sources,
                    variant: run.variant,
                    delta_n: self.longest,
                }],
            )?;
            if let Some(e) = race.estimate(0) {
                *run.verdict = too_slow(&e, subject.root, self.longest, *strategy);
            }
        }
        match self.replay(key, run.sources, run.variant, dn, None)? {
            Ok((m, _)) => {
                run.measurements.push(m);
                if dn == self.longest
                    && let Some(why) = run.verdict.take()
                {
                    self.progress
                        .note(&format!("{who} `{text}`: set aside: {why}"));
                    *run.failure = Some(why);
                }
            }
            Err(e) => {
                self.progress
                    .note(&format!("{who}: set aside: replay failed at Δn={dn}: {e}"));
                *run.failure = Some(format!("replay failed at Δn={dn}: {e}"));
            }
        }
        self.progress.step(&format!("{who} {strategy} Δn={dn}"));
        Ok(())
    }
}

/// What the periods of one [`Replayer::replay_plan`] share.
struct PeriodRun<'r, 'v> {
    subject: &'r Subject,
    sources: &'r [String],
    variant: &'r reproj_instance::Variant,
    measurements: &'r mut Vec<Measurement>,
    failure: &'r mut Option<String>,
    /// Why the subject is set aside after its replay at the longest period, once its race says so.
    verdict: &'v mut Option<String>,
}
