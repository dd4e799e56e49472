//! The reconstruction filter as a measured variant dimension (`analyze --reconstruct auto`).
//!
//! Catmull-Rom lowers the error per reuse (a value carried for Δn frames is resampled up to Δn
//! times, and bilinear blurs each time) but reads nine texels where bilinear reads one: whether it
//! pays depends on the scene and the device. The question the selector asks is *which is faster
//! at a given error*, so that is what the race measures, per node, after the node's strategy was
//! chosen and profiled with the base filter (bilinear):
//!
//! 0. a node whose base variant was no faster than the original at the longest training Δn in its
//!    strategy race is not raced: a dearer filter at the same period cannot pay where it does not;
//! 1. the challenger (Catmull-Rom) is replayed over the whole session at the longest training Δn
//!    (its error there; the replay is kept as its first measurement if it wins);
//! 2. where its error is no lower than the base's at that Δn, the base is kept at once (no race);
//! 3. otherwise the base is taken at its *equal-error period* — the longest Δn whose error the
//!    base's fitted model predicts at or below the challenger's: what the selector would pick for
//!    the base under that budget — and both are timed interleaved with the original in one race;
//! 4. the challenger is kept only when its speedup beats the base's beyond doubt (their intervals
//!    separate) and it is not slower than the original; ties and noise keep the base, the simpler
//!    and cheaper filter. Where the short race leaves the challenger ahead by its estimate but
//!    not beyond doubt, the two are raced again, longer ([`crate::replayer::LONG_RACE`]), and that
//!    race decides. A kept challenger is then replayed at the node's other periods, and the
//!    node's models are fitted to its measurements alone.
//!
//! A node that does not need the sharper filter pays one replay and one short race; one that keeps
//! it pays its periods twice. Comparing at equal error rather than at equal Δn (or by error per
//! time saved at one Δn, a ray from the original through one point) is what makes the rule agree
//! with the selector: on lavapipe, Catmull-Rom halves marble's error at equal Δn and still loses at
//! equal error, because bilinear at half the Δn has nearly the same hit rate.

use reproj_instance::{InstanceOptions, NodeSelector, Reconstruct, Strategy};
use reproj_models::profile::{FilterProbe, Measurement, Timed};
use reproj_models::speedup::{SpeedupEstimate, separates};
use reproj_models::{ErrorFit, ErrorFitOptions, fit_error};

use crate::AnalyzeError;
use crate::replayer::{Challenger, Duel, RaceEntry, Replayer, finite, timed_candidate};

/// The filter raced against the analysis's own (bilinear).
pub(crate) const CHALLENGER: Reconstruct = Reconstruct::CatmullRom;

/// The base filter's equal-error period: the longest Δn in `2..=longest` whose error, as
/// `predict` gives it, is at most `error` (the selector's pick for the base under a budget of
/// `error`). `None`: the base exceeds `error` even at Δn = 2, so only the original reaches it.
pub(crate) fn equal_error_period(
    predict: impl Fn(u32) -> Option<f64>,
    error: f64,
    longest: u32,
) -> Option<u32> {
    (2..=longest)
        .rev()
        .find(|&dn| predict(dn).is_some_and(|e| e.is_finite() && e <= error))
}

/// Whether the challenger pays for itself at equal error: its speedup over the original beats the
/// base's beyond doubt (their 95 % intervals separate, the challenger's above), and it is not
/// slower than the original beyond doubt. `base` is `None` where the base reaches the
/// challenger's error at no period: the original (1×) stands in, and the challenger must be surely
/// faster than it. Ties and noise keep the base.
pub(crate) fn challenger_pays(
    base: Option<&SpeedupEstimate>,
    challenger: &SpeedupEstimate,
) -> bool {
    if challenger.surely_slower() {
        return false;
    }
    match base {
        Some(b) => challenger.speedup > b.speedup && separates(challenger, b),
        None => challenger.surely_faster(),
    }
}

/// Whether a short race left the challenger ahead of the base by its estimate (by more than 3 %)
/// without deciding: then a longer race is worth its time. Behind, or level, the base stays
/// whatever more rounds would say; against the original (no base) the short race decides.
pub(crate) fn worth_racing_longer(
    base: Option<&SpeedupEstimate>,
    challenger: &SpeedupEstimate,
) -> bool {
    match base {
        Some(b) => {
            challenger.speedup > 1.03 * b.speedup
                && !challenger_pays(Some(b), challenger)
                && !challenger.surely_slower()
        }
        None => false,
    }
}

/// Whether a node is worth a filter race: its base variant at the longest period (the fastest it
/// gets) was timed faster than the original (`base_speedup`, the strategy race's estimate). A
/// dearer filter at the same period is no faster, so where the base does not pay, nothing can;
/// a node never timed is not raced either.
pub(crate) fn worth_racing(base_speedup: Option<f64>) -> bool {
    base_speedup.is_some_and(|s| s > 1.0)
}

/// A node's variant as its strategy race left it, with its base-filter measurements.
pub(crate) struct FilterRace<'a> {
    pub(crate) id: u32,
    pub(crate) sel: NodeSelector,
    pub(crate) strategy: Strategy,
    pub(crate) block: u32,
    pub(crate) base_sources: &'a [String],
    pub(crate) base_variant: &'a reproj_instance::Variant,
    pub(crate) base_measurements: &'a [Measurement],
    /// The base variant's speedup at the longest period (its strategy race's estimate).
    pub(crate) base_speedup: Option<f64>,
}

/// The challenger, kept: its variant and its measurement at the longest period.
pub(crate) type Kept = Challenger;

/// Race the challenger filter against the node's base filter (see the module docs), appending
/// the probes to `probes`. `Some`: the challenger is kept and its remaining periods are the
/// caller's to replay. Reports three progress steps (instance, replay, race). Phases: the base's
/// error model, the challenger at the longest period, the race at equal error, the verdict.
pub(crate) fn race_filter(
    rp: &mut Replayer<'_, '_>,
    race: &FilterRace<'_>,
    probes: &mut Vec<FilterProbe>,
) -> Result<Option<Kept>, AnalyzeError> {
    let longest = rp.longest;
    let base = rp.opts.instance.reconstruct;
    if !worth_racing(race.base_speedup) {
        return Ok(None);
    }
    let Some((base_at_longest, fit)) = base_model(rp, race) else {
        return Ok(None);
    };
    rp.progress.extend(3);
    let Some(challenger) = challenger_at_longest(rp, race)? else {
        return Ok(None);
    };
    let challenger_error = challenger.measurement.error;
    if challenger_error >= base_at_longest {
        rp.progress.step(&format!("node {} filters", race.id));
        probes.push(FilterProbe {
            note: Some(format!(
                "{CHALLENGER} is no more accurate than {base} at Δn {longest} ({challenger_error:.5} vs {base_at_longest:.5}): not raced"
            )),
            ..probe(race, CHALLENGER, longest, challenger_error)
        });
        return Ok(None);
    }
    let predict = |dn: u32| fit.predict(f64::from(dn));
    let base_period = equal_error_period(predict, challenger_error, longest);
    let raced = race_at_equal_error(rp, race, &challenger, base_period)?;
    let kept = match &raced.challenger {
        Some(c) if base_period.is_none() || raced.base.is_some() => {
            challenger_pays(raced.base.as_ref(), c)
        }
        _ => false,
    };
    let verdict = Verdict {
        base,
        base_period,
        base_error: base_period.map(|dn| predict(dn).unwrap_or(0.0)),
        challenger_error,
        kept,
    };
    record(rp, race, &raced, &verdict, probes);
    Ok(kept.then_some(challenger))
}

/// A probe of the node's race: `reconstruct` at `delta_n` with its error, untimed, not kept.
fn probe(race: &FilterRace, reconstruct: Reconstruct, delta_n: u32, error: f64) -> FilterProbe {
    FilterProbe {
        node: race.id,
        reconstruct: Some(reconstruct.name().into()),
        strategy: race.strategy.name().into(),
        block: race.block,
        delta_n,
        error: finite(error),
        timed: Timed::default(),
        kept: false,
        note: None,
    }
}

/// The base filter's error at the longest period and its error model over the training
/// periods; `None` when there is nothing to compare against (no measurement there, or a failed
/// fit, which sets the node aside on its own).
fn base_model(rp: &Replayer<'_, '_>, race: &FilterRace<'_>) -> Option<(f64, ErrorFit)> {
    let base_at_longest = race
        .base_measurements
        .iter()
        .find(|m| m.delta_n == rp.longest)
        .map(|m| m.error)?;
    let train: Vec<(f64, f64)> = race
        .base_measurements
        .iter()
        .filter(|m| rp.opts.delta_n_train.contains(&m.delta_n))
        .map(|m| (f64::from(m.delta_n), m.error))
        .collect();
    let fit = fit_error(&train, &ErrorFitOptions::default());
    fit.is_ok().then_some((base_at_longest, fit))
}

/// The challenger filter instanced and replayed at the longest period
/// ([`Replayer::challenger_at`]).
fn challenger_at_longest(
    rp: &mut Replayer<'_, '_>,
    race: &FilterRace<'_>,
) -> Result<Option<Kept>, AnalyzeError> {
    let base = rp.opts.instance.reconstruct;
    let inst = InstanceOptions {
        strategy: race.strategy,
        block: race.block,
        reconstruct: CHALLENGER,
        ..rp.opts.instance
    };
    let longest = rp.longest;
    rp.challenger_at(
        race.id,
        race.sel,
        &inst,
        longest,
        CHALLENGER.name(),
        base.name(),
        "filters",
    )
}

/// Race the base at its equal-error period (when it has one) and the challenger at the longest,
/// again and longer when the first race leaves it undecided ([`worth_racing_longer`]; the third
/// progress step).
fn race_at_equal_error(
    rp: &mut Replayer<'_, '_>,
    race: &FilterRace<'_>,
    challenger: &Kept,
    base_period: Option<u32>,
) -> Result<Duel, AnalyzeError> {
    let longest = rp.longest;
    let base = rp.opts.instance.reconstruct;
    let base_entry = base_period.map(|dn| RaceEntry {
        name: format!("{base}@{dn}"),
        sources: race.base_sources,
        variant: race.base_variant,
        delta_n: dn,
    });
    let challenger_entry = RaceEntry {
        name: format!("{CHALLENGER}@{longest}"),
        sources: &challenger.sources,
        variant: &challenger.variant,
        delta_n: longest,
    };
    rp.duel(race.id, "filters", base_entry, challenger_entry, |b, c| {
        worth_racing_longer(Some(b), c)
    })
}

/// What the race decided: the base filter and its equal-error period with the error its model
/// predicts there, the challenger's error, and whether the challenger is kept.
struct Verdict {
    base: Reconstruct,
    base_period: Option<u32>,
    base_error: Option<f64>,
    challenger_error: f64,
    kept: bool,
}

/// The verdict as a note and as the two timed probes (the base's, when it raced, and the
/// challenger's).
fn record(
    rp: &Replayer<'_, '_>,
    race: &FilterRace<'_>,
    raced: &Duel,
    v: &Verdict,
    probes: &mut Vec<FilterProbe>,
) {
    let (base, longest) = (v.base, rp.longest);
    let challenger_error = v.challenger_error;
    let timed = |p: FilterProbe, i: usize| FilterProbe {
        timed: timed_candidate(&raced.report, i),
        ..p
    };
    let shown = |e: Option<&SpeedupEstimate>| e.map_or_else(|| "untimed".into(), |e| e.display());
    let against = match v.base_period {
        Some(dn) => format!(
            "{base} at Δn {dn}, its equal-error period, {}",
            shown(raced.base.as_ref())
        ),
        None => format!("the original ({base} exceeds that error at every period)"),
    };
    let note = format!(
        "{CHALLENGER} at Δn {longest} (error {challenger_error:.5}, {}) against {against}: {}",
        shown(raced.challenger.as_ref()),
        if v.kept {
            format!("faster at equal error, keeps {CHALLENGER}")
        } else {
            format!("not faster beyond doubt, keeps {base}")
        }
    );
    rp.progress.note(&format!("node {}: {note}", race.id));
    if let (Some(dn), Some(error)) = (v.base_period, v.base_error) {
        probes.push(FilterProbe {
            kept: !v.kept,
            ..timed(probe(race, base, dn, error), 0)
        });
    }
    probes.push(FilterProbe {
        kept: v.kept,
        note: Some(note),
        ..timed(
            probe(race, CHALLENGER, longest, challenger_error),
            raced.last,
        )
    });
}

#[cfg(test)]
mod tests {
    use super::*;

    use crate::replayer::test_estimate as e;

    /// Marble's node 680 on lavapipe (docs/PASSES.md): bilinear's error is 0.0102 at Δn 13 and
    /// 0.0158 at Δn 30; Catmull-Rom has 0.0084 at Δn 30, bilinear's error at Δn 9–10.
    fn bilinear(dn: u32) -> Option<f64> {
        Some(0.018 * (1.0 - (-0.07 * (f64::from(dn) - 1.0)).exp()))
    }

    #[test]
    fn the_equal_error_period_is_the_base_s_longest_period_within_the_challenger_s_error() {
        let target = 0.0084;
        let dn = equal_error_period(bilinear, target, 30).unwrap();
        assert!(bilinear(dn).unwrap() <= target && bilinear(dn + 1).unwrap() > target);
        assert_eq!(dn, 9);
        // Within the error at every period: the longest.
        assert_eq!(equal_error_period(bilinear, 1.0, 30), Some(30));
        // Above the error even at Δn 2: only the original reaches it.
        assert_eq!(equal_error_period(bilinear, 1e-4, 30), None);
        // No prediction, or a non-finite one, is never within.
        assert_eq!(equal_error_period(|_| None, 1.0, 30), None);
        assert_eq!(equal_error_period(|_| Some(f64::NAN), 1.0, 30), None);
    }

    #[test]
    fn only_a_challenger_ahead_but_undecided_is_raced_again() {
        // The H200's node 680: Catmull-Rom 2.39× [1.89, 3.03] against bilinear 1.84× [1.78, 1.90].
        assert!(worth_racing_longer(
            Some(&e(1.84, 1.78, 1.90)),
            &e(2.39, 1.89, 3.03)
        ));
        // Decided already (apart), behind, level within 3 %, or against the original: no.
        assert!(!worth_racing_longer(
            Some(&e(1.84, 1.78, 1.90)),
            &e(2.39, 2.20, 2.60)
        ));
        assert!(!worth_racing_longer(
            Some(&e(1.96, 1.88, 2.05)),
            &e(1.66, 1.59, 1.75)
        ));
        assert!(!worth_racing_longer(
            Some(&e(1.18, 1.10, 1.26)),
            &e(1.20, 1.12, 1.28)
        ));
        assert!(!worth_racing_longer(None, &e(1.5, 0.9, 2.1)));
    }

    #[test]
    fn a_node_whose_base_does_not_pay_at_its_longest_period_is_not_raced() {
        assert!(worth_racing(Some(1.4)));
        assert!(!worth_racing(Some(0.9)));
        assert!(!worth_racing(Some(1.0)));
        assert!(!worth_racing(None));
    }

    #[test]
    fn the_challenger_is_kept_only_when_faster_at_equal_error_beyond_doubt() {
        // Lavapipe: Catmull-Rom at Δn 30 (1.66×) against bilinear at its equal-error period
        // (1.96×): the base stays.
        assert!(!challenger_pays(
            Some(&e(1.96, 1.88, 2.05)),
            &e(1.66, 1.59, 1.75)
        ));
        // Faster, but the intervals overlap: noise keeps the base.
        assert!(!challenger_pays(
            Some(&e(1.90, 1.80, 2.00)),
            &e(1.98, 1.92, 2.05)
        ));
        // Faster beyond doubt (a GPU, where the fetches are cheap next to the node): kept.
        assert!(challenger_pays(
            Some(&e(1.90, 1.85, 1.95)),
            &e(2.40, 2.30, 2.50)
        ));
        // The base reaches that error at no period: the original stands in.
        assert!(challenger_pays(None, &e(1.3, 1.1, 1.5)));
        assert!(!challenger_pays(None, &e(1.1, 0.9, 1.3)));
        // Never a challenger slower than the original beyond doubt.
        assert!(!challenger_pays(
            Some(&e(0.5, 0.45, 0.55)),
            &e(0.8, 0.75, 0.85)
        ));
    }
}
