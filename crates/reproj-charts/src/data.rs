//! What each chart shows, taken from the profile: pure data (the trade-off's paths, frontier and
//! budget marks, the hit-rate fit's points); `draw` turns it into pictures.

use std::collections::{BTreeMap, BTreeSet};

use reproj_models::profile::{NodeProfile, NodeStatus};
use reproj_models::{HitRateStatus, Profile};
use reproj_select::{
    Budget, DEFAULT_MAX_DELTA_N, DEFAULT_MIN_DELTA_N, NodeRecord, SelectOptions, Selection,
    SetRecord, pareto, select_with_sets,
};

use crate::{finite_pos, node_label, setting, shader_name, usable};

/// More nodes than this: only the best [`HIGHLIGHTED`] get a color and a legend entry.
const MAX_LEGEND_NODES: usize = 12;
/// Nodes highlighted when there are more than [`MAX_LEGEND_NODES`].
pub(crate) const HIGHLIGHTED: usize = 8;

/// One node's measured path over Δn.
#[derive(Debug, Clone)]
pub(crate) struct NodePath {
    pub(crate) id: u32,
    pub(crate) label: String,
    /// Palette index; `None`: drawn thin grey without a legend entry.
    pub(crate) color: Option<usize>,
    pub(crate) set_aside: bool,
    /// `(Δn, frame ms, error)`, sorted by Δn.
    pub(crate) points: Vec<(u32, f64, f64)>,
}

/// Chart 1 (Fig. 7).
#[derive(Debug, Clone)]
pub(crate) struct Tradeoff {
    pub(crate) title: String,
    pub(crate) subtitle: String,
    /// Colored (legend) paths first, then the thin grey and set-aside ones.
    pub(crate) paths: Vec<NodePath>,
    /// Paths drawn thin grey without a legend entry (usable nodes not among the best).
    pub(crate) others: usize,
    /// Predicted frontier: `(ms, error, Δn, node id)`, by increasing time.
    pub(crate) pareto: Vec<(f64, f64, u32, u32)>,
    pub(crate) original_ms: Option<f64>,
    /// The selections at the chart's budgets, predicted: `(ms, error, label)`.
    pub(crate) marks: Vec<(f64, f64, String)>,
}

/// Chart 2 (Fig. 5).
#[derive(Debug, Clone)]
pub(crate) struct HitRate {
    pub(crate) title: String,
    pub(crate) subtitle: String,
    /// `(Δn, hit rate)` at training Δn.
    pub(crate) train: Vec<(f64, f64)>,
    /// `(Δn, hit rate)` at held-out Δn.
    pub(crate) holdout: Vec<(f64, f64)>,
    pub(crate) mu: Option<f64>,
    pub(crate) max_delta_n: f64,
}

/// The selector's records of the profile: its usable nodes and sets, as `reproj emit` builds them
/// (`reproj_select::profile_records`). Every node has an L2 model (`NodeProfile::fit`), so the
/// builder's only error, a missing model, cannot happen here.
pub(crate) fn records(profile: &Profile) -> (Vec<NodeRecord>, Vec<SetRecord>) {
    let keep = |_: &NodeProfile| true;
    reproj_select::profile_records(profile, reproj_models::Metric::L2, None, &keep, true)
        .map(|r| (r.nodes, r.sets))
        .unwrap_or_default()
}

/// The selections at `budgets` (emit's selector, sets included): one mark per distinct choice,
/// labelled with its budgets.
pub(crate) fn marks(profile: &Profile, budgets: &[f64]) -> Vec<(f64, f64, String)> {
    let (nodes, sets) = records(profile);
    /// (node, members, strategy, Δn), predicted ms and error, the budgets that choose it.
    type Marked = ((u32, Vec<u32>, String, u32), f64, f64, Vec<f64>);
    let mut marks: Vec<Marked> = Vec::new();
    for &budget in budgets {
        // A budget that is none (negative, not finite) selects nothing.
        let Ok(max_error) = Budget::new(budget) else {
            continue;
        };
        let Selection::Node(c) = select_with_sets(
            &nodes,
            &sets,
            &profile.hit_rate,
            profile.original.frame_ms,
            &SelectOptions::new(max_error),
        ) else {
            continue;
        };
        let key = (c.node_id, c.members.clone(), c.strategy.clone(), c.delta_n);
        match marks.iter_mut().find(|m| m.0 == key) {
            Some(m) => m.3.push(budget),
            None => marks.push((
                key,
                c.predicted_ms,
                c.predicted_error.max(0.0),
                vec![budget],
            )),
        }
    }
    marks
        .into_iter()
        .map(|((id, members, _, dn), ms, error, budgets)| {
            let budgets: Vec<String> = budgets.iter().map(|b| significant(*b)).collect();
            let what = if members.is_empty() {
                format!("node {id}")
            } else {
                let ids: Vec<String> = members.iter().map(u32::to_string).collect();
                format!("set {}", ids.join("+"))
            };
            (
                ms,
                error,
                format!("ε ≤ {}: {what}, Δn {dn}", budgets.join(", ")),
            )
        })
        .collect()
}

/// `v` with three significant digits, trailing zeros trimmed: `0.002`, `0.0127`, `0.1`.
pub(crate) fn significant(v: f64) -> String {
    if !(v.is_finite() && v > 0.0) {
        return format!("{v}");
    }
    let decimals = (2.0 - v.log10().floor()).clamp(0.0, 12.0) as usize;
    let s = format!("{v:.decimals$}");
    if s.contains('.') {
        s.trim_end_matches('0').trim_end_matches('.').to_string()
    } else {
        s
    }
}

/// The trade-off chart's data: every node's measured path, the predicted frontier, the
/// original's time and the selections at `budgets`; the best nodes highlighted
/// ([`highlighted`]).
pub(crate) fn tradeoff(profile: &Profile, budgets: &[f64]) -> Tradeoff {
    let original_ms = finite_pos(profile.original.frame_ms);
    let pareto: Vec<(f64, f64, u32, u32)> = pareto(
        &records(profile).0,
        &profile.hit_rate,
        DEFAULT_MIN_DELTA_N,
        DEFAULT_MAX_DELTA_N,
    )
    .into_iter()
    .filter(|p| p.predicted_ms.is_finite() && p.predicted_error.is_finite())
    .map(|p| {
        (
            p.predicted_ms,
            p.predicted_error.max(0.0),
            p.delta_n,
            p.node_id,
        )
    })
    .collect();
    let ok: Vec<&NodeProfile> = profile
        .nodes
        .iter()
        .filter(|n| n.status == NodeStatus::Ok && !measured_points(n).is_empty())
        .collect();
    let aside: Vec<&NodeProfile> = profile
        .nodes
        .iter()
        .filter(|n| n.status != NodeStatus::Ok && !measured_points(n).is_empty())
        .collect();
    let chosen = highlighted(&ok, &pareto);
    let path = |n: &NodeProfile, color: Option<usize>, set_aside: bool| NodePath {
        id: n.id,
        label: node_label(n, 38),
        color,
        set_aside,
        points: measured_points(n),
    };
    let mut paths = Vec::new();
    // Colored first (in id order), so they get stable colors; then the others below them.
    for n in ok.iter().filter(|n| chosen.contains(&n.id)) {
        paths.push(path(n, Some(paths.len()), false));
    }
    let mut others = 0;
    for n in ok.iter().filter(|n| !chosen.contains(&n.id)) {
        others += 1;
        paths.push(path(n, None, false));
    }
    for n in &aside {
        paths.push(path(n, None, true));
    }
    let usable_nodes = profile
        .nodes
        .iter()
        .filter(|n| n.status == NodeStatus::Ok)
        .count();
    Tradeoff {
        title: format!(
            "Error vs frame time per cached node — {}",
            shader_name(profile)
        ),
        subtitle: format!(
            "{}; {} nodes ({usable_nodes} usable); one path per node over Δn (numbers: Δn at the ends)",
            setting(profile),
            profile.nodes.len()
        ),
        paths,
        others,
        pareto,
        original_ms,
        marks: marks(profile, budgets),
    }
}

/// A node's usable measurements as `(Δn, ms, error)`, by Δn.
pub(crate) fn measured_points(n: &NodeProfile) -> Vec<(u32, f64, f64)> {
    let mut v: Vec<(u32, f64, f64)> = n
        .measurements
        .iter()
        .filter(|m| usable(m))
        .map(|m| (m.delta_n, m.frame_ms, m.error))
        .collect();
    v.sort_by_key(|p| p.0);
    v
}

/// The nodes drawn in colour: all of them when the legend holds them, else the best ones: most
/// points on the predicted and on the measured frontier, then lowest normalized distance to the
/// lower left.
pub(crate) fn highlighted(ok: &[&NodeProfile], pareto: &[(f64, f64, u32, u32)]) -> BTreeSet<u32> {
    if ok.len() <= MAX_LEGEND_NODES {
        return ok.iter().map(|n| n.id).collect();
    }
    let all: Vec<(u32, f64, f64)> = ok
        .iter()
        .flat_map(|n| measured_points(n).into_iter().map(|(_, t, e)| (n.id, t, e)))
        .collect();
    let mut on_front: BTreeMap<u32, usize> = BTreeMap::new();
    for &(id, t, e) in &all {
        let dominated = all
            .iter()
            .any(|&(_, t2, e2)| t2 <= t && e2 <= e && (t2 < t || e2 < e));
        if !dominated {
            *on_front.entry(id).or_default() += 1;
        }
    }
    for p in pareto {
        *on_front.entry(p.3).or_default() += 1;
    }
    let (tmax, emax) = all
        .iter()
        .fold((0.0f64, 0.0f64), |(a, b), p| (a.max(p.1), b.max(p.2)));
    let closeness = |n: &NodeProfile| -> f64 {
        measured_points(n)
            .iter()
            .map(|&(_, t, e)| {
                t / if tmax > 0.0 { tmax } else { 1.0 } + e / if emax > 0.0 { emax } else { 1.0 }
            })
            .fold(f64::INFINITY, f64::min)
    };
    let mut ranked: Vec<(usize, f64, u32)> = ok
        .iter()
        .map(|n| {
            (
                on_front.get(&n.id).copied().unwrap_or(0),
                closeness(n),
                n.id,
            )
        })
        .collect();
    ranked.sort_by(|a, b| b.0.cmp(&a.0).then(a.1.total_cmp(&b.1)).then(a.2.cmp(&b.2)));
    ranked.iter().take(HIGHLIGHTED).map(|r| r.2).collect()
}

pub(crate) fn hit_rate(profile: &Profile) -> HitRate {
    let holdout: BTreeSet<u32> = profile.delta_n_holdout.iter().copied().collect();
    let mut train = Vec::new();
    let mut held = Vec::new();
    let mut max_dn = 0u32;
    for m in profile.nodes.iter().flat_map(|n| &n.measurements) {
        if !(m.hit_rate.is_finite() && m.delta_n >= 1) {
            continue;
        }
        max_dn = max_dn.max(m.delta_n);
        let p = (f64::from(m.delta_n), m.hit_rate.clamp(0.0, 1.0));
        if holdout.contains(&m.delta_n) && !profile.delta_n_train.contains(&m.delta_n) {
            held.push(p);
        } else {
            train.push(p);
        }
    }
    let fit = &profile.hit_rate;
    let mu = if fit.is_usable() {
        fit.mu.filter(|m| m.is_finite())
    } else {
        None
    };
    let fit_text = match (&fit.status, mu) {
        (HitRateStatus::Failed { reason }, _) => format!("fit failed: {reason}"),
        (_, None) => "no fit".to_string(),
        (status, Some(mu)) => {
            let r2 = fit
                .r2
                .filter(|r| r.is_finite())
                .map_or_else(|| "n/a".to_string(), |r| format!("{r:.3}"));
            let clamped = if matches!(status, HitRateStatus::Clamped { .. }) {
                " (clamped)"
            } else {
                ""
            };
            format!("µ = {mu:.3}{clamped}, R² = {r2}")
        }
    };
    HitRate {
        title: format!("Hit rate vs refresh period: γ(Δn) = µ(1 − 1/Δn), {fit_text}"),
        subtitle: format!(
            "{} — {}; {} measurements over {} nodes",
            shader_name(profile),
            setting(profile),
            train.len() + held.len(),
            profile
                .nodes
                .iter()
                .filter(|n| !n.measurements.is_empty())
                .count()
        ),
        train,
        holdout: held,
        mu,
        max_delta_n: f64::from(max_dn.max(DEFAULT_MAX_DELTA_N)),
    }
}
