//! The greedy search for sets of nodes cached together in one payload (the paper leaves caching
//! several nodes open, §6).
//!
//! After the single nodes are replayed and fitted, [`search_sets`] takes the `top` single nodes by
//! predicted saving at the longest training period, forms every pair of them except nested pairs
//! (one node inside the other's expression: the outer one's cache already skips the inner one) and
//! pairs whose payload is wider than [`MAX_PAYLOAD_FLOATS`], ranks the pairs by the frame time
//! `reproj-select`'s `combine` predicts from the members' single-node fits, and replays the best
//! `replays` of them through the same replay and fit code the single nodes use
//! ([`crate::replayer`]'s `Replayer`). The best measured set then grows by one node at a time, up to
//! `max_nodes`, while the set's own fitted models combined with one more node's predict a faster
//! frame and the grown set measures faster. A set slower than the original at the longest period
//! is set aside as a single node is.

use reproj_instance::{InstanceOptions, NodeSelector, Strategy, instance_nodes};
use reproj_models::HitRateFit;
use reproj_models::profile::{Measurement, NodeProfile, NodeStatus, SetPredicted, SetProfile};
use reproj_select::{NodeRecord, predict, predict_set};

use crate::AnalyzeError;
use crate::input::Progress;
pub use crate::options::SetSearchOptions;
use crate::options::period_plan;
use crate::replayer::{Fitted, Replayer, Subject, fit_replays};

/// The most floats one payload holds (an RGBA texture).
pub const MAX_PAYLOAD_FLOATS: u32 = 4;

/// A single node the search may put in a set.
#[derive(Debug, Clone, PartialEq)]
pub struct SetCandidate {
    /// Its fitted models (L2 error).
    pub record: NodeRecord,
    /// Floats of its payload.
    pub components: u32,
    /// Refresh block size k of its measurements.
    pub block: u32,
    /// Ids of the other candidates inside its expression (its subtree).
    pub inside: Vec<u32>,
}

/// What the predictions of [`search_sets`] need: the shared hit-rate model, the original's frame
/// time and the period at which pairs are ranked (the longest training period, replayed first).
#[derive(Debug, Clone, Copy)]
pub struct SetContext<'a> {
    pub hit_rate: &'a HitRateFit,
    pub original_ms: f64,
    pub delta_n: u32,
}

/// Search sets among `candidates` (see the module docs). `measure` replays and fits one set
/// (members in payload order) and returns its profile entry; the search fills in its
/// [`SetProfile::predicted`]. Returns every set measured, in the order replayed; none (and one
/// progress line saying why) when no pair can be formed.
pub fn search_sets(
    candidates: &[SetCandidate],
    ctx: &SetContext,
    opts: &SetSearchOptions,
    measure: &mut dyn FnMut(&[&SetCandidate]) -> Result<SetProfile, AnalyzeError>,
    progress: &dyn Progress,
) -> Result<Vec<SetProfile>, AnalyzeError> {
    // The top nodes by predicted saving (ties: lower id).
    let mut ranked: Vec<(&SetCandidate, f64)> = candidates
        .iter()
        .filter_map(|c| {
            let p = predict(&c.record, ctx.hit_rate, ctx.delta_n)?;
            let saving = ctx.original_ms - p.predicted_ms;
            (saving > 0.0).then_some((c, saving))
        })
        .collect();
    ranked.sort_by(|a, b| b.1.total_cmp(&a.1).then(a.0.record.id.cmp(&b.0.record.id)));
    ranked.truncate(opts.top);
    let top: Vec<&SetCandidate> = ranked.into_iter().map(|(c, _)| c).collect();

    // Pairs, in payload order (the larger saving first), ranked by the combined prediction.
    let (mut nested, mut wide) = (0usize, 0usize);
    let mut pairs: Vec<(Vec<&SetCandidate>, f64)> = Vec::new();
    for (i, a) in top.iter().enumerate() {
        for b in &top[i + 1..] {
            if is_nested(a, b) {
                nested += 1;
            } else if a.components + b.components > MAX_PAYLOAD_FLOATS {
                wide += 1;
            } else if let Some(p) = predict_set(
                &[&a.record, &b.record],
                ctx.hit_rate,
                ctx.original_ms,
                ctx.delta_n,
            ) {
                pairs.push((vec![*a, *b], p.predicted_ms));
            }
        }
    }
    if pairs.is_empty() {
        progress.note(&format!(
            "sets: no pair possible among the top {} nodes by predicted saving ({nested} nested, {wide} wider than {MAX_PAYLOAD_FLOATS} floats)",
            top.len()
        ));
        return Ok(Vec::new());
    }
    pairs.sort_by(|a, b| a.1.total_cmp(&b.1).then_with(|| ids(&a.0).cmp(&ids(&b.0))));
    let chosen = &pairs[..opts.replays.min(pairs.len())];
    progress.note(&format!(
        "sets: {} pairs among the top {} nodes ({nested} nested and {wide} too wide skipped); replaying {}",
        pairs.len(),
        top.len(),
        chosen
            .iter()
            .map(|(m, ms)| format!("{} ({ms:.3} ms predicted at Δn = {})", name(m), ctx.delta_n))
            .collect::<Vec<_>>()
            .join(", ")
    ));

    let mut measured: Vec<SetProfile> = Vec::new();
    for (members, _) in chosen {
        measured.push(run(members, ctx, measure)?);
    }

    // Grow the best measured set while it is predicted to help.
    let Some(mut best) = fastest(&measured, ctx.delta_n).cloned() else {
        progress.note("sets: no pair was usable; no set grows");
        return Ok(measured);
    };
    while best.members.len() < opts.max_nodes {
        let members: Vec<&SetCandidate> = best
            .members
            .iter()
            .filter_map(|id| candidates.iter().find(|c| c.record.id == *id))
            .collect();
        let width: u32 = members.iter().map(|c| c.components).sum();
        let as_node = set_record(&best, &members);
        let Some(now) = predict(&as_node, ctx.hit_rate, ctx.delta_n) else {
            break;
        };
        let next = top
            .iter()
            .filter(|c| !best.members.contains(&c.record.id))
            .filter(|c| width + c.components <= MAX_PAYLOAD_FLOATS)
            .filter(|c| members.iter().all(|m| !is_nested(m, c)))
            .filter_map(|c| {
                let p = predict_set(
                    &[&as_node, &c.record],
                    ctx.hit_rate,
                    ctx.original_ms,
                    ctx.delta_n,
                )?;
                (p.predicted_ms < now.predicted_ms).then_some((*c, p.predicted_ms))
            })
            .min_by(|a, b| a.1.total_cmp(&b.1).then(a.0.record.id.cmp(&b.0.record.id)));
        let Some((c, ms)) = next else {
            progress.note(&format!(
                "sets: {} grows no further: no node that fits its payload is predicted to help",
                best.name()
            ));
            break;
        };
        let mut grown = members.clone();
        grown.push(c);
        progress.note(&format!(
            "sets: growing {} by node {}: {ms:.3} ms predicted at Δn = {} vs {:.3} ms",
            best.name(),
            c.record.id,
            ctx.delta_n,
            now.predicted_ms
        ));
        let set = run(&grown, ctx, measure)?;
        let faster = set.status == NodeStatus::Ok
            && measured_ms(&set, ctx.delta_n) < measured_ms(&best, ctx.delta_n);
        measured.push(set.clone());
        if !faster {
            progress.note(&format!(
                "sets: {} is not measured faster than {}; growth stops",
                set.name(),
                best.name()
            ));
            break;
        }
        best = set;
    }
    Ok(measured)
}

/// Whether one of `a` and `b` is inside the other's expression.
fn is_nested(a: &SetCandidate, b: &SetCandidate) -> bool {
    a.inside.contains(&b.record.id) || b.inside.contains(&a.record.id)
}

fn ids(members: &[&SetCandidate]) -> Vec<u32> {
    members.iter().map(|c| c.record.id).collect()
}

fn name(members: &[&SetCandidate]) -> String {
    ids(members)
        .iter()
        .map(u32::to_string)
        .collect::<Vec<_>>()
        .join("+")
}

/// Measure one set and record the combined prediction at each measured period.
fn run(
    members: &[&SetCandidate],
    ctx: &SetContext,
    measure: &mut dyn FnMut(&[&SetCandidate]) -> Result<SetProfile, AnalyzeError>,
) -> Result<SetProfile, AnalyzeError> {
    let mut set = measure(members)?;
    let records: Vec<&NodeRecord> = members.iter().map(|c| &c.record).collect();
    set.predicted = set
        .measurements
        .iter()
        .map(|m| {
            let p = predict_set(&records, ctx.hit_rate, ctx.original_ms, m.delta_n);
            SetPredicted {
                delta_n: m.delta_n,
                error: p.as_ref().map(|p| p.predicted_error),
                frame_ms: p.map(|p| p.predicted_ms),
            }
        })
        .collect();
    Ok(set)
}

/// The measured frame time of `set` at `delta_n` (infinite when not measured).
fn measured_ms(set: &SetProfile, delta_n: u32) -> f64 {
    set.measurements
        .iter()
        .find(|m| m.delta_n == delta_n)
        .map_or(f64::INFINITY, |m: &Measurement| m.frame_ms)
}

/// The usable set measured fastest at `delta_n` (ties: the first).
fn fastest(sets: &[SetProfile], delta_n: u32) -> Option<&SetProfile> {
    sets.iter()
        .filter(|s| s.status == NodeStatus::Ok && measured_ms(s, delta_n).is_finite())
        .min_by(|a, b| measured_ms(a, delta_n).total_cmp(&measured_ms(b, delta_n)))
}

/// A measured set as one node of the selector: its own fits.
fn set_record(set: &SetProfile, members: &[&SetCandidate]) -> NodeRecord {
    NodeRecord {
        id: set.members.first().copied().unwrap_or(0),
        text: set.texts.join(" + "),
        strategy: set.strategy.clone(),
        error: set.error_fit.clone(),
        timing: set.timing_fit.clone(),
        mean_pixels: members.first().map_or(0.0, |c| c.record.mean_pixels),
        measured: None,
        measured_errors: Vec::new(),
    }
}

/// `analyze`'s set phase: the usable single nodes as candidates ([`set_candidates`]), each set
/// instanced in its first member's strategy and block and replayed at the longest training
/// period and then the single nodes' periods ([`measure_set`]).
pub(crate) fn analyze_sets(
    rp: &mut Replayer,
    nodes: &[NodeProfile],
    hit_rate: &HitRateFit,
    mean_pixels: f64,
    opts: &SetSearchOptions,
) -> Result<Vec<SetProfile>, AnalyzeError> {
    let candidates = set_candidates(rp, nodes, mean_pixels);
    let ctx = SetContext {
        hit_rate,
        original_ms: rp.original_ms,
        delta_n: rp.longest,
    };
    let progress = rp.progress;
    let plan: Vec<(u32, bool)> = std::iter::once((rp.longest, false))
        .chain(period_plan(rp.opts, rp.longest))
        .collect();
    let fits = SetFits {
        hit_rate,
        mean_pixels,
    };
    let mut measure = |members: &[&SetCandidate]| measure_set(rp, members, &plan, &fits);
    search_sets(&candidates, &ctx, opts, &mut measure, progress)
}

/// The usable single nodes (fitted, not the root) as set candidates: their records, payload
/// components and block, and the other candidates inside their subtrees.
fn set_candidates(rp: &Replayer, nodes: &[NodeProfile], mean_pixels: f64) -> Vec<SetCandidate> {
    let input = rp.input;
    let fun = input.norm.function();
    let usable: Vec<(&NodeProfile, &reproj_front::Node)> = nodes
        .iter()
        .filter(|n| n.status == NodeStatus::Ok && !n.root)
        .filter_map(|n| Some((n, input.table.get(n.id)?)))
        .filter(|(_, t)| t.handle.is_some())
        .collect();
    usable
        .iter()
        .map(|(n, t)| {
            let sub = reproj_front::nodes::subtree(fun, t.handle.expect("filtered"));
            SetCandidate {
                record: NodeRecord {
                    id: n.id,
                    text: n.text.clone(),
                    strategy: n.strategy.clone(),
                    error: n.error_fit.clone(),
                    timing: n.timing_fit.clone(),
                    mean_pixels,
                    measured: None,
                    measured_errors: Vec::new(),
                },
                components: t.components,
                block: n.block.unwrap_or(rp.opts.block.unwrap_or(8)),
                inside: usable
                    .iter()
                    .filter(|(o, ot)| o.id != n.id && ot.handle.is_some_and(|h| sub.contains(&h)))
                    .map(|(o, _)| o.id)
                    .collect(),
            }
        })
        .collect()
}

/// What a set's fits need of the analysis: the session's hit-rate model and the original's
/// mean shaded pixels.
struct SetFits<'a> {
    hit_rate: &'a HitRateFit,
    mean_pixels: f64,
}

/// One set instanced in one payload, replayed over `plan` and fitted (a note when its fits set
/// it aside).
fn measure_set(
    rp: &mut Replayer,
    members: &[&SetCandidate],
    plan: &[(u32, bool)],
    fits: &SetFits,
) -> Result<SetProfile, AnalyzeError> {
    let (input, progress) = (rp.input, rp.progress);
    let (hit_rate, mean_pixels) = (fits.hit_rate, fits.mean_pixels);
    let first = members[0];
    let strategy: Strategy = first.record.strategy.parse().unwrap_or(Strategy::ThreePass);
    let block = first.block;
    let ids: Vec<u32> = members.iter().map(|c| c.record.id).collect();
    let who = format!("set {}", name(members));
    let texts: Vec<String> = members.iter().map(|c| c.record.text.clone()).collect();
    progress.extend(plan.len() as u64);
    let t = std::time::Instant::now();
    let variant = instance_nodes(
        input.shader,
        input.norm,
        input.table,
        &ids.iter()
            .map(|&id| NodeSelector::Id(id))
            .collect::<Vec<_>>(),
        &InstanceOptions {
            strategy,
            block,
            ..rp.opts.instance
        },
    );
    rp.time.instancing_s += t.elapsed().as_secs_f64();
    let mut measurements = Vec::new();
    let mut failure = None;
    match variant {
        Err(e) => {
            progress.note(&format!("{who}: cannot instance: {e}"));
            failure = Some(format!("cannot instance: {e}"));
            for &(dn, _) in plan {
                progress.step(&format!("{who} Δn={dn}"));
            }
        }
        Ok(variant) => {
            let sources: Vec<String> = variant.passes.iter().map(|p| p.wgsl.clone()).collect();
            let subject = Subject {
                node: ids[0],
                set: ids.clone(),
                who: who.clone(),
                text: texts.join(" + "),
                root: false,
                strategy,
                block,
                reconstruct: None,
                raced: false,
                verdict: None,
            };
            rp.replay_plan(
                &subject,
                &sources,
                &variant,
                plan,
                &mut measurements,
                &mut failure,
            )?;
        }
    }
    let Fitted {
        error_fit,
        flip_fit,
        dssim_fit,
        timing_fit,
        holdout,
        status,
    } = fit_replays(
        &measurements,
        failure.as_deref(),
        rp.opts,
        hit_rate,
        mean_pixels,
    );
    if let (NodeStatus::SetAside { reason }, None) = (&status, &failure) {
        progress.note(&format!("{who}: set aside: {reason}"));
    }
    Ok(SetProfile {
        members: ids,
        texts,
        strategy: strategy.name().into(),
        block,
        measurements,
        predicted: Vec::new(),
        error_fit,
        flip_fit,
        dssim_fit,
        timing_fit,
        holdout,
        status,
    })
}

#[cfg(test)]
mod tests;
