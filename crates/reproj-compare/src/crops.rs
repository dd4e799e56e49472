//! Side-by-side crops (the insets of the paper's Fig. 10): the same square of the middle frame
//! for the reference and each method, in `compare.json`'s `crops.order`, enlarged by pixel
//! replication to at least 128 pixels; below each method, its per-pixel L2 error as the replay's
//! heat map (`output::heat`, the scale of `render`'s error maps). 4 white pixels between panels.
//! Above each, its name and what it measured (speedup, PSNR), in the charts' font.

use reproj_charts::{Caption, draw_captions};
use reproj_metrics::l2::pixel_errors;
use reproj_metrics::output::heat;
use reproj_metrics::srgb::frame_to_rgba8;
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

/// One column of the crops: a full frame and the two caption lines above it.
#[derive(Debug, Clone, PartialEq)]
pub struct Panel<'a> {
    /// `reference` or the method's name (bold).
    pub name: String,
    /// What to read beside it: the measured speedup and PSNR, or the original's frame time.
    pub detail: String,
    /// RGBA f32 full frame.
    pub frame: &'a [f32],
}

/// Height of the caption band above the crops, pixels.
const CAPTION: usize = 40;

/// The crops PNG of `panels` (the reference first) and the warnings of its captions (no font:
/// the crops are drawn without them).
pub fn crops_png(
    panels: &[Panel<'_>],
    [width, _]: [u32; 2],
    r: &CropRegion,
) -> Result<(Vec<u8>, Vec<String>), CompareError> {
    let size = r.size as usize;
    let zoom = 128usize.div_ceil(size).max(1);
    let side = size * zoom;
    let n = panels.len();
    let out_w = n * side + (n - 1) * GAP;
    let out_h = CAPTION + 2 * side + GAP;
    let mut img = vec![255u8; out_w * out_h * 3];
    let reference = panels[0].frame;
    for (k, panel) in panels.iter().enumerate() {
        let srgb = frame_to_rgba8(panel.frame);
        let errors = pixel_errors(panel.frame, reference);
        for y in 0..side {
            for x in 0..side {
                let (fx, fy) = (r.x as usize + x / zoom, r.y as usize + y / zoom);
                let i = fy * width as usize + fx;
                let ox = k * (side + GAP) + x;
                let top = ((CAPTION + y) * out_w + ox) * 3;
                img[top..top + 3].copy_from_slice(&srgb[i * 4..i * 4 + 3]);
                let bottom = ((CAPTION + y + side + GAP) * out_w + ox) * 3;
                img[bottom..bottom + 3].copy_from_slice(&heat(errors[i])[..3]);
            }
        }
    }
    let captions: Vec<Caption> = panels
        .iter()
        .enumerate()
        .flat_map(|(k, p)| {
            let x = (k * (side + GAP) + side / 2) as i32;
            [
                Caption {
                    x,
                    y: 3,
                    text: p.name.clone(),
                    size: 16.0,
                    bold: true,
                },
                Caption {
                    x,
                    y: 21,
                    text: p.detail.clone(),
                    size: 13.0,
                    bold: false,
                },
            ]
        })
        .collect();
    let internal = |what: &str, message: String| CompareError::Internal {
        what: what.into(),
        message,
    };
    let warnings = draw_captions(&mut img, (out_w as u32, out_h as u32), &captions)
        .map_err(|e| internal("cannot label crops.png", e))?;
    let mut bytes = Vec::new();
    use image::ImageEncoder;
    image::codecs::png::PngEncoder::new(&mut bytes)
        .write_image(
            &img,
            out_w as u32,
            out_h as u32,
            image::ExtendedColorType::Rgb8,
        )
        .map_err(|e| internal("cannot encode crops.png", e.to_string()))?;
    Ok((bytes, warnings))
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
        let panel = |name: &str| Panel {
            name: name.into(),
            detail: "1.00×".into(),
            frame: &a,
        };
        let r = region(16, 16, &[0.5; 256], 0);
        let (png, warnings) = crops_png(&[panel("reference"), panel("x")], [16, 16], &r).unwrap();
        let img = image::load_from_memory(&png).unwrap().to_rgb8();
        assert_eq!(
            (img.width(), img.height()),
            (2 * 128 + GAP as u32, (CAPTION + 2 * 128 + GAP) as u32)
        );
        // The caption band is inked when a font is found, and left white otherwise.
        let band_inked = (0..img.width())
            .flat_map(|x| (0..CAPTION as u32).map(move |y| (x, y)))
            .any(|(x, y)| img.get_pixel(x, y)[0] < 128);
        assert_eq!(band_inked, warnings.is_empty());
        // The crop itself starts below the band: mid-grey, not white.
        assert!(img.get_pixel(10, CAPTION as u32 + 10)[0] < 250);
    }
}
