//! The one race skeleton: variants of a node (its strategies, or a base and a challenger of a
//! refresh block or a reconstruction filter) raced against the original in one short race, and
//! where that leaves a question open, raced again — longer, that race deciding, or as long, the
//! rounds of both pooled.

use reproj_models::speedup::SpeedupEstimate;

use super::{RaceEntry, RaceLength, Replayer};
use crate::AnalyzeError;

/// What a contest's first race leaves open, and how it is settled ([`Replayer::contest`]).
pub(crate) enum Again {
    /// Every entry raced again, longer; that race decides. `why` is said first.
    Longer { why: String },
    /// The entries `which` raced again as long; each one's estimate becomes that of the rounds of
    /// both races (the same subjects, windows and baseline). `why` is said with the result.
    Pooled { which: Vec<usize>, why: String },
}

/// What [`Replayer::contest`] measured: the report the estimates come from (the longer race's, or
/// for pooled rounds the first race's) and each entry's estimate.
pub(crate) struct Contest {
    pub(crate) report: reproj_bench::BenchReport,
    pub(crate) estimates: Vec<Option<SpeedupEstimate>>,
}

/// What [`Replayer::duel`] measured: the deciding race's report, and its estimates of the base
/// (where it raced) and of the challenger, the report's candidate `last`.
pub(crate) struct Duel {
    pub(crate) report: reproj_bench::BenchReport,
    pub(crate) base: Option<SpeedupEstimate>,
    pub(crate) challenger: Option<SpeedupEstimate>,
    pub(crate) last: usize,
}

impl Replayer<'_, '_> {
    /// Race `entries` (variants of node `id`) against the original, interleaved, in one short
    /// race; where `again` finds a question open in its estimates, race again as it says
    /// ([`Again`]). `label` names the race in the progress, whose step `done` ends it (one more
    /// step where the rounds are pooled).
    pub(crate) fn contest(
        &mut self,
        (id, label, done): (u32, &str, &str),
        entries: &[RaceEntry<'_>],
        again: impl FnOnce(&[Option<SpeedupEstimate>]) -> Option<Again>,
    ) -> Result<Contest, AnalyzeError> {
        let estimates_of = |r: &reproj_bench::BenchReport| -> Vec<Option<SpeedupEstimate>> {
            (0..r.candidates.len()).map(|i| r.estimate(i)).collect()
        };
        let mut report = self.race(label, id, &[], entries)?;
        let mut estimates = estimates_of(&report);
        match again(&estimates) {
            None => {}
            Some(Again::Longer { why }) => {
                self.progress.note(&why);
                report = self.race_as(label, id, &[], entries, RaceLength::Long)?;
                estimates = estimates_of(&report);
            }
            Some(Again::Pooled { which, why }) => {
                let chosen: Vec<RaceEntry<'_>> = which
                    .iter()
                    .map(|&i| RaceEntry {
                        name: entries[i].name.clone(),
                        ..entries[i]
                    })
                    .collect();
                self.progress.extend(1);
                let second = self.race_as(label, id, &[], &chosen, RaceLength::Again)?;
                self.progress.step(&format!("{label} race again"));
                let mut said = Vec::new();
                for (j, &i) in which.iter().enumerate() {
                    let Some(pooled) = report.pooled_estimate(i, &second, j) else {
                        continue;
                    };
                    said.push(format!(
                        "{} {} → {}",
                        entries[i].name,
                        estimates[i].map_or_else(|| "–".into(), |e| e.display()),
                        pooled.display()
                    ));
                    estimates[i] = Some(pooled);
                }
                self.progress.note(&format!(
                    "{why}; raced again, both races' rounds: {}",
                    said.join(", ")
                ));
            }
        }
        self.progress.step(done);
        Ok(Contest { report, estimates })
    }

    /// The contest of one variant dimension (a refresh block, a reconstruction filter) for node
    /// `id`: `base` (where it races) against `challenger`; where `undecided` says the short race
    /// left the two open, they race again, longer, and that race decides. `what` names the
    /// dimension in the progress (`blocks`, `filters`), whose last step this is.
    pub(crate) fn duel(
        &mut self,
        id: u32,
        what: &str,
        base: Option<RaceEntry<'_>>,
        challenger: RaceEntry<'_>,
        undecided: impl Fn(&SpeedupEstimate, &SpeedupEstimate) -> bool,
    ) -> Result<Duel, AnalyzeError> {
        let who = format!("node {id}");
        let label = format!("{who} {what}");
        let has_base = base.is_some();
        let names = (
            base.as_ref().map(|b| b.name.clone()).unwrap_or_default(),
            challenger.name.clone(),
        );
        let entries: Vec<RaceEntry<'_>> = base.into_iter().chain([challenger]).collect();
        let last = entries.len() - 1;
        let done = format!("{label} raced");
        let contest = self.contest((id, &label, &done), &entries, |e| {
            let (Some(b), Some(c)) = (has_base.then(|| e[0]).flatten(), e[last]) else {
                return None;
            };
            undecided(&b, &c).then(|| Again::Longer {
                why: format!(
                    "{who}: {} {} against {} {}: undecided, racing again, longer",
                    names.1,
                    c.display(),
                    names.0,
                    b.display()
                ),
            })
        })?;
        Ok(Duel {
            base: has_base.then(|| contest.estimates[0]).flatten(),
            challenger: contest.estimates[last],
            report: contest.report,
            last,
        })
    }
}
