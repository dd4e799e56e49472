//! The warning of a run that a limit stopped while an interval was still wider than its target,
//! and which limit it was: the engine's text names no flag (the commands that time through it
//! have different ones, or none), so a command that has the flag reads the limit back here.

/// A limit that stopped a run.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Limit {
    /// The most rounds.
    Rounds,
    /// The most seconds.
    Time,
}

const WIDE: &str = "the interval is wider than";

/// The warning that `limit` stopped the run after `rounds` rounds in `seconds`, with an
/// interval wider than ± `target_percent` %.
pub(crate) fn wide_warning(limit: Limit, target_percent: f64, rounds: u32, seconds: f64) -> String {
    match limit {
        Limit::Rounds => {
            format!("{WIDE} ±{target_percent:.0} % after the last of {rounds} rounds")
        }
        Limit::Time => format!("{WIDE} ±{target_percent:.0} % after {seconds:.0} s"),
    }
}

/// The limit a warning of [`wide_warning`] names; `None` for any other warning.
pub fn limit_of(warning: &str) -> Option<Limit> {
    if !warning.starts_with(WIDE) {
        None
    } else if warning.ends_with(" rounds") {
        Some(Limit::Rounds)
    } else {
        Some(Limit::Time)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_limit_reads_back_from_its_warning() {
        for limit in [Limit::Rounds, Limit::Time] {
            assert_eq!(limit_of(&wide_warning(limit, 3.0, 48, 30.2)), Some(limit));
        }
        assert_eq!(limit_of("the machine was busy: a 1.20× [1.00, 1.40]"), None);
    }
}
