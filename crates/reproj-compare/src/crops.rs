//! Side-by-side crops (the insets of the paper's Fig. 10): the same square of the middle frame
//! for the reference and each method, in `compare.json`'s `crops.order`, enlarged by pixel
//! replication to at least 128 pixels; below each method, its per-pixel L2 error as the replay's
//! heat map (`output::heat`, the scale of `render`'s error maps). 4 white pixels between panels.

use reproj_replay::metrics::pixel_errors;
use reproj_replay::output::{frame_to_rgba8, heat};
use serde::{Deserialize, Serialize};

use crate::CompareError;

/// Where the crops were taken.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct CropRegion {
    /// Frame index.
    pub frame: u32,
    /// Top-left corner, full-resolution pixels.
    pub x: u32,
    pub y: u32,
    /// Side of the square, pixels.
    pub size: u32,
}

const GAP: usize = 4;

/// A square of half the shorter side, centered on the covered pixels' centroid (the frame's
/// center when nothing is covered), inside the frame.
pub fn region(width: u32, height: u32, depth: &[f32], frame: u32) -> CropRegion {
    let size = (width.min(height) / 2).max(1);
    let (mut sx, mut sy, mut n) = (0u64, 0u64, 0u64);
    for (i, &d) in depth.iter().enumerate() {
        if d < 1.0 {
            sx += (i as u64) % u64::from(width);
            sy += (i as u64) / u64::from(width);
            n += 1;
        }
    }
    let (cx, cy) = match (sx.checked_div(n), sy.checked_div(n)) {
        (Some(x), Some(y)) => (x as u32, y as u32),
        _ => (width / 2, height / 2),
    };
    CropRegion {
        frame,
        x: cx.saturating_sub(size / 2).min(width - size),
        y: cy.saturating_sub(size / 2).min(height - size),
        size,
    }
}

/// The crops PNG of `frames` (name, RGBA f32 full frame; the reference first).
pub fn crops_png(
    frames: &[(String, Vec<f32>)],
    [width, _]: [u32; 2],
    r: &CropRegion,
) -> Result<Vec<u8>, CompareError> {
    let size = r.size as usize;
    let zoom = 128usize.div_ceil(size).max(1);
    let side = size * zoom;
    let n = frames.len();
    let out_w = n * side + (n - 1) * GAP;
    let out_h = 2 * side + GAP;
    let mut img = vec![255u8; out_w * out_h * 4];
    let reference = &frames[0].1;
    for (k, (_, frame)) in frames.iter().enumerate() {
        let srgb = frame_to_rgba8(frame);
        let errors = pixel_errors(frame, reference);
        for y in 0..side {
            for x in 0..side {
                let (fx, fy) = (r.x as usize + x / zoom, r.y as usize + y / zoom);
                let i = fy * width as usize + fx;
                let ox = k * (side + GAP) + x;
                let top = (y * out_w + ox) * 4;
                img[top..top + 4].copy_from_slice(&srgb[i * 4..i * 4 + 4]);
                let bottom = ((y + side + GAP) * out_w + ox) * 4;
                img[bottom..bottom + 4].copy_from_slice(&heat(errors[i]));
            }
        }
    }
    let mut bytes = Vec::new();
    use image::ImageEncoder;
    image::codecs::png::PngEncoder::new(&mut bytes)
        .write_image(
            &img,
            out_w as u32,
            out_h as u32,
            image::ExtendedColorType::Rgba8,
        )
        .map_err(|e| CompareError::Internal {
            what: "cannot encode crops.png".into(),
            message: e.to_string(),
        })?;
    Ok(bytes)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_region_is_centered_on_the_covered_pixels_and_stays_inside() {
        let (w, h) = (8u32, 8u32);
        let mut depth = vec![1.0f32; 64];
        depth[7 * 8 + 7] = 0.5;
        let r = region(w, h, &depth, 3);
        assert_eq!((r.x, r.y, r.size, r.frame), (4, 4, 4, 3));
        let r = region(w, h, &[1.0; 64], 0);
        assert_eq!((r.x, r.y), (2, 2));
    }

    #[test]
    fn crops_are_laid_out_side_by_side_with_error_maps_below() {
        let a = vec![0.5f32; 16 * 16 * 4];
        let frames = vec![("reference".to_string(), a.clone()), ("x".into(), a)];
        let r = region(16, 16, &[0.5; 256], 0);
        let png = crops_png(&frames, [16, 16], &r).unwrap();
        let img = image::load_from_memory(&png).unwrap();
        assert_eq!(
            (img.width(), img.height()),
            (2 * 128 + GAP as u32, 2 * 128 + GAP as u32)
        );
    }
}
