//! The runoff of `emit --verify`: the nodes whose predicted speed cannot be told from the choice's
//! are timed together, interleaved with the original, and the fastest measured is written.
//!
//! Why: a node's predicted speedup is its timing model scaled to one short race of `analyze`
//! (8 rounds, intervals of ±15–20 % on a CPU rasterizer), so two nodes a few per cent apart in
//! prediction are a coin toss — marble at budget 0.1 predicted node 697 at 2.63× and measured
//! 2.38×, while node 680 at Δn 50 measured 2.62×. This module is the GPU-free half: who races
//! ([`contenders`]) and what the report keeps ([`Runoff`]); reproj-analyze's `runoff` times them.

use std::path::Path;

use reproj_instance::Variant;
use reproj_models::Profile;
use reproj_select::{Choice, Selection};
use serde::{Deserialize, Serialize};

use crate::EmitError;
use crate::motion::PeriodChoice;
use crate::spec::{Profiled, VariantSpec};
use crate::{
    EmitOptions, EmitReport, NodeChoice, choose, gather, load_profiled, records_of, select_options,
};

/// One node's own best choice under the budget, in memory, ready to be timed.
#[derive(Debug, Clone)]
pub struct Contender {
    /// The node as the report names it: its id, or `root`.
    pub node: String,
    /// How `emit --node` selects it.
    pub choice: NodeChoice,
    /// What the selector predicts for it (its fastest Δn under the budget).
    pub selection: Choice,
    /// Whether it is what `emit` chose.
    pub chosen_by_prediction: bool,
    /// Its passes and manifest at that Δn.
    pub variant: Variant,
}

impl Contender {
    /// `opts` restricted to this contender (`--node` and `--strategy`): what [`crate::emit`]
    /// writes when the runoff chooses it.
    pub fn emit_options(&self, opts: &EmitOptions) -> EmitOptions {
        EmitOptions {
            node: Some(self.choice),
            strategy: Some(self.variant.manifest.strategy),
            ..opts.clone()
        }
    }
}

/// What the runoff measured (`report.json` `runoff`, report version 6).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Runoff {
    /// Rounds of the one interleaved run that timed every contender.
    pub rounds: u32,
    /// The contenders, in order of predicted speedup.
    pub entries: Vec<RunoffEntry>,
    /// Whether the written choice differs from the prediction's.
    pub changed: bool,
}

/// One contender of the runoff.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct RunoffEntry {
    pub node: String,
    pub strategy: String,
    pub delta_n: u32,
    pub predicted_error: f64,
    pub predicted_speedup: f64,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub predicted_speedup_ci95: Option<[f64; 2]>,
    /// Original time over the contender's, from the interleaved run (`None`: no usable frame).
    pub measured_speedup: Option<f64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub measured_speedup_ci95: Option<[f64; 2]>,
    /// The one the prediction chose.
    pub predicted_choice: bool,
    /// The one written.
    pub written: bool,
}

/// How far below the choice's predicted speedup a node's own best may lie and still race it,
/// where neither has a measured interval: 10 %.
const CLOSE_WITHOUT_INTERVALS: f64 = 0.9;

/// The contenders of a runoff for `report` (what [`crate::emit`] chose under `opts`): the choice
/// itself and every other node whose own best choice under the budget is predicted too close to
/// tell apart — its predicted interval reaches the choice's (within 10 % of it where there are no
/// intervals) — at most `max` of them, the fastest predicted first. Empty (no runoff) when fewer
/// than two qualify, `max` < 2, the choice is the original or a set, a node was forced
/// (`--node`), or the period is adaptive.
pub fn contenders(
    profile: &Profile,
    profile_path: &Path,
    opts: &EmitOptions,
    report: &EmitReport,
    max: usize,
) -> Result<Vec<Contender>, EmitError> {
    let (Some(current), Some(best), Some(current_strategy)) = (
        report.node.as_deref(),
        report.predicted_speedup,
        report.strategy.as_deref(),
    ) else {
        return Ok(Vec::new());
    };
    if max < 2
        || opts.node.is_some()
        || opts.period == PeriodChoice::Adaptive
        || current.contains('+')
    {
        return Ok(Vec::new());
    }
    let best_lo = report
        .predicted_speedup_ci95
        .map_or(best * CLOSE_WITHOUT_INTERVALS, |[lo, _]| lo);
    let (records, _) = records_of(profile, profile_path, opts)?;
    let mut ids: Vec<u32> = records.iter().map(|r| r.id).collect();
    ids.sort_unstable();
    ids.dedup();
    let select_opts = select_options(opts);
    let mut found: Vec<(Choice, bool)> = Vec::new();
    for id in ids {
        let node_opts = EmitOptions {
            node: Some(NodeChoice::Id(id)),
            ..opts.clone()
        };
        let all = gather(profile, profile_path, &node_opts)?;
        let names: Vec<String> = all.iter().map(|(p, _, _)| p.session.path.clone()).collect();
        let Selection::Node(choice) = choose(&all, &names, &node_opts, &select_opts).selection
        else {
            continue;
        };
        if !choice.members.is_empty() {
            continue;
        }
        let name = node_name(profile, choice.node_id);
        let is_current = name == current && choice.strategy == current_strategy;
        let hi = choice
            .predicted_speedup_ci95
            .map_or(choice.predicted_speedup, |[_, hi]| hi);
        if is_current || hi >= best_lo {
            found.push((choice, is_current));
        }
    }
    found.sort_by(|a, b| b.0.predicted_speedup.total_cmp(&a.0.predicted_speedup));
    // The choice always races; the others by predicted speed, up to `max` in all.
    let mut kept: Vec<(Choice, bool)> = Vec::new();
    let mut others = 0;
    for (c, is_current) in found {
        if is_current || others + 1 < max {
            others += usize::from(!is_current);
            kept.push((c, is_current));
        }
    }
    if kept.len() < 2 || !kept.iter().any(|(_, cur)| *cur) {
        return Ok(Vec::new());
    }
    let (_, loaded, shader) = load_profiled(profile, profile_path, opts.shader.as_deref())?;
    kept.into_iter()
        .map(|(selection, chosen_by_prediction)| {
            let node = profile
                .nodes
                .iter()
                .find(|n| n.id == selection.node_id && n.strategy == selection.strategy)
                .expect("the selection comes from the profile's nodes");
            let spec = VariantSpec::of(
                profile,
                profile_path,
                Profiled::Node(node),
                selection.delta_n,
            )?
            .in_format(opts.cache_format);
            let variant = spec.instance(&shader, &loaded, &opts.integration)?;
            Ok(Contender {
                node: node_name(profile, node.id),
                choice: if node.root {
                    NodeChoice::Root
                } else {
                    NodeChoice::Id(node.id)
                },
                selection,
                chosen_by_prediction,
                variant,
            })
        })
        .collect()
}

/// A node as the report names it: `root`, or its id.
fn node_name(profile: &Profile, id: u32) -> String {
    if profile.nodes.iter().any(|n| n.id == id && n.root) {
        "root".into()
    } else {
        id.to_string()
    }
}
