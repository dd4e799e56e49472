//! The static cost of every expression's subtree and its overlap (the part the rest of the shader
//! still needs when the node is cached), from one reachability graph over the dependency edges.

use naga::{Expression, Handle};

use super::walk::Walk;
use crate::cost::op_cost;
use crate::graph::{Reach, dominators};

/// The costs of every expression's subtree, from one reachability graph over the dependency
/// edges (see `crate::graph`). The weights are whole numbers, so sums in any order are exact and
/// equal the old per-node ones.
pub(super) struct Costs {
    reach: Reach,
    /// Prefix sums over `reach`'s positions of every expression's weight.
    all_weight: Vec<f64>,
    /// The same, of the weight of what the output needs.
    needed_weight: Vec<f64>,
    /// What only each expression leads to from the output and the kill conditions.
    dominated: Vec<f64>,
    /// Whether the output (or a kill condition) needs each expression.
    total_closure: Vec<bool>,
    /// The cost of everything the output needs.
    pub(super) total_cost: f64,
}

impl Costs {
    /// What each expression reaches, and what only it leads to from the output and the kill
    /// conditions (a virtual vertex `n` stands for them).
    pub(super) fn new(
        fun: &naga::Function,
        info: &naga::valid::FunctionInfo,
        types: &naga::UniqueArena<naga::Type>,
        root: Handle<Expression>,
        walked: &Walk,
        deps: &[Vec<(Handle<Expression>, bool)>],
    ) -> Costs {
        let n = fun.expressions.len();
        let weight: Vec<f64> = fun
            .expressions
            .iter()
            .map(|(h, e)| {
                let mult = walked.places.get(&h).map_or(1.0, |p| p.weight);
                op_cost(e, info[h].ty.inner_with(types)) * mult
            })
            .collect();
        let outputs = n as u32;
        let mut succ: Vec<Vec<u32>> = deps
            .iter()
            .map(|d| d.iter().map(|&(h, _)| h.index() as u32).collect())
            .collect();
        succ.push(
            std::iter::once(root)
                .chain(walked.kills.iter().copied())
                .map(|h| h.index() as u32)
                .collect(),
        );
        let reach = Reach::new(&succ, &[outputs]);
        let mut total_closure = vec![false; n + 1];
        for &(s, e) in reach.runs(outputs) {
            for &v in &reach.by_position()[s as usize..e as usize] {
                total_closure[v as usize] = true;
            }
        }
        total_closure.truncate(n);
        let total_cost: f64 = (0..n)
            .filter(|&i| total_closure[i])
            .map(|i| weight[i])
            .sum();
        // Prefix sums over positions: of the weight, and of the weight of what the output needs.
        let prefix = |keep: &dyn Fn(usize) -> bool| -> Vec<f64> {
            let mut sums = Vec::with_capacity(n + 2);
            sums.push(0.0);
            let mut acc = 0.0;
            for &v in reach.by_position() {
                let v = v as usize;
                if v < n && keep(v) {
                    acc += weight[v];
                }
                sums.push(acc);
            }
            sums
        };
        let all_weight = prefix(&|_| true);
        let needed_weight = prefix(&|v| total_closure[v]);
        let mut dominated = dominators(&succ, outputs).subtree_sums(&{
            let mut w = weight.clone();
            w.push(0.0);
            w
        });
        dominated.truncate(n);
        Costs {
            reach,
            all_weight,
            needed_weight,
            dominated,
            total_closure,
            total_cost,
        }
    }

    /// The cost of `h`'s subtree, and its overlap: the part of the subtree the rest still needs,
    /// all of it but what only `h` leads to (when the output needs `h`), or what the output
    /// needs (when it does not).
    pub(super) fn of(&self, h: Handle<Expression>, is_root: bool) -> (f64, f64) {
        let v = h.index() as u32;
        let cost = self.reach.sum(v, &self.all_weight);
        let overlap = if is_root {
            0.0
        } else if self.total_closure[h.index()] {
            cost - self.dominated[h.index()]
        } else {
            self.reach.sum(v, &self.needed_weight)
        };
        (cost, overlap)
    }
}
