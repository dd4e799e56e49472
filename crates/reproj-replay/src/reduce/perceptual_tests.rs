//! The GPU's ꟻLIP and SSIM against the CPU's (NVIDIA's reference code and `reproj-metrics`' SSIM):
//! the same means to f32 rounding, on noise, edges, flat and tiny frames, with uncovered pixels.

use super::*;
use crate::reduce::GpuReference;
use reproj_metrics::perceptual::compare_perceptual;

use crate::reduce::noise::Rng;

/// Score `frame` against `reference` on the GPU, through slot 1 of a two-slot scorer.
fn gpu(
    r: &Gpu,
    w: u32,
    h: u32,
    frame: &[f32],
    reference: &[f32],
    depth: &[f32],
) -> PerceptualError {
    let refr = GpuReference::upload(r, w, h, &[reference.to_vec()], &[depth.to_vec()]).unwrap();
    let ones = vec![1.0; (w * h) as usize];
    let var = GpuReference::upload(r, w, h, &[frame.to_vec()], &[ones]).unwrap();
    let scorer = GpuPerceptual::new(r, PerceptualKernel::new(r).unwrap(), w, h, 2).unwrap();
    let mut enc = r.device.create_command_encoder(&Default::default());
    scorer.encode(r, &mut enc, &var.frames[0].color, &refr.frames[0], 1);
    r.queue.submit([enc.finish()]);
    r.map_read(&[scorer.read_buffer()]).unwrap();
    let e = scorer.read(1).unwrap();
    Gpu::unmap_all(&[scorer.read_buffer()]);
    r.check_errors("the perceptual test").unwrap();
    e
}

/// The GPU's means are the CPU's to f32 rounding (and the odd pixel whose 8-bit sRGB value a
/// GPU's `pow` rounds the other way).
fn assert_close(w: u32, h: u32, frame: &[f32], reference: &[f32], depth: &[f32], what: &str) {
    let r = Gpu::open(None, false).expect("a Vulkan adapter (lavapipe)");
    let g = gpu(&r, w, h, frame, reference, depth);
    let (c, _) = compare_perceptual(frame, reference, depth, w, h);
    assert!(
        (g.flip - c.flip).abs() <= 1e-5 + 1e-4 * c.flip,
        "{what} ({w}×{h}) ꟻLIP: GPU {} CPU {}",
        g.flip,
        c.flip
    );
    assert!(
        (g.ssim - c.ssim).abs() <= 1e-4,
        "{what} ({w}×{h}) SSIM: GPU {} CPU {}",
        g.ssim,
        c.ssim
    );
}

/// A frame of smooth colour with a few hard edges (a disc and a bar), as shaded frames are.
fn shapes(w: u32, h: u32, shift: f32) -> Vec<f32> {
    let mut out = Vec::with_capacity((4 * w * h) as usize);
    for y in 0..h {
        for x in 0..w {
            let (u, v) = (x as f32 / w as f32, y as f32 / h as f32);
            let disc = ((u - 0.5 - shift).powi(2) + (v - 0.5).powi(2)).sqrt() < 0.25;
            let bar = (u * 8.0 + shift * 8.0).fract() < 0.1;
            let base = [0.2 + 0.6 * u, 0.3 * v, 0.5 + 0.4 * (6.0 * u).sin() * v];
            let c = if disc {
                [0.9, 0.8, 0.1]
            } else if bar {
                [0.05, 0.05, 0.6]
            } else {
                base
            };
            out.extend(c);
            out.push(1.0);
        }
    }
    out
}

#[test]
fn gpu_perceptual_metrics_equal_the_reference_code_s_on_noise() {
    let mut rng = Rng(0x2468_ace1);
    // Not a multiple of the tile (partial tiles at the right and bottom edges); colours in
    // [-0.25, 1.25) (the clamp matters); a third of the pixels uncovered.
    for (w, h) in [(70, 37), (128, 96)] {
        let (frame, reference, depth) = rng.frames((w * h) as usize, -0.25, 1.5, 0.3);
        assert_close(w, h, &frame, &reference, &depth, "noise");
    }
}

#[test]
fn gpu_perceptual_metrics_equal_the_reference_code_s_on_edges_and_flat_frames() {
    let (w, h) = (160, 120);
    let px = (w * h) as usize;
    let covered = vec![0.5; px];
    let reference = shapes(w, h, 0.0);
    // Shapes moved by a pixel or two: errors along the edges only.
    assert_close(
        w,
        h,
        &shapes(w, h, 0.01),
        &reference,
        &covered,
        "moved edges",
    );
    // Identical: ꟻLIP 0 exactly; SSIM 1 to f32 rounding (the window's variances and covariance
    // are sums a driver may fuse differently).
    let r = Gpu::open(None, false).expect("a Vulkan adapter (lavapipe)");
    let same = gpu(&r, w, h, &reference, &reference, &covered);
    assert_eq!(same.flip, 0.0);
    assert!((same.ssim - 1.0).abs() < 2e-5, "{}", same.ssim);
    // Two flat frames: SSIM is the luminance term alone.
    let grey = |v: f32| (0..px).flat_map(|_| [v, v, v, 1.0]).collect::<Vec<f32>>();
    assert_close(w, h, &grey(0.2), &grey(0.3), &covered, "flat");
    // Nothing covered: ꟻLIP 0 and SSIM 1, as on the CPU.
    assert_close(w, h, &grey(0.2), &grey(0.3), &vec![1.0; px], "uncovered");
}

#[test]
fn gpu_perceptual_metrics_handle_frames_smaller_than_the_window_and_non_finite_colours() {
    // 7×5: no SSIM window fits (SSIM 1), ꟻLIP's filters clamp at every edge.
    let (w, h) = (7, 5);
    let px = (w * h) as usize;
    let mut rng = Rng(0x1357_9bdf);
    let reference: Vec<f32> = (0..4 * px).map(|_| rng.next()).collect();
    let mut frame: Vec<f32> = (0..4 * px).map(|_| rng.next()).collect();
    let depth = vec![0.25; px];
    assert_close(w, h, &frame, &reference, &depth, "tiny");
    // NaN and infinities read as the PNGs write them: NaN and −∞ as 0, +∞ as 1.
    frame[0] = f32::NAN;
    frame[5] = f32::INFINITY;
    frame[10] = f32::NEG_INFINITY;
    assert_close(w, h, &frame, &reference, &depth, "non-finite");
}

#[test]
fn the_filters_are_normalized_as_the_reference_code_s() {
    let colour = colour_filter(PIXELS_PER_DEGREE);
    let feature = feature_filter(PIXELS_PER_DEGREE);
    // 10 and 9 pixels of radius at 67 pixels per degree (reproj-metrics' `flip_support`).
    assert_eq!((colour.len(), feature.len()), (21, 19));
    let sum = |taps: &[[f32; 4]], c: usize| taps.iter().map(|t| t[c]).sum::<f32>();
    assert!((sum(&colour, 0) - 1.0).abs() < 1e-5 && (sum(&colour, 1) - 1.0).abs() < 1e-5);
    assert!((sum(&feature, 0) - 1.0).abs() < 1e-5);
    // The derivatives' weights sum to 0 (±1 each side).
    assert!(sum(&feature, 1).abs() < 1e-5 && sum(&feature, 2).abs() < 1e-5);
    assert!((sum(&ssim_window(), 0) - 1.0).abs() < 1e-6);
    let p = params(4, 4).unwrap();
    assert_eq!(p.decode[63][3], 1.0);
    assert_eq!(p.decode[0][0], 0.0);
}
