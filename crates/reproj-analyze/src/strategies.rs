//! Strategy pruning in `analyze`: which variant strategies stop being tried once they have clearly
//! lost on this adapter (fused on a CPU rasterizer), so that later nodes replay fewer of them.

/// Strategy pruning in `analyze`: a strategy at least [`StrategyPruner::MARGIN`] times slower than
/// the node's winner at the longest Δn, the two intervals apart, for [`StrategyPruner::LOSSES`]
/// nodes, and never the winner where the winner beat the original, cannot win on this adapter
/// (fused on a CPU rasterizer, which runs both sides of its branch; 3pass beside 2pass on
/// lavapipe, 1.2–1.6× slower on marble's nodes); it is not tried for the remaining nodes. The
/// intervals apart already say it is slower; the margin asks that it be slower by enough to
/// matter. One loss by [`StrategyPruner::DECISIVE`] or more counts as [`StrategyPruner::LOSSES`]:
/// fused on lavapipe runs 2.8–5.9× slower than 2pass on the node saving the most (marble, ambient
/// occlusion, environment map), and compiling and racing it on a second node cost marble's
/// analysis about 4 s. A strategy level with the winner (intervals overlapping) neither wins nor
/// loses: the race could not tell them apart, and the winner is then the simplest.
#[derive(Debug, Clone)]
pub(crate) struct StrategyPruner {
    losses: Vec<usize>,
    wins: Vec<usize>,
    announced: Vec<bool>,
}

/// How one strategy did in one node's race ([`StrategyPruner::record`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) enum Outcome {
    /// The race's winner; `beat_original`: its interval lies above 1× (being the fastest among
    /// variants that all lose to the original is no win).
    Won { beat_original: bool },
    /// Its interval overlaps the winner's: not told apart.
    Level,
    /// Slower than the winner, the intervals apart: the winner's speedup over its own (infinite
    /// where it could not be timed).
    Slower(f64),
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
    pub(crate) const MARGIN: f64 = 1.1;
    /// A loss at least this many times slower than the winner, beyond doubt, is decisive.
    pub(crate) const DECISIVE: f64 = 2.0;

    pub(crate) fn new(strategies: usize) -> Self {
        StrategyPruner {
            losses: vec![0; strategies],
            wins: vec![0; strategies],
            announced: vec![false; strategies],
        }
    }

    /// Record how strategy `i` did in one node's race.
    pub(crate) fn record(&mut self, i: usize, outcome: Outcome) {
        match outcome {
            Outcome::Won { beat_original } => self.wins[i] += usize::from(beat_original),
            Outcome::Level => {}
            Outcome::Slower(ratio) => {
                if ratio >= Self::DECISIVE || !ratio.is_finite() {
                    self.losses[i] += Self::LOSSES;
                } else if ratio >= Self::MARGIN {
                    self.losses[i] += 1;
                }
            }
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

    const WON: Outcome = Outcome::Won {
        beat_original: true,
    };

    #[test]
    fn a_strategy_clearly_slower_twice_is_pruned() {
        let mut p = StrategyPruner::new(3);
        // Node 1: 0 won, 1 slower within the margin, 2 half as fast again.
        p.record(0, WON);
        p.record(1, Outcome::Slower(1.05));
        p.record(2, Outcome::Slower(1.5));
        // One loss is not enough.
        assert_eq!(p.verdict(2), Verdict::Try);
        // Node 2: 1 won this time.
        p.record(0, Outcome::Slower(1.05));
        p.record(1, WON);
        p.record(2, Outcome::Slower(1.4));
        assert_eq!(p.verdict(0), Verdict::Try);
        assert_eq!(p.verdict(1), Verdict::Try);
        assert_eq!(p.verdict(2), Verdict::PruneNow);
        assert_eq!(p.verdict(2), Verdict::Pruned);
    }

    #[test]
    fn strategies_within_the_margin_are_kept() {
        let mut p = StrategyPruner::new(2);
        for _ in 0..5 {
            p.record(0, WON);
            p.record(1, Outcome::Slower(1.05));
        }
        assert_eq!(p.verdict(1), Verdict::Try);
    }

    #[test]
    fn a_strategy_that_won_once_is_kept() {
        let mut p = StrategyPruner::new(2);
        p.record(1, WON);
        for _ in 0..5 {
            p.record(1, Outcome::Slower(3.0));
        }
        assert_eq!(p.verdict(1), Verdict::Try);
    }

    /// marble on lavapipe: 3pass level with 2pass on the first node (2.09× [1.77, 2.46] against
    /// 2.31× [1.96, 2.72]; the simplest, 2pass, won), then 1.58× and 1.40× slower beyond doubt. A
    /// level race is no win: it used to count as one and kept 3pass raced on every node.
    #[test]
    fn a_level_race_is_no_win() {
        let mut p = StrategyPruner::new(2);
        p.record(0, Outcome::Level);
        p.record(1, WON);
        for ratio in [1.58, 1.40] {
            p.record(0, Outcome::Slower(ratio));
            p.record(1, WON);
        }
        assert_eq!(p.verdict(0), Verdict::PruneNow);
        assert_eq!(p.verdict(1), Verdict::Try);
    }

    /// fused on lavapipe at marble's node 730: 0.86× against 2pass's 2.41×.
    #[test]
    fn one_decisive_loss_prunes() {
        let mut p = StrategyPruner::new(2);
        p.record(0, WON);
        p.record(1, Outcome::Slower(2.41 / 0.86));
        assert_eq!(p.verdict(1), Verdict::PruneNow);
        let mut p = StrategyPruner::new(2);
        p.record(1, Outcome::Slower(1.99));
        assert_eq!(p.verdict(1), Verdict::Try);
    }

    #[test]
    fn the_winner_among_losers_to_the_original_is_no_win() {
        let mut p = StrategyPruner::new(2);
        // A tiny node: every strategy is slower than the original, 1 the least slow.
        p.record(0, Outcome::Slower(1.3));
        p.record(
            1,
            Outcome::Won {
                beat_original: false,
            },
        );
        // Then 1 is clearly slower twice.
        for _ in 0..2 {
            p.record(0, WON);
            p.record(1, Outcome::Slower(2.0));
        }
        assert_eq!(p.verdict(1), Verdict::PruneNow);
    }
}
