//! Strategy pruning in `analyze`: which variant strategies stop being tried once they have clearly
//! lost on this adapter (fused on a CPU rasterizer), so that later nodes replay fewer of them.

/// Strategy pruning in `analyze`: a strategy at least [`StrategyPruner::MARGIN`] times slower than
/// the fastest strategy of the node at the longest Δn, for [`StrategyPruner::LOSSES`] nodes, and
/// never the fastest where the fastest beat the original, cannot win on this adapter (fused on a CPU rasterizer, which runs both sides
/// of its branch); it is not tried for the remaining nodes. Strategies within the margin of each
/// other (3pass and 2pass on lavapipe) are both kept: timing noise decides between them.
#[derive(Debug, Clone)]
pub(crate) struct StrategyPruner {
    losses: Vec<usize>,
    wins: Vec<usize>,
    announced: Vec<bool>,
}

/// What [`StrategyPruner::verdict`] says about a strategy for the next node.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Verdict {
    Try,
    /// Pruned from this node on (first time: say so).
    PruneNow,
    Pruned,
}

impl StrategyPruner {
    pub(crate) const LOSSES: usize = 2;
    pub(crate) const MARGIN: f64 = 1.25;

    pub(crate) fn new(strategies: usize) -> Self {
        StrategyPruner {
            losses: vec![0; strategies],
            wins: vec![0; strategies],
            announced: vec![false; strategies],
        }
    }

    /// Record one node's replay of strategy `i`: its frame time over the fastest strategy's
    /// (1 for the fastest), and whether the fastest beat the original (being fastest among
    /// variants that all lose to the original is no win).
    pub(crate) fn record(&mut self, i: usize, ratio_to_best: f64, best_beats_original: bool) {
        if ratio_to_best <= 1.0 {
            if best_beats_original {
                self.wins[i] += 1;
            }
        } else if ratio_to_best >= Self::MARGIN || !ratio_to_best.is_finite() {
            self.losses[i] += 1;
        }
    }

    pub(crate) fn verdict(&mut self, i: usize) -> Verdict {
        if self.losses[i] >= Self::LOSSES && self.wins[i] == 0 {
            if std::mem::replace(&mut self.announced[i], true) {
                Verdict::Pruned
            } else {
                Verdict::PruneNow
            }
        } else {
            Verdict::Try
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_strategy_clearly_slower_twice_is_pruned() {
        let mut p = StrategyPruner::new(3);
        // Node 1: 0 fastest, 1 within the margin, 2 twice as slow.
        p.record(0, 1.0, true);
        p.record(1, 1.1, true);
        p.record(2, 2.0, true);
        // One loss is not enough.
        assert_eq!(p.verdict(2), Verdict::Try);
        // Node 2: 1 fastest this time.
        p.record(0, 1.05, true);
        p.record(1, 1.0, true);
        p.record(2, 1.9, true);
        assert_eq!(p.verdict(0), Verdict::Try);
        assert_eq!(p.verdict(1), Verdict::Try);
        assert_eq!(p.verdict(2), Verdict::PruneNow);
        assert_eq!(p.verdict(2), Verdict::Pruned);
    }

    #[test]
    fn strategies_within_the_margin_are_kept() {
        let mut p = StrategyPruner::new(2);
        for _ in 0..5 {
            p.record(0, 1.0, true);
            p.record(1, 1.2, true);
        }
        assert_eq!(p.verdict(1), Verdict::Try);
    }

    #[test]
    fn a_strategy_that_was_fastest_once_is_kept() {
        let mut p = StrategyPruner::new(2);
        p.record(1, 1.0, true);
        for _ in 0..5 {
            p.record(1, 3.0, true);
        }
        assert_eq!(p.verdict(1), Verdict::Try);
    }

    #[test]
    fn fastest_among_losers_to_the_original_is_no_win() {
        let mut p = StrategyPruner::new(2);
        // A tiny node: every strategy is slower than the original, 1 the least slow.
        p.record(0, 1.3, false);
        p.record(1, 1.0, false);
        // Then 1 is clearly slower twice.
        for _ in 0..2 {
            p.record(0, 1.0, true);
            p.record(1, 2.0, true);
        }
        assert_eq!(p.verdict(1), Verdict::PruneNow);
    }
}
