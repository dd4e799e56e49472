//! The selector's choice for every budget of the slider, precomputed: `select_with_sets` (as `reproj
//! emit` runs it, on the records `emit` builds: nodes and measured sets) at log-spaced budgets over
//! the profile's error range and at every candidate's predicted error. The choice only changes
//! where the budget crosses a candidate's predicted error, so "the entry with the largest budget ≤
//! b" is exactly the selector at b for any b in the range.

use reproj_models::Profile;
use reproj_select::{
    Budget, Choice, DEFAULT_MAX_DELTA_N, DEFAULT_MIN_DELTA_N, NodeRecord, SelectOptions, Selection,
    SetRecord, candidates, select_with_sets,
};
use serde::Serialize;

/// Log-spaced budgets over the range, beside the thresholds.
pub const GRID: usize = 64;

/// One budget and what the selector does there.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct BudgetEntry {
    pub budget: f64,
    /// Index into [`Budgets::choices`]; `None`: the original shader is kept.
    pub choice: Option<usize>,
    /// Why the original is kept.
    pub reason: Option<String>,
}

/// Every budget of the slider and the distinct choices among them.
#[derive(Debug, Clone, PartialEq)]
pub struct Budgets {
    /// `[lowest, highest]` budget of the slider (log scale).
    pub range: [f64; 2],
    /// By increasing budget.
    pub entries: Vec<BudgetEntry>,
    /// The distinct (node or set, strategy, Δn) choices, in order of first appearance (lowest
    /// budget).
    pub choices: Vec<Choice>,
    /// The lowest budget that selects each choice.
    pub first_budget: Vec<f64>,
}

/// The selector's records: the profile's usable nodes and sets, as `reproj emit` builds them
/// (`reproj_emit::selector_records`).
#[derive(Debug, Clone)]
pub struct Records {
    pub nodes: Vec<NodeRecord>,
    pub sets: Vec<SetRecord>,
}

impl Records {
    /// Every (node or set, Δn) the selector weighs, as points (a set as its first member).
    fn candidates(&self, profile: &Profile) -> Vec<reproj_select::Prediction> {
        let sets: Vec<NodeRecord> = self.sets.iter().map(SetRecord::as_node).collect();
        [&self.nodes[..], &sets[..]]
            .into_iter()
            .flat_map(|r| {
                candidates(
                    r,
                    &profile.hit_rate,
                    DEFAULT_MIN_DELTA_N,
                    DEFAULT_MAX_DELTA_N,
                )
            })
            .collect()
    }
}

/// The selection at `budget` (emit's defaults: Δn in [`reproj_select::DELTA_N_RANGE`]).
pub fn select_at(profile: &Profile, records: &Records, budget: Budget) -> Selection {
    select_with_sets(
        &records.nodes,
        &records.sets,
        &profile.hit_rate,
        profile.original.frame_ms,
        &SelectOptions::new(budget),
    )
}

/// The same choice: the same node or set, strategy and Δn.
pub fn same_choice(a: &Choice, b: &Choice) -> bool {
    (a.node_id, &a.members, &a.strategy, a.delta_n)
        == (b.node_id, &b.members, &b.strategy, b.delta_n)
}

/// What the page calls a choice: `node 680`, `set 680+697`.
pub fn label(c: &Choice) -> String {
    if c.members.is_empty() {
        format!("node {}", c.node_id)
    } else {
        let ids: Vec<String> = c.members.iter().map(u32::to_string).collect();
        format!("set {}", ids.join("+"))
    }
}

/// The slider's range: from half the lowest positive predicted (or measured) error to twice the
/// highest; `[1e-4, 0.1]` when the profile has none.
pub fn range(profile: &Profile, records: &Records) -> [f64; 2] {
    let predicted = records
        .candidates(profile)
        .into_iter()
        .map(|p| p.predicted_error);
    let measured = profile
        .nodes
        .iter()
        .flat_map(|n| n.measurements.iter().map(|m| m.error));
    let (lo, hi) = predicted
        .chain(measured)
        .filter(|e| e.is_finite() && *e > 0.0)
        .fold((f64::INFINITY, 0.0f64), |(a, b), e| (a.min(e), b.max(e)));
    if lo.is_finite() && hi > 0.0 {
        [lo / 2.0, (hi * 2.0).max(lo)]
    } else {
        [1e-4, 0.1]
    }
}

/// The choices at [`GRID`] log-spaced budgets over [`range`] and at every candidate's predicted
/// error inside it.
pub fn budgets(profile: &Profile, records: &Records) -> Budgets {
    let [lo, hi] = range(profile, records);
    let mut at: Vec<f64> = (0..GRID)
        .map(|i| lo * (hi / lo).powf(i as f64 / (GRID - 1) as f64))
        .collect();
    at.extend(
        records
            .candidates(profile)
            .into_iter()
            .map(|p| p.predicted_error)
            .filter(|e| (lo..=hi).contains(e)),
    );
    at.sort_by(f64::total_cmp);
    at.dedup();
    let mut choices: Vec<Choice> = Vec::new();
    let mut first_budget = Vec::new();
    let entries = at
        .into_iter()
        .map(|budget| {
            // The range is finite and positive, and so is every point of it.
            Budget::new(budget).expect("the slider's budgets lie in a finite, positive range")
        })
        .map(|b| (b.get(), select_at(profile, records, b)))
        .map(|(budget, selection)| match selection {
            Selection::Node(c) => {
                let i = choices
                    .iter()
                    .position(|k| same_choice(k, &c))
                    .unwrap_or_else(|| {
                        choices.push(c.clone());
                        first_budget.push(budget);
                        choices.len() - 1
                    });
                BudgetEntry {
                    budget,
                    choice: Some(i),
                    reason: None,
                }
            }
            Selection::Original { reason } => BudgetEntry {
                budget,
                choice: None,
                reason: Some(reason.to_string()),
            },
        })
        .collect();
    Budgets {
        range: [lo, hi],
        entries,
        choices,
        first_budget,
    }
}

impl Budgets {
    /// The entry the page shows at `budget`: the one with the largest budget ≤ it (the lowest
    /// entry below the range). The page's script does the same.
    pub fn lookup(&self, budget: f64) -> Option<&BudgetEntry> {
        let i = self.entries.partition_point(|e| e.budget <= budget);
        self.entries.get(i.saturating_sub(1))
    }
}
