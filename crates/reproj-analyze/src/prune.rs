//! Choosing which cacheable nodes to profile.
//!
//! The paper profiled every cacheable node (1.5 to 9.5 hours per shader) and listed pruning as
//! future work. A node can only pay off by what it saves: its cost minus its overlap (the part the
//! rest of the shader still computes). reproj profiles the root (the whole-pixel cache), drops nodes
//! that would save less than `min_saving` of the shader's cost, merges nodes whose savings are
//! nearly equal (a node and its cheap parent, `n` and `abs(n)`), and keeps up to `max_nodes` spread
//! evenly over the range of savings, so that cheap, accurate nodes and expensive, lossy ones are
//! both measured.

use reproj_front::{Node, NodeTable};

/// Options of [`profile_candidates`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PruneOptions {
    /// Most nodes to profile (the root included). `usize::MAX`: no cap.
    pub max_nodes: usize,
    /// Smallest static saving (cost − overlap) worth profiling, as a fraction of the shader's cost.
    pub min_saving: f64,
    /// Nodes whose savings differ by less than this fraction of the shader's cost are one choice.
    pub merge_within: f64,
}

impl Default for PruneOptions {
    fn default() -> Self {
        PruneOptions {
            max_nodes: 16,
            min_saving: 0.05,
            merge_within: 0.01,
        }
    }
}

/// The ids of the nodes to profile, in id order. The root is always first in importance and is
/// always included.
pub fn profile_candidates(table: &NodeTable, opts: &PruneOptions) -> Vec<u32> {
    let total = table.total_cost.max(1e-9);
    let root = table.root();
    let mut pool: Vec<&Node> = table
        .cacheable()
        .filter(|n| !n.root && n.saving() >= opts.min_saving * total)
        .collect();
    // Among nodes that save about the same, keep the cheapest one: it is the furthest upstream, so
    // more of what follows it stays fresh and its error is lower (the turbulence sum rather than the
    // lit color computed from it). Cheapest first, then merge; ties by id for determinism.
    pool.sort_by(|a, b| a.cost.total_cmp(&b.cost).then(a.id.cmp(&b.id)));
    let mut merged: Vec<&Node> = Vec::new();
    for n in pool {
        let near = merged
            .iter()
            .any(|m| (m.saving() - n.saving()).abs() < opts.merge_within * total);
        // A node saving as much as the whole shader is the root again.
        let near_root = (root.saving() - n.saving()).abs() < opts.merge_within * total;
        if !near && !near_root {
            merged.push(n);
        }
    }
    // Highest saving first for the spread below.
    merged.sort_by(|a, b| b.saving().total_cmp(&a.saving()).then(a.id.cmp(&b.id)));
    let room = opts.max_nodes.saturating_sub(1);
    let chosen: Vec<&Node> = if merged.len() <= room {
        merged
    } else if room == 0 {
        Vec::new()
    } else if room == 1 {
        vec![merged[0]]
    } else {
        // Evenly spaced ranks from the highest to the lowest saving.
        let last = merged.len() - 1;
        let mut idx: Vec<usize> = (0..room)
            .map(|i| (i * last + (room - 1) / 2) / (room - 1))
            .collect();
        idx.dedup();
        idx.into_iter().map(|i| merged[i]).collect()
    };
    let mut ids: Vec<u32> = chosen.into_iter().map(|n| n.id).collect();
    if root.cacheable {
        ids.push(root.id);
    }
    ids.sort_unstable();
    ids.dedup();
    ids
}

#[cfg(test)]
mod tests {
    use super::*;

    fn node(id: u32, cost: f64, overlap: f64, root: bool) -> Node {
        Node {
            id,
            cacheable: true,
            reason: None,
            ty: "f32".into(),
            components: 1,
            cost,
            overlap,
            line: 1,
            col: 1,
            text: format!("n{id}"),
            call_line: None,
            call_col: None,
            root,
            handle: None,
        }
    }

    fn table(nodes: Vec<Node>) -> NodeTable {
        NodeTable {
            schema: "reproj.nodes".into(),
            version: 2,
            shader: "t.wgsl".into(),
            entry: "fs".into(),
            total_cost: 1000.0,
            nodes,
        }
    }

    #[test]
    fn keeps_root_drops_small_merges_near() {
        let t = table(vec![
            node(0, 10.0, 0.0, false),  // 1%: too small
            node(1, 300.0, 0.0, false), // 30%
            node(2, 305.0, 0.0, false), // 30.5%: merged into 1, the cheaper
            node(3, 600.0, 100.0, false),
            node(9, 1000.0, 0.0, true),
        ]);
        let ids = profile_candidates(&t, &PruneOptions::default());
        assert_eq!(ids, vec![1, 3, 9]);
    }

    #[test]
    fn spreads_over_savings_under_a_cap() {
        let mut nodes: Vec<Node> = (0..50)
            .map(|i| node(i, 60.0 + 18.0 * i as f64, 0.0, false))
            .collect();
        nodes.push(node(100, 1000.0, 0.0, true));
        let t = table(nodes);
        let ids = profile_candidates(
            &t,
            &PruneOptions {
                max_nodes: 5,
                ..Default::default()
            },
        );
        assert_eq!(ids.len(), 5);
        assert!(ids.contains(&100));
        // Both ends of the range are represented.
        assert!(ids.iter().any(|&i| i < 5), "{ids:?}");
        assert!(ids.iter().any(|&i| (45..50).contains(&i)), "{ids:?}");
    }

    #[test]
    fn nothing_worth_caching_leaves_the_root() {
        let t = table(vec![node(0, 1.0, 0.0, false), node(1, 3.0, 0.0, true)]);
        assert_eq!(profile_candidates(&t, &PruneOptions::default()), vec![1]);
    }
}
