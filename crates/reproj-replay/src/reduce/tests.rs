//! The GPU reduction against the CPU's: the same sums, the same NaN counts.

use super::*;

use super::noise::Rng;

/// Reduce `frame` against `reference` on the GPU, through slot 1 of a two-slot reducer.
fn gpu(r: &Gpu, w: u32, h: u32, frame: &[f32], reference: &[f32], depth: &[f32]) -> FrameError {
    let refr = GpuReference::upload(r, w, h, &[reference.to_vec()], &[depth.to_vec()]).unwrap();
    let ones = vec![1.0; (w * h) as usize];
    let var = GpuReference::upload(r, w, h, &[frame.to_vec()], &[ones]).unwrap();
    let kernel = Kernel::new(r).unwrap();
    let red = Reducer::new(r, kernel, Cow::Borrowed(&refr), w, h, 2).unwrap();
    let mut enc = r.device.create_command_encoder(&Default::default());
    red.encode(r, &mut enc, &var.frames[0].color, 0, 1).unwrap();
    r.queue.submit([enc.finish()]);
    r.map_read(&[red.read_buffer()]).unwrap();
    let e = red.read(1).unwrap();
    Gpu::unmap_all(&[red.read_buffer()]);
    e
}

fn close(a: f64, b: f64) -> bool {
    a == b || (a - b).abs() <= 1e-5 * a.abs().max(b.abs())
}

#[test]
fn gpu_sums_equal_the_cpu_sums() {
    let r = Gpu::open(None, false).expect("a Vulkan adapter (lavapipe)");
    let mut rng = Rng(0x1234_5678);
    // Not a multiple of the tile: partial tiles at the right and bottom edges. Colors in
    // [-0.5, 1.5) (clamping matters), a third of the pixels uncovered.
    for (w, h) in [(70, 37), (256, 256), (1, 1)] {
        let (frame, reference, depth) = rng.frames((w * h) as usize, -0.5, 2.0, 0.2);
        let cpu = l2::compare(&frame, &reference, &depth);
        let g = gpu(&r, w, h, &frame, &reference, &depth);
        assert_eq!((g.pixels, g.covered), (cpu.pixels, cpu.covered), "{w}×{h}");
        assert_eq!(g.max_abs_diff, cpu.max_abs_diff, "{w}×{h}");
        assert!(close(g.sum_l2, cpu.sum_l2), "{w}×{h}: {g:?} vs {cpu:?}");
        assert!(close(g.sum_sq, cpu.sum_sq), "{w}×{h}: {g:?} vs {cpu:?}");
    }
}

#[test]
fn gpu_nan_matches_the_cpu() {
    let r = Gpu::open(None, false).expect("a Vulkan adapter (lavapipe)");
    let reference = vec![0.5f32; 4 * 4];
    let depth = [0.5, 1.0, 0.5, 1.0];
    // A NaN in an uncovered pixel's green: the L2 sum is NaN, the covered squares are not.
    let mut frame = reference.clone();
    frame[4 + 1] = f32::NAN;
    frame[8] = 0.75;
    let cpu = l2::compare(&frame, &reference, &depth);
    let g = gpu(&r, 2, 2, &frame, &reference, &depth);
    assert!(cpu.sum_l2.is_nan() && g.sum_l2.is_nan());
    assert_eq!(g.sum_sq, cpu.sum_sq);
    assert_eq!(g.max_abs_diff, f64::INFINITY);
    assert_eq!(cpu.max_abs_diff, f64::INFINITY);
    // In a covered pixel: both NaN.
    frame[1] = f32::NAN;
    let g = gpu(&r, 2, 2, &frame, &reference, &depth);
    assert!(g.sum_sq.is_nan() && l2::compare(&frame, &reference, &depth).sum_sq.is_nan());
    assert_eq!((g.nonfinite, g.nonfinite_reference), (2, 0));
}

#[test]
fn gpu_counts_nonfinite_pixels_as_the_cpu_and_leaves_the_reference_s_out() {
    let r = Gpu::open(None, false).expect("a Vulkan adapter (lavapipe)");
    let mut reference = vec![0.5f32; 4 * 4];
    let depth = [0.5, 0.5, 0.5, 1.0];
    let mut frame = reference.clone();
    frame[0] = 0.25;
    // The reference's own NaN (pixel 1) and +inf (pixel 2): left out, whatever the frame has.
    reference[4] = f32::NAN;
    reference[8 + 2] = f32::INFINITY;
    frame[4] = f32::NAN;
    let cpu = l2::compare(&frame, &reference, &depth);
    let g = gpu(&r, 2, 2, &frame, &reference, &depth);
    assert_eq!((g.nonfinite, g.nonfinite_reference), (0, 2));
    assert_eq!((cpu.nonfinite, cpu.nonfinite_reference), (0, 2));
    assert_eq!((g.covered, cpu.covered), (1, 1));
    assert!(
        close(g.sum_l2, cpu.sum_l2) && close(g.sum_l2, 0.25),
        "{g:?}"
    );
    // The mean is over the two pixels that could be measured.
    assert!(close(g.error(), 0.125) && close(cpu.error(), 0.125));
    // An infinity in the frame where the reference is finite: counted, and the error is NaN.
    frame[12 + 1] = f32::NEG_INFINITY;
    let cpu = l2::compare(&frame, &reference, &depth);
    let g = gpu(&r, 2, 2, &frame, &reference, &depth);
    assert_eq!((g.nonfinite, cpu.nonfinite), (1, 1));
    assert!(g.error().is_nan() && cpu.error().is_nan());
}
