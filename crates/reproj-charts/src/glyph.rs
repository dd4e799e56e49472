//! A bitmap backend that draws its own text with ab_glyph.
//!
//! plotters' bitmap text (its `ab_glyph` feature) places glyphs without their side bearings and
//! needs fonts registered in a global table; this wrapper forwards every shape to plotters'
//! `BitMapBackend` and lays text out itself: advances and kerning, a real baseline, the same
//! anchors and font size as the SVG backend (`font-size = size / 1.24`, top anchor at 0.76 em
//! above the baseline), rotation by quarter turns. Without a font, text is skipped.

use ab_glyph::{Font, FontVec, Glyph, PxScale, ScaleFont, point};
use plotters::prelude::{BitMapBackend, DrawingBackend};
use plotters_backend::text_anchor::{HPos, VPos};
use plotters_backend::{
    BackendColor, BackendCoord, BackendStyle, BackendTextStyle, DrawingErrorKind, FontStyle,
};

use crate::font::Fonts;

/// `BitMapBackend` with ab_glyph text.
pub(crate) struct GlyphBitmap<'a> {
    inner: BitMapBackend<'a>,
    fonts: Option<&'a Fonts>,
}

impl std::fmt::Debug for GlyphBitmap<'_> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("GlyphBitmap")
            .field("size", &self.inner.get_size())
            .field("fonts", &self.fonts)
            .finish()
    }
}

impl<'a> GlyphBitmap<'a> {
    pub(crate) fn new(inner: BitMapBackend<'a>, fonts: Option<&'a Fonts>) -> Self {
        Self { inner, fonts }
    }

    fn face(&self, style: FontStyle) -> Option<&'a FontVec> {
        let fonts = self.fonts?;
        Some(match style {
            FontStyle::Bold => fonts.bold.as_ref().unwrap_or(&fonts.regular),
            _ => &fonts.regular,
        })
    }
}

/// Glyphs of one line of text on a baseline at y = 0 from x = 0.
struct Line {
    glyphs: Vec<Glyph>,
    width: f32,
    height: f32,
}

/// The em size in pixels of a plotters text size (as the SVG backend writes `font-size`).
fn em(size: f64) -> f32 {
    (size / 1.24).max(1.0) as f32
}

fn layout(font: &FontVec, em: f32, text: &str) -> Line {
    let units = font.units_per_em().unwrap_or(1000.0).max(1.0);
    let scale = PxScale::from(em * font.height_unscaled() / units);
    let scaled = font.as_scaled(scale);
    let mut caret = 0.0f32;
    let mut prev = None;
    let mut glyphs = Vec::with_capacity(text.len());
    for c in text.chars() {
        let id = scaled.glyph_id(c);
        if let Some(p) = prev {
            caret += scaled.kern(p, id);
        }
        glyphs.push(id.with_scale_and_position(scale, point(caret, 0.0)));
        caret += scaled.h_advance(id);
        prev = Some(id);
    }
    Line {
        glyphs,
        width: caret,
        height: scaled.ascent() - scaled.descent(),
    }
}

type Error<'a> = DrawingErrorKind<<BitMapBackend<'a> as DrawingBackend>::ErrorType>;

impl<'a> DrawingBackend for GlyphBitmap<'a> {
    type ErrorType = <BitMapBackend<'a> as DrawingBackend>::ErrorType;

    fn get_size(&self) -> (u32, u32) {
        self.inner.get_size()
    }

    fn ensure_prepared(&mut self) -> Result<(), Error<'a>> {
        self.inner.ensure_prepared()
    }

    fn present(&mut self) -> Result<(), Error<'a>> {
        self.inner.present()
    }

    fn draw_pixel(&mut self, point: BackendCoord, color: BackendColor) -> Result<(), Error<'a>> {
        self.inner.draw_pixel(point, color)
    }

    fn draw_line<S: BackendStyle>(
        &mut self,
        from: BackendCoord,
        to: BackendCoord,
        style: &S,
    ) -> Result<(), Error<'a>> {
        self.inner.draw_line(from, to, style)
    }

    fn draw_rect<S: BackendStyle>(
        &mut self,
        upper_left: BackendCoord,
        bottom_right: BackendCoord,
        style: &S,
        fill: bool,
    ) -> Result<(), Error<'a>> {
        self.inner.draw_rect(upper_left, bottom_right, style, fill)
    }

    fn draw_path<S: BackendStyle, I: IntoIterator<Item = BackendCoord>>(
        &mut self,
        path: I,
        style: &S,
    ) -> Result<(), Error<'a>> {
        self.inner.draw_path(path, style)
    }

    fn draw_circle<S: BackendStyle>(
        &mut self,
        center: BackendCoord,
        radius: u32,
        style: &S,
        fill: bool,
    ) -> Result<(), Error<'a>> {
        self.inner.draw_circle(center, radius, style, fill)
    }

    fn fill_polygon<S: BackendStyle, I: IntoIterator<Item = BackendCoord>>(
        &mut self,
        vert: I,
        style: &S,
    ) -> Result<(), Error<'a>> {
        self.inner.fill_polygon(vert, style)
    }

    fn blit_bitmap(
        &mut self,
        pos: BackendCoord,
        size: (u32, u32),
        src: &[u8],
    ) -> Result<(), Error<'a>> {
        self.inner.blit_bitmap(pos, size, src)
    }

    fn draw_text<TStyle: BackendTextStyle>(
        &mut self,
        text: &str,
        style: &TStyle,
        pos: BackendCoord,
    ) -> Result<(), Error<'a>> {
        let color = style.color();
        let Some(font) = self.face(style.style()) else {
            return Ok(());
        };
        if color.alpha <= 0.0 || text.is_empty() {
            return Ok(());
        }
        let em = em(style.size());
        let line = layout(font, em, text);
        let anchor = style.anchor();
        let dx = match anchor.h_pos {
            HPos::Left => 0.0,
            HPos::Center => -line.width / 2.0,
            HPos::Right => -line.width,
        };
        let baseline = match anchor.v_pos {
            VPos::Top => 0.76 * em,
            VPos::Center => 0.36 * em,
            VPos::Bottom => -0.24 * em,
        };
        let mut coverage: Vec<(i32, i32, f32)> = Vec::new();
        for mut glyph in line.glyphs {
            glyph.position.x += dx;
            glyph.position.y += baseline;
            if let Some(outline) = font.outline_glyph(glyph) {
                let bounds = outline.px_bounds();
                let (bx, by) = (bounds.min.x as i32, bounds.min.y as i32);
                outline.draw(|x, y, c| {
                    if c > 0.0 {
                        coverage.push((bx + x as i32, by + y as i32, c.min(1.0)));
                    }
                });
            }
        }
        let trans = style.transform();
        for (x, y, c) in coverage {
            let (x, y) = trans.transform(x, y);
            self.inner.draw_pixel(
                (pos.0 + x, pos.1 + y),
                BackendColor {
                    alpha: color.alpha * f64::from(c),
                    rgb: color.rgb,
                },
            )?;
        }
        Ok(())
    }

    fn estimate_text_size<TStyle: BackendTextStyle>(
        &self,
        text: &str,
        style: &TStyle,
    ) -> Result<(u32, u32), Error<'a>> {
        let em = em(style.size());
        Ok(match self.face(style.style()) {
            Some(font) => {
                let line = layout(font, em, text);
                (line.width.ceil() as u32, line.height.ceil() as u32)
            }
            None => (
                (0.6 * em * text.chars().count() as f32).ceil() as u32,
                em.ceil() as u32,
            ),
        })
    }
}
