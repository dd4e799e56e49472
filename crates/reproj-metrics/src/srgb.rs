//! What a viewer sees of a linear frame: clamped to [0, 1], sRGB-encoded, 8 bits. The one
//! encoding the PNGs ([`crate::output`]) and the perceptual metrics (`crate::perceptual`) share, so
//! ꟻLIP and SSIM compare the pixels `render --frames` writes. Imports nothing of the crate.

/// Linear → sRGB transfer function.
pub fn srgb_encode(x: f32) -> f32 {
    let x = x.clamp(0.0, 1.0);
    if x <= 0.003_130_8 {
        12.92 * x
    } else {
        1.055 * x.powf(1.0 / 2.4) - 0.055
    }
}

/// RGBA f32 linear frame → sRGB-encoded RGBA8 (clamped, alpha forced to 255).
pub fn frame_to_rgba8(rgba: &[f32]) -> Vec<u8> {
    rgba.chunks_exact(4)
        .flat_map(|p| {
            [
                (srgb_encode(p[0]) * 255.0 + 0.5) as u8,
                (srgb_encode(p[1]) * 255.0 + 0.5) as u8,
                (srgb_encode(p[2]) * 255.0 + 0.5) as u8,
                255,
            ]
        })
        .collect()
}

/// A linear RGBA f32 frame as the viewer sees it: clamped, sRGB-encoded, 8-bit RGB (no alpha),
/// rounded as [`frame_to_rgba8`] does for PNGs.
pub fn to_srgb8(rgba: &[f32]) -> Vec<u8> {
    rgba.chunks_exact(4)
        .flat_map(|p| [0, 1, 2].map(|c| (srgb_encode(p[c]) * 255.0 + 0.5) as u8))
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn srgb8_rounds_like_the_pngs() {
        let px = [0.0, 0.5, 1.0, 0.3, 2.0, -1.0, 0.0031308, 1.0];
        let rgb = to_srgb8(&px);
        let png = frame_to_rgba8(&px);
        assert_eq!(rgb, [png[0], png[1], png[2], png[4], png[5], png[6]]);
        assert_eq!(&rgb[..3], &[0, 188, 255]);
    }
}
