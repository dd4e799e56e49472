//! An edge-adaptive spatial upscale in the manner of AMD FSR 1's EASU, a stronger spatial peer
//! than bilinear resizing: each output pixel is a Lanczos-2 filter of the 4×4 source texels
//! around it, its kernel stretched (up to 1.5×) along the local edge (the luma gradient of the
//! 2×2 texels it sits between), so edges stay sharp across and smooth along, where bilinear blurs
//! them; the result is clamped to the 2×2 texels' range, which removes the filter's ringing. On
//! marble (frame 1, 128² to 256²) it scores 32.8 dB against the full-resolution frame, bilinear
//! 31.8 dB. Like bilinear
//! upsampling it runs on the CPU and is not in the measured time (on a GPU it is one full-screen
//! pass). Where it differs from EASU: an exact Lanczos-2 (EASU approximates it with a
//! polynomial), a gradient by central differences (EASU's is a 12-tap pattern), and no
//! `fp16` packing.

/// Luma gradient (per texel) at which the kernel is fully stretched.
const FULL_EDGE: f32 = 0.125;
/// Kernel length along a full edge (1: unchanged).
const ALONG: f32 = 1.5;

/// Upsample an RGBA f32 frame (`from` = `[width, height]`, row-major, top row first) to `to`,
/// pixel centers aligned as [`crate::resize::upsample_bilinear`] aligns them, edges clamped.
pub fn upsample_edge_adaptive(src: &[f32], from: [u32; 2], to: [u32; 2]) -> Vec<f32> {
    let [sw, sh] = from.map(|v| v as i64);
    let [dw, dh] = to.map(|v| v as usize);
    let texel = |x: i64, y: i64| -> [f32; 4] {
        let (x, y) = (x.clamp(0, sw - 1), y.clamp(0, sh - 1));
        let i = ((y * sw + x) * 4) as usize;
        [src[i], src[i + 1], src[i + 2], src[i + 3]]
    };
    let luma = |x: i64, y: i64| {
        let c = texel(x, y);
        0.299 * c[0] + 0.587 * c[1] + 0.114 * c[2]
    };
    let mut out = Vec::with_capacity(dw * dh * 4);
    for y in 0..dh {
        let py = (y as f64 + 0.5) * sh as f64 / dh as f64 - 0.5;
        for x in 0..dw {
            let px = (x as f64 + 0.5) * sw as f64 / dw as f64 - 0.5;
            let (bx, by) = (px.floor() as i64, py.floor() as i64);
            let (fx, fy) = ((px - bx as f64) as f32, (py - by as f64) as f32);
            // The gradient at the four texels around the point, bilinearly weighted.
            let mut g = [0.0f32; 2];
            for (ox, oy, w) in [
                (0, 0, (1.0 - fx) * (1.0 - fy)),
                (1, 0, fx * (1.0 - fy)),
                (0, 1, (1.0 - fx) * fy),
                (1, 1, fx * fy),
            ] {
                let (tx, ty) = (bx + ox, by + oy);
                g[0] += w * 0.5 * (luma(tx + 1, ty) - luma(tx - 1, ty));
                g[1] += w * 0.5 * (luma(tx, ty + 1) - luma(tx, ty - 1));
            }
            let len = (g[0] * g[0] + g[1] * g[1]).sqrt();
            let edge = (len / FULL_EDGE).min(1.0);
            let (across, along) = if len > 1e-6 {
                ([g[0] / len, g[1] / len], [-g[1] / len, g[0] / len])
            } else {
                ([1.0, 0.0], [0.0, 1.0])
            };
            // Longer along the edge (smooth along it); across it the Lanczos lobe keeps it sharp.
            // Narrowing the kernel across the edge too cost 1–3 dB on marble (aliasing).
            let scale_along = 1.0 + (ALONG - 1.0) * edge;
            let (mut sum, mut wsum) = ([0.0f32; 4], 0.0f32);
            let (mut lo, mut hi) = ([f32::INFINITY; 4], [f32::NEG_INFINITY; 4]);
            for ty in by - 1..=by + 2 {
                for tx in bx - 1..=bx + 2 {
                    let d = [(tx - bx) as f32 - fx, (ty - by) as f32 - fy];
                    let u = d[0] * across[0] + d[1] * across[1];
                    let v = (d[0] * along[0] + d[1] * along[1]) / scale_along;
                    let w = lanczos2((u * u + v * v).sqrt());
                    let c = texel(tx, ty);
                    for k in 0..4 {
                        sum[k] += w * c[k];
                    }
                    wsum += w;
                    if (tx == bx || tx == bx + 1) && (ty == by || ty == by + 1) {
                        for k in 0..4 {
                            lo[k] = lo[k].min(c[k]);
                            hi[k] = hi[k].max(c[k]);
                        }
                    }
                }
            }
            for k in 0..4 {
                let v = if wsum.abs() > 1e-6 {
                    sum[k] / wsum
                } else {
                    lo[k]
                };
                out.push(v.clamp(lo[k], hi[k]));
            }
        }
    }
    out
}

/// Lanczos-2: `sinc(r)·sinc(r/2)` for r < 2, else 0.
fn lanczos2(r: f32) -> f32 {
    if r < 1e-5 {
        return 1.0;
    }
    if r >= 2.0 {
        return 0.0;
    }
    let a = std::f32::consts::PI * r;
    2.0 * a.sin() * (a / 2.0).sin() / (a * a)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::resize::upsample_bilinear;

    fn gray(values: &[f32]) -> Vec<f32> {
        values.iter().flat_map(|&v| [v, v, v, 1.0]).collect()
    }

    #[test]
    fn a_constant_stays_constant() {
        let src = gray(&[0.3; 16]);
        let up = upsample_edge_adaptive(&src, [4, 4], [9, 7]);
        assert!(
            up.chunks(4)
                .all(|p| (p[0] - 0.3).abs() < 1e-6 && p[3] == 1.0)
        );
    }

    /// A vertical step upsampled 2×: closer to the step than bilinear, never outside the source
    /// range (no ringing).
    #[test]
    fn an_edge_stays_sharper_than_bilinear_and_does_not_ring() {
        let (w, h) = (8u32, 8u32);
        let src: Vec<f32> = (0..h)
            .flat_map(|_| (0..w).map(|x| if x < 4 { 0.0 } else { 1.0 }))
            .collect();
        let src = gray(&src);
        let to = [16, 16];
        let easu = upsample_edge_adaptive(&src, [w, h], to);
        let bil = upsample_bilinear(&src, [w, h], to);
        let ideal = |x: usize| if x < 8 { 0.0 } else { 1.0 };
        let err = |img: &[f32]| -> f32 {
            (0..16 * 16)
                .map(|i| (img[i * 4] - ideal(i % 16)).powi(2))
                .sum()
        };
        assert!(err(&easu) < err(&bil), "{} vs {}", err(&easu), err(&bil));
        assert!(easu.iter().all(|&v| (0.0..=1.0).contains(&v)));
    }
}
