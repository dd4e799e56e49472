//! Drawing the charts with plotters: which chart, on which backend (SVG, or RGB pixels with
//! [`GlyphBitmap`]'s text, skipped when no font file was found). Each chart's drawing lives in its
//! own module over the primitives of [`crate::style`]; this module only dispatches.

use plotters::coord::Shift;
use plotters::prelude::*;

use crate::font::Fonts;
use crate::glyph::GlyphBitmap;
use crate::models::Models;
use crate::style::{DrawResult, Theme};
use crate::{HitRate, Tradeoff};

/// What to draw.
#[derive(Debug, Clone)]
pub(crate) enum Chart {
    Tradeoff(Tradeoff),
    HitRate(HitRate),
    Models(Models),
}

/// The chart as an SVG document.
pub(crate) fn render_svg(chart: &Chart, size: (u32, u32)) -> Result<String, String> {
    let mut svg = String::new();
    {
        let root = SVGBackend::with_string(&mut svg, size).into_drawing_area();
        draw(&root, chart, &Theme).map_err(|e| e.to_string())?;
        root.present().map_err(|e| e.to_string())?;
    }
    Ok(svg)
}

/// The chart as RGB8 pixels, text drawn with `fonts` (none: no text).
pub(crate) fn render_rgb(
    chart: &Chart,
    size: (u32, u32),
    fonts: Option<&Fonts>,
) -> Result<Vec<u8>, String> {
    let mut rgb = vec![255u8; size.0 as usize * size.1 as usize * 3];
    {
        let backend = GlyphBitmap::new(BitMapBackend::with_buffer(&mut rgb, size), fonts);
        let root = backend.into_drawing_area();
        draw(&root, chart, &Theme).map_err(|e| e.to_string())?;
        root.present().map_err(|e| e.to_string())?;
    }
    Ok(rgb)
}

/// Draw `chart` on `root`: a dispatch to the chart's own module.
pub(crate) fn draw<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    chart: &Chart,
    theme: &Theme,
) -> DrawResult
where
    DB::ErrorType: 'static,
{
    root.fill(&WHITE)?;
    match chart {
        Chart::Tradeoff(t) => crate::tradeoff::tradeoff(root, t, theme),
        Chart::HitRate(h) => crate::hitrate::hit_rate(root, h, theme),
        Chart::Models(m) => crate::models::draw(root, m, theme),
    }
}
