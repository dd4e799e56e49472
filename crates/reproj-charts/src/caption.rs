//! Text over a picture another crate made (the labels of `reproj compare`'s crops): one line of
//! text centered on a point, drawn into an RGB8 buffer with the charts' PNG font and text styles,
//! so labels and charts look alike. Without a font nothing is drawn and the caller is told.

use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, VPos};

use crate::font::font;
use crate::glyph::GlyphBitmap;
use crate::style::{Theme, at};

/// One line of text, centered horizontally on `x`, its top at `y` (pixels).
#[derive(Debug, Clone, PartialEq)]
pub struct Caption {
    pub x: i32,
    pub y: i32,
    pub text: String,
    /// Text size in plotters' units (the charts use 13–16).
    pub size: f64,
    /// Bold ink; otherwise the charts' muted grey.
    pub bold: bool,
}

/// Draw `captions` into `rgb` (`size.0 × size.1` RGB8 pixels). `Ok(warnings)`: empty when the
/// text was drawn, else why not (no font file: see [`crate::font_path`]).
pub fn draw_captions(
    rgb: &mut [u8],
    size: (u32, u32),
    captions: &[Caption],
) -> Result<Vec<String>, String> {
    let state = font();
    if state.fonts.is_none() {
        let mut w = state.warnings.clone();
        if w.is_empty() {
            w.push("no font found: labels are not drawn".into());
        }
        return Ok(w);
    }
    if rgb.len() != size.0 as usize * size.1 as usize * 3 {
        return Err(format!(
            "caption buffer holds {} bytes, not {}×{}×3",
            rgb.len(),
            size.0,
            size.1
        ));
    }
    let backend = GlyphBitmap::new(BitMapBackend::with_buffer(rgb, size), state.fonts.as_ref());
    let root = backend.into_drawing_area();
    let theme = Theme;
    for c in captions {
        let style = if c.bold {
            theme.bold(c.size)
        } else {
            theme.muted(c.size)
        };
        root.draw_text(&c.text, &at(&style, HPos::Center, VPos::Top), (c.x, c.y))
            .map_err(|e| e.to_string())?;
    }
    root.present().map_err(|e| e.to_string())?;
    Ok(Vec::new())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn captions_ink_pixels_near_their_anchor_only() {
        let (w, h) = (120u32, 40u32);
        let mut rgb = vec![255u8; (w * h * 3) as usize];
        let caption = Caption {
            x: 60,
            y: 10,
            text: "resize".into(),
            size: 16.0,
            bold: true,
        };
        let warnings = draw_captions(&mut rgb, (w, h), &[caption]).unwrap();
        if !warnings.is_empty() {
            // No font on this machine: nothing drawn, and the caller is told.
            assert!(rgb.iter().all(|&b| b == 255));
            return;
        }
        let inked: Vec<(u32, u32)> = (0..h)
            .flat_map(|y| (0..w).map(move |x| (x, y)))
            .filter(|&(x, y)| rgb[((y * w + x) * 3) as usize] < 128)
            .collect();
        assert!(inked.len() > 20, "{} dark pixels", inked.len());
        let (min_x, max_x) = (
            inked.iter().map(|p| p.0).min().unwrap(),
            inked.iter().map(|p| p.0).max().unwrap(),
        );
        // Centered on x = 60 within a few pixels, below the top anchor.
        assert!(
            ((min_x + max_x) as i32 / 2 - 60).abs() <= 3,
            "{min_x}..{max_x}"
        );
        assert!(inked.iter().all(|p| p.1 >= 9), "text above its top");
        assert!(draw_captions(&mut rgb[..3], (w, h), &[]).is_err());
    }
}
