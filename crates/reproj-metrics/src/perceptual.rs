//! Perceptual error of a frame against its reference: ꟻLIP and SSIM over the covered pixels.
//!
//! The mean L2 distance over all pixels (the paper's error, [`crate::l2`]) says how much a
//! frame changed, not whether a person sees it; ꟻLIP (Andersson et al. 2020) and SSIM (Wang et
//! al. 2004) are what graphics teams trust for that. Both compare what a viewer sees: the linear
//! RGB frame clamped to [0, 1], sRGB-encoded and quantized to 8 bits, as the PNGs `render --frames`
//! writes. Both are pooled over the *covered* pixels (reference depth < 1), so a budget means the
//! same for a small object as for a large one. Definitions in `docs/SCHEMAS.md`.
//!
//! ꟻLIP is NVIDIA's reference implementation through the `nv-flip` crate (LDR ꟻLIP, default
//! viewing conditions: [`nv_flip::DEFAULT_PIXELS_PER_DEGREE`]). SSIM is implemented here (no kept
//! crate computes the standard single-scale definition): 11×11 Gaussian window, σ = 1.5,
//! K1 = 0.01, K2 = 0.03, dynamic range 1, on the luma of the sRGB-encoded image, over the windows
//! that lie inside the frame (Wang et al.'s reference code filters with `'valid'`).

use crate::srgb::to_srgb8;

/// ꟻLIP's viewing conditions: pixels per degree of visual angle (NVIDIA's default: a 0.7 m wide
/// 4K monitor seen from 0.7 m).
pub const PIXELS_PER_DEGREE: f32 = nv_flip::DEFAULT_PIXELS_PER_DEGREE;

/// Side of the SSIM window.
pub const SSIM_WINDOW: usize = 11;
/// Standard deviation of the SSIM window's Gaussian, pixels.
pub const SSIM_SIGMA: f64 = 1.5;
const SSIM_K1: f64 = 0.01;
const SSIM_K2: f64 = 0.03;

/// One frame's perceptual error against its reference.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PerceptualError {
    /// Mean ꟻLIP error over the covered pixels, in [0, 1] (0: identical); 0 when nothing is
    /// covered.
    pub flip: f64,
    /// Mean SSIM over the covered pixels whose window lies inside the frame, in [-1, 1]
    /// (1: identical); 1 when there is no such pixel.
    pub ssim: f64,
}

/// The ꟻLIP error map of `test` against `reference` (both sRGB 8-bit RGB, `width`×`height`, top
/// row first): one value in [0, 1] per pixel.
///
/// The same values as one call of NVIDIA's code on the whole frame, for less: ꟻLIP is local (a
/// pixel depends on the pixels within [`flip_support`] of it), so it is 0 wherever the two
/// frames agree over that distance. Only the box around the pixels that differ is computed, in
/// horizontal strips on every core, each strip with a margin wider than the support (the
/// reference code is single-threaded: about 26 ms for a 256×256 frame, 0.8 s at 1080p).
pub fn flip_map(test: &[u8], reference: &[u8], width: u32, height: u32) -> Vec<f32> {
    flip_map_in_strips(test, reference, width, height, rayon::current_num_threads())
}

/// How far, in pixels, a pixel's ꟻLIP value depends on the others at the default viewing
/// conditions: the larger radius of the colour filter (3·√(b_max / 2π²)·ppd with the largest
/// scale parameter, 0.04) and the feature filter (3 · ½ · 0.082 · ppd), rounded up as the
/// reference code rounds them (`sharedflip.h`, `image.h`): 10 pixels at 67 pixels per degree.
pub fn flip_support() -> usize {
    let ppd = nv_flip::DEFAULT_PIXELS_PER_DEGREE;
    let pi_sq = std::f32::consts::PI * std::f32::consts::PI;
    let colour = (3.0 * (0.04 / (2.0 * pi_sq)).sqrt() * ppd).ceil();
    let feature = (3.0 * 0.5 * 0.082 * ppd).ceil();
    colour.max(feature) as usize
}

/// [`flip_map`] with at most `strips` strips (1: the box in one call).
fn flip_map_in_strips(
    test: &[u8],
    reference: &[u8],
    width: u32,
    height: u32,
    strips: usize,
) -> Vec<f32> {
    use rayon::prelude::*;
    let (w, h) = (width as usize, height as usize);
    let mut out = vec![0.0f32; w * h];
    // The box of the pixels that differ; none: the map is 0.
    let (mut x0, mut y0, mut x1, mut y1) = (w, h, 0, 0);
    for (i, (a, b)) in test
        .chunks_exact(3)
        .zip(reference.chunks_exact(3))
        .enumerate()
    {
        if a != b {
            let (x, y) = (i % w, i / w);
            (x0, y0, x1, y1) = (x0.min(x), y0.min(y), x1.max(x + 1), y1.max(y + 1));
        }
    }
    if x0 >= x1 {
        return out;
    }
    // Outside the box grown by the support the frames agree over the support: 0. Inside it each
    // pixel's neighbourhood lies inside the box grown by twice the support (or is clamped at the
    // frame's edge, as in the whole frame), so the values are those of the whole frame.
    let margin = 2 * flip_support() + 1;
    let (cx0, cx1) = (x0.saturating_sub(margin), (x1 + margin).min(w));
    let (cy0, cy1) = (y0.saturating_sub(margin), (y1 + margin).min(h));
    let rows = cy1 - cy0;
    // Strips no thinner than a few margins, or the margins would cost more than they save.
    let n = strips.clamp(1, (rows / (4 * margin)).max(1));
    let per = rows.div_ceil(n);
    let cw = cx1 - cx0;
    let parts: Vec<(usize, Vec<f32>)> = (0..n)
        .into_par_iter()
        .map(|k| {
            let (a, b) = (cy0 + k * per, (cy0 + (k + 1) * per).min(cy1));
            // The strip with its margins, clipped to the box (the box's edges are clamped the
            // same way whatever the strip).
            let (ea, eb) = (a.saturating_sub(margin).max(cy0), (b + margin).min(cy1));
            let cut = |img: &[u8]| -> Vec<u8> {
                (ea..eb)
                    .flat_map(|y| &img[3 * (y * w + cx0)..3 * (y * w + cx1)])
                    .copied()
                    .collect()
            };
            let map = flip_whole(&cut(test), &cut(reference), cw as u32, (eb - ea) as u32);
            (a, map[(a - ea) * cw..(b - ea) * cw].to_vec())
        })
        .collect();
    for (a, strip) in parts {
        for (r, row) in strip.chunks_exact(cw).enumerate() {
            let at = (a + r) * w + cx0;
            out[at..at + cw].copy_from_slice(row);
        }
    }
    out
}

/// One call of NVIDIA's ꟻLIP on the whole of two images.
fn flip_whole(test: &[u8], reference: &[u8], width: u32, height: u32) -> Vec<f32> {
    let reference = nv_flip::FlipImageRgb8::with_data(width, height, reference);
    let test = nv_flip::FlipImageRgb8::with_data(width, height, test);
    nv_flip::flip(reference, test, nv_flip::DEFAULT_PIXELS_PER_DEGREE).to_vec()
}

/// A ꟻLIP error map through NVIDIA's magma colour map, as RGBA8 (black: no error).
pub fn flip_colors(map: &[f32], width: u32, height: u32) -> Vec<u8> {
    let image = nv_flip::FlipImageFloat::with_data(width, height, map);
    image
        .apply_color_lut(&nv_flip::magma_lut())
        .to_vec()
        .chunks_exact(3)
        .flat_map(|p| [p[0], p[1], p[2], 255])
        .collect()
}

/// Luma of sRGB-encoded 8-bit RGB in [0, 1], with the Rec. 601 weights of Wang et al.'s setup
/// (MATLAB's `rgb2gray`).
pub fn luma(rgb: &[u8]) -> Vec<f64> {
    rgb.chunks_exact(3)
        .map(|p| {
            (0.298_936 * f64::from(p[0])
                + 0.587_043 * f64::from(p[1])
                + 0.114_021 * f64::from(p[2]))
                / 255.0
        })
        .collect()
}

/// The normalized 1-D Gaussian of the SSIM window (the 2-D window is its outer product).
fn gaussian() -> [f64; SSIM_WINDOW] {
    let r = (SSIM_WINDOW / 2) as f64;
    let mut g = [0.0; SSIM_WINDOW];
    for (i, v) in g.iter_mut().enumerate() {
        let x = i as f64 - r;
        *v = (-x * x / (2.0 * SSIM_SIGMA * SSIM_SIGMA)).exp();
    }
    let sum: f64 = g.iter().sum();
    g.map(|v| v / sum)
}

/// The SSIM map of two luma images (`width`×`height`, values in [0, 1]): the value at pixel
/// (x, y) is that of the window centred there, `None` where the window leaves the image.
pub fn ssim_map(a: &[f64], b: &[f64], width: usize, height: usize) -> Vec<Option<f64>> {
    let n = SSIM_WINDOW;
    let r = n / 2;
    let mut out = vec![None; width * height];
    if width < n || height < n {
        return out;
    }
    let g = gaussian();
    let (vw, vh) = (width - n + 1, height - n + 1);
    // The five images the window averages, each blurred horizontally then vertically ('valid').
    let products: [Vec<f64>; 5] = [
        a.to_vec(),
        b.to_vec(),
        a.iter().map(|v| v * v).collect(),
        b.iter().map(|v| v * v).collect(),
        a.iter().zip(b).map(|(u, v)| u * v).collect(),
    ];
    let blurred: Vec<Vec<f64>> = products
        .iter()
        .map(|img| {
            let mut h = vec![0.0; vw * height];
            for y in 0..height {
                let row = &img[y * width..(y + 1) * width];
                for x in 0..vw {
                    h[y * vw + x] = g.iter().zip(&row[x..x + n]).map(|(g, v)| g * v).sum();
                }
            }
            let mut v = vec![0.0; vw * vh];
            for y in 0..vh {
                for x in 0..vw {
                    v[y * vw + x] = (0..n).map(|k| g[k] * h[(y + k) * vw + x]).sum();
                }
            }
            v
        })
        .collect();
    let c1 = SSIM_K1 * SSIM_K1;
    let c2 = SSIM_K2 * SSIM_K2;
    for y in 0..vh {
        for x in 0..vw {
            let i = y * vw + x;
            let (ma, mb) = (blurred[0][i], blurred[1][i]);
            let va = blurred[2][i] - ma * ma;
            let vb = blurred[3][i] - mb * mb;
            let cov = blurred[4][i] - ma * mb;
            let s = ((2.0 * ma * mb + c1) * (2.0 * cov + c2))
                / ((ma * ma + mb * mb + c1) * (va + vb + c2));
            out[(y + r) * width + x + r] = Some(s);
        }
    }
    out
}

/// How [`compare_perceptual_split`] spreads one frame's ꟻLIP over the threads of the current
/// rayon pool.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum FrameSplit {
    /// In strips, one per thread ([`flip_map`]): the fastest for one frame alone. Each strip
    /// recomputes a margin of its neighbours' rows (about a quarter more work for two strips of a
    /// 256×256 frame).
    Strips,
    /// In one piece: the least work, for callers that score several frames at once, one per
    /// thread.
    Whole,
}

/// The perceptual error of `frame` against `reference` (linear RGBA f32, `width`×`height`, top
/// row first), pooled over the pixels where `reference_depth` < 1; with the ꟻLIP map (for
/// `render --frames`). One frame alone: its ꟻLIP in strips over the current pool's threads.
pub fn compare_perceptual(
    frame: &[f32],
    reference: &[f32],
    reference_depth: &[f32],
    width: u32,
    height: u32,
) -> (PerceptualError, Vec<f32>) {
    compare_perceptual_split(
        frame,
        reference,
        reference_depth,
        width,
        height,
        FrameSplit::Strips,
    )
}

/// [`compare_perceptual`], the frame's ꟻLIP spread over threads as `split` says (the values do
/// not depend on it).
pub fn compare_perceptual_split(
    frame: &[f32],
    reference: &[f32],
    reference_depth: &[f32],
    width: u32,
    height: u32,
    split: FrameSplit,
) -> (PerceptualError, Vec<f32>) {
    let (test, refr) = (to_srgb8(frame), to_srgb8(reference));
    let strips = match split {
        FrameSplit::Strips => rayon::current_num_threads(),
        FrameSplit::Whole => 1,
    };
    let (flip, ssim) = rayon::join(
        || flip_map_in_strips(&test, &refr, width, height, strips),
        || ssim_map(&luma(&test), &luma(&refr), width as usize, height as usize),
    );
    let covered = || reference_depth.iter().map(|&d| d < 1.0);
    let flip_mean = mean_where(flip.iter().map(|&v| Some(f64::from(v))), covered());
    let ssim_mean = mean_where(ssim.iter().copied(), covered());
    (
        PerceptualError {
            flip: flip_mean.unwrap_or(0.0),
            ssim: ssim_mean.unwrap_or(1.0),
        },
        flip,
    )
}

/// Mean of the present values at the selected pixels; `None` when there are none.
fn mean_where(
    values: impl Iterator<Item = Option<f64>>,
    selected: impl Iterator<Item = bool>,
) -> Option<f64> {
    let (sum, n) = values
        .zip(selected)
        .filter_map(|(v, s)| v.filter(|_| s))
        .fold((0.0, 0u64), |(s, n), v| (s + v, n + 1));
    (n > 0).then(|| sum / n as f64)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A small deterministic generator (xorshift), values in [0, 1).
    struct Rng(u32);
    impl Rng {
        fn next(&mut self) -> f32 {
            self.0 ^= self.0 << 13;
            self.0 ^= self.0 >> 17;
            self.0 ^= self.0 << 5;
            (self.0 >> 8) as f32 / (1u32 << 24) as f32
        }
    }

    fn grey(w: usize, h: usize, v: f32) -> Vec<f32> {
        (0..w * h).flat_map(|_| [v, v, v, 1.0]).collect()
    }

    #[test]
    fn a_frame_scored_whole_equals_the_frame_scored_in_strips() {
        let mut rng = Rng(5);
        let (w, h) = (96usize, 200usize);
        let reference: Vec<f32> = (0..4 * w * h).map(|_| rng.next()).collect();
        let frame: Vec<f32> = reference
            .iter()
            .map(|&v| (v + 0.1 * (rng.next() - 0.5)).clamp(0.0, 1.0))
            .collect();
        let depth = vec![0.5; w * h];
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(3)
            .build()
            .unwrap();
        let [strips, whole] = [FrameSplit::Strips, FrameSplit::Whole].map(|split| {
            pool.install(|| {
                compare_perceptual_split(&frame, &reference, &depth, w as u32, h as u32, split)
            })
        });
        assert!(strips.0.flip > 0.0);
        assert_eq!(strips, whole);
    }

    #[test]
    fn flip_in_strips_of_the_differing_box_equals_one_call_on_the_whole_frame() {
        assert_eq!(flip_support(), 10);
        let mut rng = Rng(11);
        let (w, h) = (150usize, 400usize);
        let noise: Vec<u8> = (0..3 * w * h).map(|_| (rng.next() * 256.0) as u8).collect();
        // Differences over the whole frame, in a box away from the edges, in a box touching a
        // corner, in one pixel; and none.
        let boxes = [
            (0, 0, w, h),
            (40, 70, 90, 300),
            (0, 350, 30, h),
            (77, 77, 78, 78),
            (0, 0, 0, 0),
        ];
        for (bx0, by0, bx1, by1) in boxes {
            let mut test = noise.clone();
            for y in by0..by1 {
                for x in bx0..bx1 {
                    for c in 0..3 {
                        test[3 * (y * w + x) + c] = (rng.next() * 256.0) as u8;
                    }
                }
            }
            let whole = flip_whole(&test, &noise, w as u32, h as u32);
            for strips in [1, 2, 3] {
                let got = flip_map_in_strips(&test, &noise, w as u32, h as u32, strips);
                let at = whole
                    .iter()
                    .zip(&got)
                    .position(|(a, b)| a.to_bits() != b.to_bits());
                assert_eq!(at, None, "box {:?}, {strips} strips", (bx0, by0, bx1, by1));
            }
        }
    }

    #[test]
    fn the_gaussian_window_is_normalized_and_symmetric() {
        let g = gaussian();
        assert!((g.iter().sum::<f64>() - 1.0).abs() < 1e-15);
        assert_eq!(g[0], g[10]);
        assert!(g[5] > g[4] && g[4] > g[3]);
    }

    #[test]
    fn identical_frames_score_flip_0_and_ssim_1() {
        let mut rng = Rng(7);
        let (w, h) = (40, 30);
        let frame: Vec<f32> = (0..4 * w * h).map(|_| rng.next()).collect();
        let depth = vec![0.5; w * h];
        let (e, map) = compare_perceptual(&frame, &frame, &depth, w as u32, h as u32);
        assert_eq!(e.flip, 0.0);
        assert!((e.ssim - 1.0).abs() < 1e-12, "{}", e.ssim);
        assert!(map.iter().all(|&v| v == 0.0));
    }

    #[test]
    fn ssim_of_two_flat_images_is_the_luminance_term() {
        // No variance anywhere: SSIM = (2 μa μb + C1) / (μa² + μb² + C1), with μ the grey level
        // (the luma weights sum to 1). 128 and 64 in 8-bit: μ = 128/255, 64/255.
        let (w, h) = (11, 11);
        let a = vec![128.0 / 255.0; w * h];
        let b = vec![64.0 / 255.0; w * h];
        let map = ssim_map(&a, &b, w, h);
        let (ma, mb) = (128.0 / 255.0f64, 64.0 / 255.0f64);
        let expected = (2.0 * ma * mb + 1e-4) / (ma * ma + mb * mb + 1e-4);
        // One window fits an 11×11 image: its centre.
        assert_eq!(map.iter().filter(|v| v.is_some()).count(), 1);
        let centre = map[5 * w + 5].unwrap();
        assert!((centre - expected).abs() < 1e-9, "{centre} vs {expected}");
        assert!((expected - 0.800_063_48).abs() < 1e-8);
    }

    #[test]
    fn ssim_matches_a_hand_checked_structure_case() {
        // One 11×11 window: `a` is 0 with a single 1 at the centre, `b` is flat 0. Gaussian
        // weight at the centre w0 = g[5]²: μa = w0, σa² = w0 − w0², μb = σb = σab = 0:
        // SSIM = (C1 / (w0² + C1)) · (C2 / (σa² + C2)).
        let (w, h) = (11, 11);
        let mut a = vec![0.0; w * h];
        a[5 * w + 5] = 1.0;
        let b = vec![0.0; w * h];
        let g = gaussian();
        let w0 = g[5] * g[5];
        let (c1, c2) = (1e-4, 9e-4);
        let expected = (c1 / (w0 * w0 + c1)) * (c2 / (w0 - w0 * w0 + c2));
        let got = ssim_map(&a, &b, w, h)[5 * w + 5].unwrap();
        assert!((got - expected).abs() < 1e-12, "{got} vs {expected}");
        // w0 = (1 / Σ e^{-x²/4.5})² ≈ 0.0707: the value is small but not 0.
        assert!((w0 - 0.070_7).abs() < 1e-3, "{w0}");
    }

    #[test]
    fn ssim_matches_scikit_image() {
        // scikit-image 0.25 `structural_similarity(a, b, data_range=1.0, gaussian_weights=True,
        // sigma=1.5, use_sample_covariance=False, full=True)` (Wang et al.'s settings) on these
        // two 24×20 patterns: mean 0.6724511909587587 over the pixels 5 or more from the border,
        // 0.7560734984461062 at (x 5, y 5), 0.6487660553830494 at (x 12, y 10).
        let (w, h) = (24, 20);
        let a: Vec<f64> = (0..w * h)
            .map(|i| ((i % w * 7 + i / w * 13) % 17) as f64 / 16.0)
            .collect();
        let b: Vec<f64> = (0..w * h)
            .map(|i| 0.5 * ((i % w * 5 + i / w * 3) % 11) as f64 / 10.0 + 0.5 * a[i])
            .collect();
        let map = ssim_map(&a, &b, w, h);
        let valid: Vec<f64> = map.iter().flatten().copied().collect();
        assert_eq!(valid.len(), (w - 10) * (h - 10));
        let mean = valid.iter().sum::<f64>() / valid.len() as f64;
        assert!((mean - 0.672_451_190_958_758_7).abs() < 1e-12, "{mean}");
        assert!((map[5 * w + 5].unwrap() - 0.756_073_498_446_106_2).abs() < 1e-12);
        assert!((map[10 * w + 12].unwrap() - 0.648_766_055_383_049_4).abs() < 1e-12);
    }

    #[test]
    fn only_covered_pixels_count() {
        // Left half covered and identical, right half background and very different: ꟻLIP 0 and
        // SSIM 1 over the covered pixels, away from the edge between them (ꟻLIP and SSIM look at
        // neighbours).
        let (w, h) = (64, 32);
        let reference = grey(w, h, 0.5);
        let mut frame = reference.clone();
        let mut depth = vec![1.0; w * h];
        for y in 0..h {
            for x in 0..w {
                if x < 16 {
                    depth[y * w + x] = 0.5;
                } else if x >= 40 {
                    frame[4 * (y * w + x)] = 1.0;
                }
            }
        }
        let (e, map) = compare_perceptual(&frame, &reference, &depth, w as u32, h as u32);
        assert_eq!(e.flip, 0.0);
        assert!((e.ssim - 1.0).abs() < 1e-12);
        assert!(map[w - 1] > 0.1, "the background differs: {}", map[w - 1]);
        // Nothing covered: the neutral values.
        let (e, _) = compare_perceptual(&frame, &reference, &vec![1.0; w * h], w as u32, h as u32);
        assert_eq!((e.flip, e.ssim), (0.0, 1.0));
    }

    #[test]
    fn more_noise_scores_worse() {
        let mut rng = Rng(99);
        let (w, h) = (48, 48);
        let reference: Vec<f32> = (0..4 * w * h).map(|_| 0.2 + 0.1 * rng.next()).collect();
        let noisy = |amp: f32, rng: &mut Rng| -> Vec<f32> {
            reference
                .iter()
                .map(|&v| v + amp * (rng.next() - 0.5))
                .collect()
        };
        let depth = vec![0.0; w * h];
        let (small, _) = compare_perceptual(
            &noisy(0.05, &mut rng),
            &reference,
            &depth,
            w as u32,
            h as u32,
        );
        let (large, _) = compare_perceptual(
            &noisy(0.5, &mut rng),
            &reference,
            &depth,
            w as u32,
            h as u32,
        );
        assert!(
            0.0 < small.flip && small.flip < large.flip,
            "{small:?} {large:?}"
        );
        assert!(
            1.0 > small.ssim && small.ssim > large.ssim,
            "{small:?} {large:?}"
        );
    }
}
