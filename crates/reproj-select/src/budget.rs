//! The error budget ε_max and the refresh periods a selection may choose, as types: a budget is
//! checked once where it enters (the CLI's `--max-error`, a profile's sweep), so the selector and
//! everything after it take a [`Budget`] and never check it again.

use std::fmt;
use std::ops::RangeInclusive;
use std::str::FromStr;

use serde::{Deserialize, Serialize};

/// The refresh periods a selection considers by default and a profile measures at most: 2..=50
/// (Δn = 1 recomputes every frame and is never faster; 50 is the paper's clip).
pub const DELTA_N_RANGE: RangeInclusive<u32> = 2..=50;

/// An error budget ε_max: the largest acceptable error, a finite number ≥ 0 in the unit of the
/// metric the nodes' error models were fitted to (`l2`: the mean per-pixel L2 RGB distance;
/// `flip`: the mean ꟻLIP over the covered pixels). 0 admits only what is predicted exact.
/// Serialized as the bare number, checked again when read.
#[derive(Debug, Clone, Copy, PartialEq, PartialOrd, Serialize, Deserialize)]
#[serde(try_from = "f64", into = "f64")]
pub struct Budget(f64);

/// A budget that is negative or not finite.
#[derive(Debug, Clone, Copy, PartialEq, thiserror::Error)]
#[error("{0} is not an error budget (a finite number ≥ 0)")]
pub struct InvalidBudget(pub f64);

impl Budget {
    /// `max_error` as a budget, or why it is none.
    pub fn new(max_error: f64) -> Result<Self, InvalidBudget> {
        if max_error.is_finite() && max_error >= 0.0 {
            Ok(Self(max_error))
        } else {
            Err(InvalidBudget(max_error))
        }
    }

    /// The number.
    pub fn get(self) -> f64 {
        self.0
    }

    /// Whether an error of `error` is within the budget (`error ≤ ε_max`; NaN never is).
    pub fn admits(self, error: f64) -> bool {
        error <= self.0
    }
}

impl TryFrom<f64> for Budget {
    type Error = InvalidBudget;
    fn try_from(v: f64) -> Result<Self, InvalidBudget> {
        Self::new(v)
    }
}

impl From<Budget> for f64 {
    fn from(b: Budget) -> f64 {
        b.0
    }
}

impl FromStr for Budget {
    type Err = String;
    /// A budget as the command line gives it (`--max-error 0.01`).
    fn from_str(s: &str) -> Result<Self, String> {
        s.parse::<f64>()
            .ok()
            .and_then(|v| Self::new(v).ok())
            .ok_or_else(|| format!("`{s}` is not a finite number ≥ 0"))
    }
}

impl fmt::Display for Budget {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        fmt::Display::fmt(&self.0, f)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_budget_is_finite_and_non_negative() {
        assert_eq!(Budget::new(0.0).map(Budget::get), Ok(0.0));
        assert_eq!(Budget::new(0.01).map(Budget::get), Ok(0.01));
        for bad in [-1.0, f64::NAN, f64::INFINITY, -f64::INFINITY] {
            assert!(Budget::new(bad).is_err(), "{bad}");
        }
        assert!("-0.5".parse::<Budget>().is_err());
        assert!("NaN".parse::<Budget>().is_err());
        assert_eq!("0.03".parse::<Budget>(), Ok(Budget(0.03)));
        assert!(serde_json::from_str::<Budget>("-1.0").is_err());
        assert_eq!(serde_json::to_string(&Budget(0.5)).unwrap(), "0.5");
        assert!(!Budget(0.1).admits(f64::NAN));
    }
}
