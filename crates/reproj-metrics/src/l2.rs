//! The L2 error and PSNR of a frame against its reference (definitions in `docs/SCHEMAS.md`):
//! computed on the CPU by [`compare`], on the GPU by the replay's reduction pass, and both agree
//! (`gpu_error_reduction_matches_the_cpu`). The bottom of the crate: it imports nothing of it.

/// PSNR reported for identical frames (instead of +∞).
pub const PSNR_CAP: f64 = 100.0;

/// Per-pixel L2 RGB distance, clamped to [0, 1] first; RGBA f32 inputs.
pub fn pixel_errors(a: &[f32], b: &[f32]) -> Vec<f32> {
    a.chunks_exact(4)
        .zip(b.chunks_exact(4))
        .map(|(p, q)| {
            let mut s = 0.0f32;
            for c in 0..3 {
                let d = p[c].clamp(0.0, 1.0) - q[c].clamp(0.0, 1.0);
                s += d * d;
            }
            s.sqrt()
        })
        .collect()
}

/// The error sums of one frame against its reference, from which every per-frame number is
/// derived. Computed on the CPU by [`compare`] and on the GPU by the replay's reduction pass.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct FrameError {
    /// Pixels in the frame.
    pub pixels: u64,
    /// Sum over all pixels of the L2 distance between the RGB values, each channel clamped to
    /// [0, 1].
    pub sum_l2: f64,
    /// Pixels where the reference has geometry (reference depth < 1).
    pub covered: u64,
    /// Sum over the covered pixels and the three channels (clamped to [0, 1]) of the squared
    /// difference.
    pub sum_sq: f64,
    /// Largest absolute difference of any channel, RGBA, unclamped (∞ when a difference is NaN).
    pub max_abs_diff: f64,
    /// Pixels whose RGB is not finite (NaN or ±∞) where the reference's is: each makes the sums
    /// NaN, so a frame with one has a NaN error.
    pub nonfinite: u64,
    /// Pixels whose reference RGB is not finite: left out of the sums, `covered` and the mean's
    /// pixel count.
    pub nonfinite_reference: u64,
}

impl FrameError {
    /// Mean per-pixel L2 distance over all pixels: the error the budgets bound.
    pub fn error(&self) -> f64 {
        self.sum_l2 / self.pixels.saturating_sub(self.nonfinite_reference).max(1) as f64
    }

    /// Mean squared error per channel over the covered pixels; 0 when nothing is covered.
    pub fn mse(&self) -> f64 {
        mse(self.sum_sq, self.covered)
    }

    /// PSNR of [`FrameError::mse`].
    pub fn psnr(&self) -> f64 {
        psnr(self.mse())
    }
}

/// Error sums of a frame against its reference (RGBA f32, same size) where the reference's depth
/// (one f32 per pixel, 1 where nothing was drawn) says which pixels are covered.
pub fn compare(frame: &[f32], reference: &[f32], reference_depth: &[f32]) -> FrameError {
    let mut e = FrameError {
        pixels: (frame.len() / 4) as u64,
        ..FrameError::default()
    };
    for ((p, q), &depth) in frame
        .chunks_exact(4)
        .zip(reference.chunks_exact(4))
        .zip(reference_depth)
    {
        if !finite3(q) {
            e.nonfinite_reference += 1;
            continue;
        }
        if !finite3(p) {
            e.nonfinite += 1;
        }
        let mut s = 0.0f64;
        for c in 0..3 {
            // A non-finite channel makes the pixel's distance NaN, as on the GPU.
            let d = if p[c].is_finite() {
                (p[c].clamp(0.0, 1.0) - q[c].clamp(0.0, 1.0)) as f64
            } else {
                f64::NAN
            };
            s += d * d;
        }
        for c in 0..4 {
            let d = (p[c] - q[c]).abs() as f64;
            e.max_abs_diff = if d.is_nan() {
                f64::INFINITY
            } else {
                e.max_abs_diff.max(d)
            };
        }
        e.sum_l2 += s.sqrt();
        if depth < 1.0 {
            e.covered += 1;
            e.sum_sq += s;
        }
    }
    e
}

/// Whether a pixel's RGB is finite (its alpha is not checked: it is not part of the error).
pub fn finite3(p: &[f32]) -> bool {
    p[..3].iter().all(|c| c.is_finite())
}

/// Mean squared error per channel of `sum_sq` over `covered` pixels and three channels; 0 when
/// `covered` is 0.
pub fn mse(sum_sq: f64, covered: u64) -> f64 {
    if covered == 0 {
        0.0
    } else {
        sum_sq / (3.0 * covered as f64)
    }
}

/// PSNR in dB for a peak of 1, `10 log10(1 / mse)`, capped at [`PSNR_CAP`] (NaN for a NaN `mse`).
pub fn psnr(mse: f64) -> f64 {
    if mse.is_nan() {
        f64::NAN
    } else if mse <= 0.0 {
        PSNR_CAP
    } else {
        (10.0 * (1.0 / mse).log10()).min(PSNR_CAP)
    }
}

/// Mean of `xs`, 0 when empty.
pub fn mean(xs: impl Iterator<Item = f64>) -> f64 {
    let (s, n) = xs.fold((0.0, 0usize), |(s, n), x| (s + x, n + 1));
    if n == 0 { 0.0 } else { s / n as f64 }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn compare_counts_squared_error_only_where_the_reference_is_covered() {
        // Two pixels: the first covered, off by 0.1 in R; the second background, off by 0.3 in G
        // (and 0.5 in alpha, which only the max difference sees).
        let reference = [0.5, 0.5, 0.5, 1.0, 0.0, 0.0, 0.0, 1.0];
        let frame = [0.6, 0.5, 0.5, 1.0, 0.0, 0.3, 0.0, 0.5];
        let e = compare(&frame, &reference, &[0.4, 1.0]);
        assert_eq!((e.pixels, e.covered), (2, 1));
        let d0 = 0.6f32 - 0.5;
        let d1 = 0.3f32;
        assert!((e.sum_l2 - (d0 as f64 + d1 as f64)).abs() < 1e-12);
        assert!((e.error() - (d0 as f64 + d1 as f64) / 2.0).abs() < 1e-12);
        assert!((e.mse() - (d0 as f64).powi(2) / 3.0).abs() < 1e-12);
        assert!((e.psnr() - 10.0 * (3.0 / (d0 as f64).powi(2)).log10()).abs() < 1e-9);
        assert_eq!(e.max_abs_diff, 0.5);
        // Clamped to [0, 1] before differencing; NaN makes the max difference infinite.
        let e = compare(&[2.0, 0.0, 0.0, f32::NAN], &[1.0, 0.0, 0.0, 1.0], &[0.0]);
        assert_eq!((e.sum_l2, e.sum_sq), (0.0, 0.0));
        assert_eq!(e.max_abs_diff, f64::INFINITY);
    }

    #[test]
    fn nothing_covered_is_zero_mse_and_capped_psnr() {
        let e = compare(&[1.0, 1.0, 1.0, 1.0], &[0.0, 0.0, 0.0, 1.0], &[1.0]);
        assert_eq!(e.covered, 0);
        assert_eq!(e.mse(), 0.0);
        assert_eq!(e.psnr(), PSNR_CAP);
        assert!(e.error() > 1.7);
        assert!(psnr(f64::NAN).is_nan());
    }
}
