//! Small statistics shared by the fits: goodness of fit (R², RMS residual) and PSNR.

/// Coefficient of determination of `fitted` against `observed`.
///
/// When the observations are (numerically) constant, R² is undefined; we report 1 if the fit
/// reproduces them (residuals as small as the spread) and 0 otherwise, so it is always finite.
pub(crate) fn r_squared(observed: &[f64], fitted: &[f64]) -> f64 {
    let n = observed.len();
    if n == 0 {
        return 0.0;
    }
    let mean = observed.iter().sum::<f64>() / n as f64;
    let ss_tot: f64 = observed.iter().map(|y| (y - mean).powi(2)).sum();
    let ss_res: f64 = observed
        .iter()
        .zip(fitted)
        .map(|(y, f)| (y - f).powi(2))
        .sum();
    let sum_sq: f64 = observed.iter().map(|y| y * y).sum();
    let tiny = 1e-24 + 1e-20 * sum_sq;
    let r2 = if ss_tot <= tiny {
        if ss_res <= tiny.max(1e-12 * sum_sq) {
            1.0
        } else {
            0.0
        }
    } else {
        1.0 - ss_res / ss_tot
    };
    finite_or(r2, 0.0)
}

/// Root mean square of `observed − fitted`.
pub(crate) fn rms_residual(observed: &[f64], fitted: &[f64]) -> f64 {
    if observed.is_empty() {
        return 0.0;
    }
    let ss: f64 = observed
        .iter()
        .zip(fitted)
        .map(|(y, f)| (y - f).powi(2))
        .sum();
    finite_or((ss / observed.len() as f64).sqrt(), 0.0)
}

/// `x` when finite, else `fallback`.
pub(crate) fn finite_or(x: f64, fallback: f64) -> f64 {
    if x.is_finite() { x } else { fallback }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn r2_perfect_and_constant() {
        assert_eq!(r_squared(&[1.0, 2.0, 3.0], &[1.0, 2.0, 3.0]), 1.0);
        assert_eq!(r_squared(&[2.0, 2.0], &[2.0, 2.0]), 1.0);
        assert_eq!(r_squared(&[2.0, 2.0], &[1.0, 1.0]), 0.0);
        assert_eq!(r_squared(&[], &[]), 0.0);
    }
}
