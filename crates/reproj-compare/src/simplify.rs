//! Greedy code simplification (Pellacini 2005, as the paper's § 5.4 used it): replace the node
//! whose removal costs the least error per saved time by a constant — its mean over the covered
//! pixels of the session — and repeat on the simplified shader until it is fast enough.
//!
//! Each step renders, for each of `candidates` live nodes, the shader with that node also
//! replaced, and measures its error; then times them all against the original in one interleaved
//! run (`reproj-bench`). The candidates are those with the largest
//! static saving (cost not shared with the rest of the shader, `docs/COST.md`) and half as many
//! more whose saving is nearest the saving still needed for the target (`cost × (1 − 1/target)`
//! less what the steps so far saved), so the search can take a small step when a small one is
//! enough instead of only jumping to the largest subtrees. When some candidates reach the target speedup as measured, the
//! one with the least error among them is removed and the search ends there; otherwise the node
//! with the least `error / saving` is removed (ties: the larger saving, then the lower id) — the
//! saving being the static estimate, as measured times on a shared machine are too noisy to rank
//! candidates by. The search also ends after `max_steps`, or when no candidate is left. A node's mean comes
//! from one render of its probe ([`reproj_instance::probe`]) and is kept across steps.

use std::collections::{BTreeMap, HashSet};

use reproj_front::{Loaded, Node, NodeTable};
use reproj_instance::{Replacement, probe, simplify as simplified_shader};
use serde::{Deserialize, Serialize};

use crate::{CompareError, Ctx, MethodResult};

/// Options of the greedy search.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SimplifyOptions {
    /// Nodes with the largest static saving tried per step (half as many more are tried among
    /// those nearest the saving still needed).
    pub candidates: usize,
    /// Most nodes removed.
    pub max_steps: usize,
}

impl Default for SimplifyOptions {
    fn default() -> Self {
        SimplifyOptions {
            candidates: 6,
            max_steps: 8,
        }
    }
}

/// One removed node.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SimplifyStep {
    pub node: u32,
    pub text: String,
    pub line: u32,
    /// The constant it was replaced by (its first `components` values).
    pub value: Vec<f32>,
    /// Static saving (cost units of `docs/COST.md`).
    pub saving: f64,
    /// Mean per-pixel L2 error of the shader after this step.
    pub error: f64,
    /// Frame time (median block, ms) and speedup of the shader after this step, timed against
    /// the original interleaved with the step's other candidates.
    pub frame_ms: f64,
    pub speedup: f64,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub speedup_ci95: Option<[f64; 2]>,
    /// The other candidates of this step: node id and error.
    pub rejected: Vec<(u32, f64)>,
}

/// The greedy search.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SimplifyDetail {
    pub candidates: usize,
    pub steps: Vec<SimplifyStep>,
}

/// The result of [`simplify`].
#[derive(Debug, Clone)]
pub(crate) struct Simplification {
    pub(crate) detail: SimplifyDetail,
    pub(crate) result: MethodResult,
    pub(crate) frames: Vec<Vec<f32>>,
    pub(crate) wgsl: String,
}

/// Run the greedy search (see the module docs).
pub(crate) fn simplify(
    ctx: &Ctx,
    loaded: &Loaded,
    opts: &SimplifyOptions,
) -> Result<Simplification, CompareError> {
    let table = &loaded.table;
    let replaceable: Vec<&Node> = table
        .cacheable()
        .filter(|n| !n.root && (1..=4).contains(&n.components))
        .filter(|n| probe(&loaded.norm, table, n.id).is_ok())
        .collect();
    if replaceable.is_empty() {
        return Err(CompareError::NothingToSimplify {
            shader: table.shader.clone(),
        });
    }
    let total = table.root().cost;
    let mut search = Search::default();
    for _ in 0..opts.max_steps.max(1) {
        let mut pool: Vec<&Node> = replaceable
            .iter()
            .copied()
            .filter(|n| !search.removed.iter().any(|r| r.node == n.id))
            .filter(|n| !n.handle.is_some_and(|h| search.dead.contains(&h)))
            .collect();
        pool.retain(|n| saving(n) > 0.0);
        let saved: f64 = search.steps.iter().map(|s| s.saving).sum();
        let needed = (total * (1.0 - 1.0 / ctx.target) - saved).max(0.0);
        let pool = candidate_pool(pool, needed, opts.candidates.max(1));
        if pool.is_empty() {
            break;
        }
        let mut tried = render_candidates(ctx, loaded, pool, &mut search)?;
        time_candidates(ctx, &mut tried)?;
        let speedup = search.take_best(tried, ctx.target, loaded.norm.function());
        if speedup >= ctx.target {
            break;
        }
    }
    finish(ctx, search, opts, table)
}

/// The greedy search's state: the session means computed so far, the nodes replaced, the
/// expressions that died with them, the steps, and the last step's WGSL, frame time, speedup and
/// interval.
#[derive(Default)]
struct Search {
    means: BTreeMap<u32, [f32; 4]>,
    removed: Vec<Replacement>,
    dead: HashSet<naga::Handle<naga::Expression>>,
    steps: Vec<SimplifyStep>,
    last: Option<(String, f64, f64, Option<[f64; 2]>)>,
}

impl Search {
    /// Keep the step's best candidate (the least error among those reaching the target, else
    /// the fastest: [`pick`]) and record the step; its speedup.
    fn take_best(&mut self, mut tried: Vec<Tried>, target: f64, fun: &naga::Function) -> f64 {
        let best = pick(&tried, |t| t.speedup >= target);
        let chosen = tried.swap_remove(best);
        let rejected = tried.iter().map(|t| (t.node.id, t.error)).collect();
        let speedup = chosen.speedup;
        let node = chosen.node;
        if let Some(h) = node.handle {
            self.dead.extend(reproj_front::nodes::subtree(fun, h));
        }
        self.removed.push(Replacement {
            node: node.id,
            value: chosen.value,
        });
        self.steps.push(SimplifyStep {
            node: node.id,
            text: node.text.clone(),
            line: node.line,
            value: chosen.value[..node.components as usize].to_vec(),
            saving: saving(node),
            error: chosen.error,
            frame_ms: chosen.frame_ms,
            speedup,
            speedup_ci95: chosen.ci95,
            rejected,
        });
        self.last = Some((chosen.wgsl, chosen.frame_ms, speedup, chosen.ci95));
        speedup
    }
}

/// Each candidate of a step with its node replaced (beside the nodes replaced before) by its
/// session mean, rendered and scored.
fn render_candidates<'n>(
    ctx: &Ctx,
    loaded: &Loaded,
    pool: Vec<&'n Node>,
    search: &mut Search,
) -> Result<Vec<Tried<'n>>, CompareError> {
    let mut tried: Vec<Tried> = Vec::new();
    for node in pool {
        let value = match search.means.get(&node.id) {
            Some(v) => *v,
            None => {
                let v = node_mean(ctx, loaded, node)?;
                search.means.insert(node.id, v);
                v
            }
        };
        let mut replace = search.removed.clone();
        replace.push(Replacement {
            node: node.id,
            value,
        });
        let s = simplified_shader(
            &loaded.norm,
            &loaded.table,
            &reproj_instance::SimplifyOptions {
                replace: replace.clone(),
            },
        )?;
        let (error, shader) = ctx.error_of_wgsl("simplified.wgsl", &s.wgsl)?;
        ctx.progress
            .step(&format!("simplify: node {} error {error:.5}", node.id));
        tried.push(Tried {
            node,
            value,
            error,
            frame_ms: 0.0,
            speedup: 0.0,
            ci95: None,
            wgsl: s.wgsl,
            shader: Some(shader),
        });
    }
    Ok(tried)
}

/// The step's candidates against the original, interleaved in one run.
fn time_candidates(ctx: &Ctx, tried: &mut [Tried]) -> Result<(), CompareError> {
    let candidates: Vec<reproj_bench::Candidate> = tried
        .iter_mut()
        .map(|t| {
            let shader = t.shader.take().expect("rendered above");
            Ctx::shader_candidate(&format!("node {}", t.node.id), shader, 0, None)
        })
        .collect();
    for (t, e) in tried.iter_mut().zip(ctx.race(&candidates)?) {
        if let Some(e) = e {
            t.frame_ms = e.candidate_ms;
            t.speedup = e.speedup;
            t.ci95 = Some(e.ci95);
        }
    }
    Ok(())
}

/// The last step's shader, rendered again for its frames (the steps kept only their errors:
/// the crops and ꟻLIP need them), scored, as the method's result.
fn finish(
    ctx: &Ctx,
    search: Search,
    opts: &SimplifyOptions,
    table: &NodeTable,
) -> Result<Simplification, CompareError> {
    let steps = search.steps;
    let (wgsl, frame_ms, speedup, ci95) =
        search.last.ok_or_else(|| CompareError::NothingToSimplify {
            shader: table.shader.clone(),
        })?;
    let (frames, _) = ctx.render_wgsl("simplified.wgsl", &wgsl)?;
    let scores = ctx.score(&frames, true)?;
    let result = MethodResult {
        speedup_ci95: ci95,
        method: "simplify".into(),
        frame_ms,
        speedup,
        reached_target: speedup >= ctx.target,
        scores,
        setting: format!(
            "{} node(s) replaced by their session mean: {}",
            steps.len(),
            steps
                .iter()
                .map(|s| s.node.to_string())
                .collect::<Vec<_>>()
                .join(", ")
        ),
    };
    Ok(Simplification {
        detail: SimplifyDetail {
            candidates: opts.candidates,
            steps,
        },
        result,
        frames,
        wgsl,
    })
}

/// One candidate of a step, rendered, then timed with the step's other candidates.
struct Tried<'a> {
    node: &'a Node,
    value: [f32; 4],
    error: f64,
    /// Median block time and speedup in the step's interleaved run (0 without a figure).
    frame_ms: f64,
    speedup: f64,
    ci95: Option<[f64; 2]>,
    wgsl: String,
    /// The parsed shader, until it is handed to the race.
    shader: Option<reproj_front::Shader>,
}

/// The candidate to remove: the least error among those that `reach` the target, else the least
/// error per saved cost; ties: larger saving, then lower id.
fn pick(tried: &[Tried], reach: impl Fn(&Tried) -> bool) -> usize {
    let reaching = tried.iter().any(&reach);
    let key = |t: &Tried| {
        let per = if reaching {
            t.error
        } else {
            t.error / saving(t.node)
        };
        (!reach(t) && reaching, per, saving(t.node), t.node.id)
    };
    (0..tried.len())
        .min_by(|&a, &b| {
            let (ka, kb) = (key(&tried[a]), key(&tried[b]));
            ka.0.cmp(&kb.0)
                .then(ka.1.total_cmp(&kb.1))
                .then(kb.2.total_cmp(&ka.2))
                .then(ka.3.cmp(&kb.3))
        })
        .expect("at least one candidate")
}

/// Candidates from `pool`: the `n` with the largest saving, then `n / 2` more (rounded up) with
/// the saving nearest `needed` (each in order, no node twice).
fn candidate_pool(mut pool: Vec<&Node>, needed: f64, n: usize) -> Vec<&Node> {
    pool.sort_by(|a, b| saving(b).total_cmp(&saving(a)).then(a.id.cmp(&b.id)));
    let mut chosen: Vec<&Node> = pool.iter().copied().take(n).collect();
    let n = n + n.div_ceil(2);
    let mut near = pool.clone();
    near.sort_by(|a, b| {
        (saving(a) - needed)
            .abs()
            .total_cmp(&(saving(b) - needed).abs())
            .then(a.id.cmp(&b.id))
    });
    for node in near {
        if chosen.len() >= n {
            break;
        }
        if !chosen.iter().any(|c| c.id == node.id) {
            chosen.push(node);
        }
    }
    chosen
}

/// Static saving of replacing `node`: its cost not shared with the rest of the shader.
pub fn saving(node: &Node) -> f64 {
    (node.cost - node.overlap).max(0.0)
}

/// The node's mean over the covered pixels of every rendered frame, from one render of its probe.
fn node_mean(ctx: &Ctx, loaded: &Loaded, node: &Node) -> Result<[f32; 4], CompareError> {
    let p = probe(&loaded.norm, &loaded.table, node.id)?;
    let (frames, _) = ctx.render_wgsl(&format!("probe_node_{}.wgsl", node.id), &p.wgsl)?;
    let mut sum = [0.0f64; 4];
    let mut n = 0u64;
    for (f, frame) in frames.iter().enumerate() {
        for (px, &depth) in frame.chunks_exact(4).zip(&ctx.reference.depth[f]) {
            if depth < 1.0 {
                for c in 0..4 {
                    sum[c] += f64::from(px[c]);
                }
                n += 1;
            }
        }
    }
    let n = n.max(1) as f64;
    Ok(sum.map(|s| (s / n) as f32))
}

#[cfg(test)]
mod tests {
    use super::*;
    use reproj_front::{LoadOptions, load};

    fn loaded() -> Loaded {
        let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("tests/data/flat_and_stripes.wgsl");
        load(&path, None, &LoadOptions::default()).unwrap()
    }

    fn tried<'a>(node: &'a Node, error: f64, frame_ms: f64) -> Tried<'a> {
        Tried {
            node,
            value: [0.0; 4],
            error,
            frame_ms,
            speedup: 0.0,
            ci95: None,
            wgsl: String::new(),
            shader: None,
        }
    }

    #[test]
    fn the_pool_mixes_the_largest_savings_with_those_nearest_the_need() {
        let l = loaded();
        let mut nodes: Vec<&Node> = l.table.cacheable().filter(|n| saving(n) > 0.0).collect();
        assert!(nodes.len() >= 4, "{}", nodes.len());
        nodes.sort_by(|a, b| saving(a).total_cmp(&saving(b)).then(a.id.cmp(&b.id)));
        let smallest = nodes[0];
        let largest = nodes[nodes.len() - 1];
        let pool = candidate_pool(nodes.clone(), saving(smallest), 1);
        let ids: Vec<u32> = pool.iter().map(|n| n.id).collect();
        assert_eq!(pool.len(), 2);
        assert_eq!(saving(pool[0]), saving(largest), "{ids:?}");
        assert!(
            pool.iter().any(|n| saving(n) == saving(smallest)),
            "a node as small as the need: {ids:?}"
        );
        // No node twice, and never more than asked.
        let pool = candidate_pool(nodes.clone(), saving(largest), nodes.len() + 3);
        assert_eq!(pool.len(), nodes.len());
        // n largest, then n / 2 near the need: 2 + 1.
        assert_eq!(candidate_pool(nodes.clone(), saving(smallest), 2).len(), 3);
    }

    #[test]
    fn a_candidate_reaching_the_target_wins_by_error_alone() {
        let l = loaded();
        let mut nodes: Vec<&Node> = l.table.cacheable().filter(|n| saving(n) > 0.0).collect();
        nodes.sort_by(|a, b| saving(a).total_cmp(&saving(b)));
        let (small, big) = (nodes[0], nodes[nodes.len() - 1]);
        assert!(saving(big) > saving(small));
        // Slow: the least error per saving wins, the big node here.
        let t = [tried(small, 0.010, 9.0), tried(big, 0.012, 8.0)];
        let slow = |t: &Tried| t.frame_ms < 1.0;
        assert_eq!(t[pick(&t, slow)].node.id, big.id);
        // Both reach the target: the lower error wins whatever it saves.
        let fast = |_: &Tried| true;
        assert_eq!(t[pick(&t, fast)].node.id, small.id);
        // Only the big one reaches it: it wins even with more error.
        let big_only = |t: &Tried| t.node.id == big.id;
        assert_eq!(t[pick(&t, big_only)].node.id, big.id);
    }
}
