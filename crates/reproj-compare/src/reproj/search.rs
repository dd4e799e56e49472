//! Where on the profile reproj's point lies: the candidates (usable nodes and measured sets on
//! the Pareto frontier), the point at a target speedup or under an error budget, the reported
//! node's own curve (`along`), and the point steered by racing it against the original.

use std::path::Path;

use reproj_front::Loaded;
use reproj_models::profile::{NodeProfile, NodeStatus, SetProfile};
use reproj_models::{Metric, Profile};
use reproj_select::{
    Budget, DEFAULT_MIN_DELTA_N, NodeRecord, SelectOptions, Selection, SetRecord, pareto, predict,
    select_with_sets,
};

use super::{Planned, Profiled, ReprojDetail, ReprojTry, variant};
use crate::{CompareError, Ctx};

/// A planned point: (pick, Δn, predicted error, predicted ms).
pub(super) type Point<'p> = (Profiled<'p>, u32, f64, f64);

/// What reproj may choose from a profile: its usable nodes and measured sets, and their
/// selector records.
pub(super) struct Candidates<'p> {
    usable: Vec<&'p NodeProfile>,
    records: Vec<NodeRecord>,
    sets: Vec<&'p SetProfile>,
    set_records: Vec<SetRecord>,
}

impl<'p> Candidates<'p> {
    pub(super) fn of(profile: &'p Profile) -> Candidates<'p> {
        let usable: Vec<&NodeProfile> = profile
            .nodes
            .iter()
            .filter(|n| n.status == NodeStatus::Ok)
            .collect();
        let records: Vec<NodeRecord> = usable
            .iter()
            .filter_map(|n| NodeRecord::from_profile(profile, n, Metric::L2))
            .collect();
        let sets: Vec<&SetProfile> = profile
            .sets
            .iter()
            .filter(|s| s.status == NodeStatus::Ok && s.members.len() > 1)
            .collect();
        let set_records: Vec<SetRecord> = sets
            .iter()
            .map(|s| SetRecord {
                members: s.members.clone(),
                texts: s.texts.clone(),
                strategy: s.strategy.clone(),
                error: s.error_fit.clone(),
                timing: s.timing_fit.clone(),
                mean_pixels: profile.original.mean_pixels,
                measured_errors: reproj_select::measured_errors(&s.measurements, Metric::L2),
            })
            .collect();
        Candidates {
            usable,
            records,
            sets,
            set_records,
        }
    }

    /// The node `id` in `strategy`, as a pick.
    fn node(&self, id: u32, strategy: &str) -> Profiled<'p> {
        Profiled::Node(
            self.usable
                .iter()
                .find(|n| n.id == id && n.strategy == strategy)
                .expect("the choice comes from the profile's nodes"),
        )
    }
}

/// The reported point's own pick (node or set, in its strategy) at the least Δn whose predicted
/// speedup reaches `target` (the fastest of its periods where none does): where `compare` moves
/// reproj to resizing's speed, along the one curve its calibration was measured on (another
/// node's models may be off by another factor: the environment map's node 658 measured 1.73×
/// against 2.02× predicted, the root 2.61× against 2.35×). `None` where the pick is not in the
/// profile's usable nodes and sets.
pub(crate) fn along<'p>(
    profile: &'p Profile,
    reported: &ReprojDetail,
    target: f64,
    max_delta_n: u32,
) -> Option<Planned<'p>> {
    let c = Candidates::of(profile);
    let same =
        |pick: &Profiled| pick.name() == reported.node && pick.strategy_name() == reported.strategy;
    let curve: Vec<(Profiled<'p>, NodeRecord)> = c
        .records
        .iter()
        .map(|r| (c.node(r.id, &r.strategy), r.clone()))
        .chain(
            c.sets
                .iter()
                .zip(&c.set_records)
                .map(|(s, r)| (Profiled::Set(s), r.as_node())),
        )
        .filter(|(pick, _)| same(pick))
        .collect();
    let (pick, record) = curve.into_iter().next()?;
    let points: Vec<Point<'p>> = (DEFAULT_MIN_DELTA_N..=max_delta_n)
        .filter_map(|dn| {
            let p = predict(&record, &profile.hit_rate, dn)?;
            Some((pick, dn, p.predicted_error, p.predicted_ms))
        })
        .collect();
    let speedup = |ms: f64| profile.original.frame_ms / ms;
    points
        .iter()
        .filter(|p| speedup(p.3) >= target)
        .min_by_key(|p| p.1)
        .or_else(|| {
            points
                .iter()
                .max_by(|a, b| speedup(a.3).total_cmp(&speedup(b.3)))
        })
        .map(|&p| Planned::at(p, profile))
}

/// For a target speedup: among the single nodes' frontier and every set's points, the least
/// predicted error that reaches it, else the fastest; `None` when there is no point.
pub(super) fn at_speedup<'p>(
    c: &Candidates<'p>,
    profile: &Profile,
    target: f64,
    max_delta_n: u32,
) -> Option<Point<'p>> {
    let speedup = |ms: f64| profile.original.frame_ms / ms;
    let front = pareto(
        &c.records,
        &profile.hit_rate,
        DEFAULT_MIN_DELTA_N,
        max_delta_n,
    );
    let mut points: Vec<Point> = front
        .iter()
        .map(|p| {
            (
                c.node(p.node_id, &p.strategy),
                p.delta_n,
                p.predicted_error,
                p.predicted_ms,
            )
        })
        .collect();
    for (set, rec) in c.sets.iter().zip(&c.set_records) {
        let as_node = rec.as_node();
        for dn in DEFAULT_MIN_DELTA_N..=max_delta_n {
            if let Some(p) = predict(&as_node, &profile.hit_rate, dn) {
                points.push((Profiled::Set(set), dn, p.predicted_error, p.predicted_ms));
            }
        }
    }
    points
        .iter()
        .filter(|p| speedup(p.3) >= target)
        .min_by(|a, b| a.2.total_cmp(&b.2))
        .or_else(|| {
            points
                .iter()
                .max_by(|a, b| speedup(a.3).total_cmp(&speedup(b.3)))
        })
        .copied()
}

/// For an error budget: what `emit --max-error` selects, sets included; why the original is
/// kept otherwise.
pub(super) fn under_budget<'p>(
    c: &Candidates<'p>,
    profile: &Profile,
    max_error: Budget,
    max_delta_n: u32,
) -> Result<Point<'p>, String> {
    let opts = SelectOptions {
        max_error,
        min_delta_n: DEFAULT_MIN_DELTA_N,
        max_delta_n,
    };
    match select_with_sets(
        &c.records,
        &c.set_records,
        &profile.hit_rate,
        profile.original.frame_ms,
        &opts,
    ) {
        Selection::Node(choice) if !choice.members.is_empty() => {
            let set = c
                .sets
                .iter()
                .find(|s| s.members == choice.members && s.strategy == choice.strategy)
                .expect("the choice comes from the profile's sets");
            Ok((
                Profiled::Set(set),
                choice.delta_n,
                choice.predicted_error,
                choice.predicted_ms,
            ))
        }
        Selection::Node(choice) => Ok((
            c.node(choice.node_id, &choice.strategy),
            choice.delta_n,
            choice.predicted_error,
            choice.predicted_ms,
        )),
        Selection::Original { reason } => Err(reason.to_string()),
    }
}

/// At a target speedup, reproj's point steered by measurement, as resizing's scale is: each try
/// is raced against the original (interleaved, the searches' timing); when its measured speedup
/// misses the target by more than `tolerance`, the frontier is asked again for the target scaled by
/// the try's predicted over measured speedup (how far the models are off on this machine), until
/// a try lands within the tolerance, a point comes back, or `tries` are spent. The try closest to
/// the target (in log ratio, as for resizing) is kept; the tries are reported.
#[allow(clippy::too_many_arguments)]
pub(crate) fn steer<'p>(
    ctx: &Ctx,
    loaded: &Loaded,
    profile: &'p Profile,
    profile_path: &Path,
    first: Planned<'p>,
    max_delta_n: u32,
    tries: usize,
    tolerance: f64,
) -> Result<(Planned<'p>, Vec<ReprojTry>), CompareError> {
    let c = Candidates::of(profile);
    let miss = |s: f64| (s.max(1e-9) / ctx.target).ln().abs();
    let key = |p: &Planned| (p.pick.name(), p.pick.strategy_name().to_owned(), p.delta_n);
    let mut planned = first;
    let mut raced: Vec<(Planned<'p>, ReprojTry)> = Vec::new();
    for _ in 0..tries.max(1) {
        let input = variant(loaded, profile, profile_path, &planned)?;
        let (timed, races) = ctx.race_try(
            reproj_bench::Candidate {
                name: "reproj".into(),
                subject: reproj_bench::Subject::Variant(input),
            },
            tolerance,
        )?;
        let speedup = timed.map_or(0.0, |e| e.speedup);
        ctx.progress.step(&format!(
            "reproj {} at Δn {}: {speedup:.2}× (predicted {:.2}×)",
            planned.pick.name(),
            planned.delta_n,
            planned.predicted_speedup
        ));
        raced.push((
            planned,
            ReprojTry {
                node: planned.pick.name(),
                strategy: planned.pick.strategy_name().to_owned(),
                delta_n: planned.delta_n,
                predicted_error: planned.predicted_error,
                predicted_speedup: planned.predicted_speedup,
                speedup,
                speedup_ci95: timed.map(|e| e.ci95),
                races,
            },
        ));
        if speedup <= 0.0 || miss(speedup) <= (1.0 + tolerance).ln() {
            break;
        }
        let ask = ctx.target * planned.predicted_speedup / speedup;
        let Some(point) = at_speedup(&c, profile, ask, max_delta_n) else {
            break;
        };
        let next = Planned::at(point, profile);
        if raced.iter().any(|(p, _)| key(p) == key(&next)) {
            break;
        }
        planned = next;
    }
    let kept = (0..raced.len())
        .min_by(|&a, &b| miss(raced[a].1.speedup).total_cmp(&miss(raced[b].1.speedup)))
        .expect("at least one try");
    let chosen = raced[kept].0;
    Ok((chosen, raced.into_iter().map(|(_, t)| t).collect()))
}
