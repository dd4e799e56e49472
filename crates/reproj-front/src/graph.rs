//! Reachability and dominance over the dependency graph of a function's expressions, in time
//! about linear in its size, for the node table's costs and overlaps.
//!
//! The graph is given as successor lists over indices `0..n` (an expression's dependencies); it
//! may have cycles (a `Load` in a loop depends on the stores after it). Two questions are answered
//! for every vertex at once:
//!
//! - *what it reaches* ([`Reach`]): strongly connected components are numbered in the order
//!   Tarjan's search completes them, which makes the set a vertex reaches a few runs of
//!   consecutive numbers in straight-line code (a depth-first search finishes a subtree in one
//!   run); each component keeps its set as sorted disjoint runs, and a weight summed over the set
//!   is a sum of prefix-sum differences;
//! - *what only it leads to* ([`dominators`]): the dominator tree from a root, by Lengauer and
//!   Tarjan's algorithm (the simple version, `O(m log n)`).
//!
//! Both are iterative: a chain of 100 000 expressions is a 100 000-deep search.

/// Sentinel for "none" in the index vectors below.
const NONE: u32 = u32::MAX;

/// The set of vertices each vertex reaches (itself included), as runs of *positions*: the order
/// in which the search completed the vertices.
#[derive(Debug)]
pub(crate) struct Reach {
    /// Vertex at each position.
    at: Vec<u32>,
    /// Component of each vertex.
    component: Vec<u32>,
    /// Per component: what it reaches, as sorted, disjoint, non-adjacent `start..end` runs.
    runs: Vec<Vec<(u32, u32)>>,
}

impl Reach {
    /// Find what every vertex of the graph `succ` reaches. The search starts from `order` first
    /// (then from the remaining vertices by index); the sets do not depend on it, only how few
    /// runs they take.
    pub(crate) fn new(succ: &[Vec<u32>], order: &[u32]) -> Reach {
        let n = succ.len();
        let mut index = vec![NONE; n];
        let mut low = vec![0u32; n];
        let mut on_stack = vec![false; n];
        let mut stack: Vec<u32> = Vec::new();
        let mut reach = Reach {
            at: Vec::with_capacity(n),
            component: vec![NONE; n],
            runs: Vec::new(),
        };
        let mut next = 0u32;
        // Search frames: (vertex, next successor to look at).
        let mut frames: Vec<(u32, usize)> = Vec::new();
        let starts = order.iter().copied().chain(0..n as u32);
        for start in starts {
            if index[start as usize] != NONE {
                continue;
            }
            index[start as usize] = next;
            low[start as usize] = next;
            next += 1;
            stack.push(start);
            on_stack[start as usize] = true;
            frames.push((start, 0));
            while let Some(&mut (v, ref mut i)) = frames.last_mut() {
                let vi = v as usize;
                if let Some(&w) = succ[vi].get(*i) {
                    *i += 1;
                    let wi = w as usize;
                    if index[wi] == NONE {
                        index[wi] = next;
                        low[wi] = next;
                        next += 1;
                        stack.push(w);
                        on_stack[wi] = true;
                        frames.push((w, 0));
                    } else if on_stack[wi] {
                        low[vi] = low[vi].min(index[wi]);
                    }
                    continue;
                }
                frames.pop();
                if let Some(&(parent, _)) = frames.last() {
                    low[parent as usize] = low[parent as usize].min(low[vi]);
                }
                if low[vi] == index[vi] {
                    reach.complete(succ, &mut stack, &mut on_stack, v);
                }
            }
        }
        reach
    }

    /// Pop the component whose first vertex is `root` off the search stack, give its vertices
    /// the next positions and record what it reaches: its own run and those of the components it
    /// points to (all completed before it).
    fn complete(
        &mut self,
        succ: &[Vec<u32>],
        stack: &mut Vec<u32>,
        on_stack: &mut [bool],
        root: u32,
    ) {
        let c = self.runs.len() as u32;
        let first = self.at.len() as u32;
        loop {
            let w = stack
                .pop()
                .expect("the component's vertices are on the stack");
            on_stack[w as usize] = false;
            self.component[w as usize] = c;
            self.at.push(w);
            if w == root {
                break;
            }
        }
        let own = (first, self.at.len() as u32);
        let mut runs = vec![own];
        for &w in &self.at[first as usize..] {
            for &s in &succ[w as usize] {
                let d = self.component[s as usize];
                if d != c {
                    runs.extend_from_slice(&self.runs[d as usize]);
                }
            }
        }
        self.runs.push(merge(runs));
    }

    /// The vertices in position order.
    pub(crate) fn by_position(&self) -> &[u32] {
        &self.at
    }

    /// The runs of positions that vertex `v` reaches.
    pub(crate) fn runs(&self, v: u32) -> &[(u32, u32)] {
        &self.runs[self.component[v as usize] as usize]
    }

    /// Sum of `prefix` differences over what `v` reaches, where `prefix[p]` is the sum of a
    /// weight over the positions before `p` (length `n + 1`).
    pub(crate) fn sum(&self, v: u32, prefix: &[f64]) -> f64 {
        self.runs(v)
            .iter()
            .map(|&(s, e)| prefix[e as usize] - prefix[s as usize])
            .sum()
    }
}

/// Sort runs and join the overlapping and adjacent ones.
fn merge(mut runs: Vec<(u32, u32)>) -> Vec<(u32, u32)> {
    runs.sort_unstable();
    let mut out: Vec<(u32, u32)> = Vec::with_capacity(runs.len());
    for (s, e) in runs {
        match out.last_mut() {
            Some(last) if s <= last.1 => last.1 = last.1.max(e),
            _ => out.push((s, e)),
        }
    }
    out.shrink_to_fit();
    out
}

/// The dominator tree of the vertices a root reaches.
#[derive(Debug)]
pub(crate) struct Dominators {
    /// `idom[v]`: the last vertex before `v` that every path from the root to `v` goes through;
    /// the root for the root; `None` for a vertex the root does not reach.
    pub(crate) idom: Vec<Option<u32>>,
    /// The reached vertices, each after its immediate dominator.
    order: Vec<u32>,
}

impl Dominators {
    /// Per vertex, `weight` summed over the vertices it dominates (itself included); 0 for a vertex
    /// the root does not reach.
    pub(crate) fn subtree_sums(&self, weight: &[f64]) -> Vec<f64> {
        let mut sum = vec![0.0; self.idom.len()];
        for &v in self.order.iter().rev() {
            sum[v as usize] += weight[v as usize];
            let d = self.idom[v as usize].expect("ordered vertices are reached");
            if d != v {
                sum[d as usize] += sum[v as usize];
            }
        }
        sum
    }
}

/// The dominator tree from `root` in the graph `succ`.
pub(crate) fn dominators(succ: &[Vec<u32>], root: u32) -> Dominators {
    let n = succ.len();
    // 1. Depth-first numbering from the root; the rest works on these numbers.
    let mut num = vec![NONE; n];
    let mut vertex: Vec<u32> = Vec::new();
    let mut parent: Vec<u32> = Vec::new();
    let mut frames: Vec<(u32, usize)> = vec![(root, 0)];
    num[root as usize] = 0;
    vertex.push(root);
    parent.push(NONE);
    while let Some(&mut (v, ref mut i)) = frames.last_mut() {
        match succ[v as usize].get(*i) {
            Some(&w) => {
                *i += 1;
                if num[w as usize] == NONE {
                    num[w as usize] = vertex.len() as u32;
                    parent.push(num[v as usize]);
                    vertex.push(w);
                    frames.push((w, 0));
                }
            }
            None => {
                frames.pop();
            }
        }
    }
    let m = vertex.len();
    let mut pred: Vec<Vec<u32>> = vec![Vec::new(); m];
    for (v, &x) in vertex.iter().enumerate() {
        for &w in &succ[x as usize] {
            pred[num[w as usize] as usize].push(v as u32);
        }
    }
    // 2. Semidominators, and immediate dominators where they follow from them.
    let mut semi: Vec<u32> = (0..m as u32).collect();
    let mut label: Vec<u32> = (0..m as u32).collect();
    let mut ancestor = vec![NONE; m];
    let mut idom = vec![0u32; m];
    let mut bucket: Vec<Vec<u32>> = vec![Vec::new(); m];
    let mut path = Vec::new();
    for w in (1..m).rev() {
        for &v in &pred[w] {
            let u = eval(v, &mut ancestor, &mut label, &semi, &mut path);
            semi[w] = semi[w].min(semi[u as usize]);
        }
        bucket[semi[w] as usize].push(w as u32);
        let p = parent[w];
        ancestor[w] = p;
        for v in std::mem::take(&mut bucket[p as usize]) {
            let u = eval(v, &mut ancestor, &mut label, &semi, &mut path);
            idom[v as usize] = if semi[u as usize] < semi[v as usize] {
                u
            } else {
                p
            };
        }
    }
    // 3. The deferred ones.
    for w in 1..m {
        if idom[w] != semi[w] {
            idom[w] = idom[idom[w] as usize];
        }
    }
    let mut out = vec![None; n];
    for (v, &x) in vertex.iter().enumerate() {
        out[x as usize] = Some(vertex[idom[v] as usize]);
    }
    Dominators {
        idom: out,
        order: vertex,
    }
}

/// The vertex of least semidominator on the forest path above `v` (Lengauer–Tarjan `EVAL`, with
/// path compression done without recursion).
fn eval(v: u32, ancestor: &mut [u32], label: &mut [u32], semi: &[u32], path: &mut Vec<u32>) -> u32 {
    if ancestor[v as usize] == NONE {
        return v;
    }
    let mut x = v;
    while ancestor[ancestor[x as usize] as usize] != NONE {
        path.push(x);
        x = ancestor[x as usize];
    }
    while let Some(y) = path.pop() {
        let a = ancestor[y as usize] as usize;
        if semi[label[a] as usize] < semi[label[y as usize] as usize] {
            label[y as usize] = label[a];
        }
        ancestor[y as usize] = ancestor[a];
    }
    label[v as usize]
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every vertex's reachable set, by a plain search.
    fn naive_reach(succ: &[Vec<u32>], v: u32) -> Vec<bool> {
        let mut seen = vec![false; succ.len()];
        let mut stack = vec![v];
        while let Some(x) = stack.pop() {
            if !std::mem::replace(&mut seen[x as usize], true) {
                stack.extend(&succ[x as usize]);
            }
        }
        seen
    }

    /// Dominators by definition: `d` dominates `v` when `v` is unreachable from `root` with `d`
    /// removed.
    fn naive_dominates(succ: &[Vec<u32>], root: u32, d: u32, v: u32) -> bool {
        if d == v || d == root {
            return true;
        }
        let mut seen = vec![false; succ.len()];
        let mut stack = vec![root];
        while let Some(x) = stack.pop() {
            if x == d || std::mem::replace(&mut seen[x as usize], true) {
                continue;
            }
            stack.extend(&succ[x as usize]);
        }
        !seen[v as usize]
    }

    /// Small pseudo-random graphs with cycles, checked against the definitions.
    #[test]
    fn agree_with_definitions() {
        let mut state = 0x2545_f491_u64;
        let mut rand = |k: u64| {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            (state % k) as u32
        };
        for round in 0..200 {
            let n = 1 + (round % 12) as usize;
            let succ: Vec<Vec<u32>> = (0..n)
                .map(|_| (0..rand(4)).map(|_| rand(n as u64)).collect())
                .collect();
            let reach = Reach::new(&succ, &[0]);
            let prefix: Vec<f64> = std::iter::once(0.0)
                .chain(reach.by_position().iter().scan(0.0, |s, &v| {
                    *s += f64::from(1 << v);
                    Some(*s)
                }))
                .collect();
            for v in 0..n as u32 {
                let want: f64 = naive_reach(&succ, v)
                    .iter()
                    .enumerate()
                    .filter(|(_, s)| **s)
                    .map(|(i, _)| f64::from(1 << i))
                    .sum();
                assert_eq!(reach.sum(v, &prefix), want, "{succ:?} from {v}");
            }
            let doms = dominators(&succ, 0);
            let idom = &doms.idom;
            let ones = vec![1.0; n];
            let sums = doms.subtree_sums(&ones);
            let reached = naive_reach(&succ, 0);
            for v in 0..n as u32 {
                assert_eq!(idom[v as usize].is_some(), reached[v as usize]);
                let Some(d) = idom[v as usize] else { continue };
                let dominated = (0..n as u32)
                    .filter(|&x| reached[x as usize] && naive_dominates(&succ, 0, v, x))
                    .count();
                assert_eq!(sums[v as usize], dominated as f64, "{succ:?}: under {v}");
                assert!(naive_dominates(&succ, 0, d, v), "{succ:?}: {d} over {v}");
                // The immediate one: every other strict dominator dominates it.
                for o in 0..n as u32 {
                    if o != v && o != d && naive_dominates(&succ, 0, o, v) {
                        assert!(naive_dominates(&succ, 0, o, d), "{succ:?}: {o} {d} {v}");
                    }
                }
            }
        }
    }
}
