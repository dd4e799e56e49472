//! The primitives every chart draws with: the palette and text styles, the header, axis spans,
//! number formats, the mesh, legend rows and boxes, and centred notes.
//!
//! Layout is in fixed pixels: we never ask plotters to measure text (no `caption`, no series-label
//! box), so SVG and PNG look alike and neither needs a font to be laid out.

use std::error::Error;

use plotters::coord::Shift;
use plotters::coord::types::RangedCoordf64;
use plotters::element::DashedPathElement;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};

use crate::font::FAMILY;

/// What drawing a chart returns.
pub(crate) type DrawResult = Result<(), Box<dyn Error>>;

/// Node colors (Tableau 10 without its grey, then three more).
pub(crate) const PALETTE: [RGBColor; 12] = [
    RGBColor(0x1f, 0x77, 0xb4),
    RGBColor(0xff, 0x7f, 0x0e),
    RGBColor(0x2c, 0xa0, 0x2c),
    RGBColor(0xd6, 0x27, 0x28),
    RGBColor(0x94, 0x67, 0xbd),
    RGBColor(0x8c, 0x56, 0x4b),
    RGBColor(0xe3, 0x77, 0xc2),
    RGBColor(0xbc, 0xbd, 0x22),
    RGBColor(0x17, 0xbe, 0xcf),
    RGBColor(0x39, 0x3b, 0x79),
    RGBColor(0xb8, 0x86, 0x0b),
    RGBColor(0x63, 0x79, 0x39),
];
pub(crate) const INK: RGBColor = RGBColor(0x20, 0x20, 0x20);
pub(crate) const MUTED: RGBColor = RGBColor(0x60, 0x60, 0x60);
pub(crate) const GREY: RGBColor = RGBColor(0xa8, 0xa8, 0xa8);
pub(crate) const GRID_LIGHT: RGBColor = RGBColor(0xf0, 0xf0, 0xf0);
pub(crate) const GRID_BOLD: RGBColor = RGBColor(0xdc, 0xdc, 0xdc);
pub(crate) const WARN: RGBColor = RGBColor(0xb0, 0x30, 0x20);

pub(crate) fn color(i: usize) -> RGBColor {
    PALETTE[i % PALETTE.len()]
}

/// Text styles.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Theme;

impl Theme {
    pub(crate) fn style(&self, size: f64, color: RGBColor, bold: bool) -> TextStyle<'static> {
        let font = if bold {
            (FAMILY, size).into_font().style(FontStyle::Bold)
        } else {
            (FAMILY, size).into_font()
        };
        font.color(&color)
    }
    pub(crate) fn text(&self, size: f64) -> TextStyle<'static> {
        self.style(size, INK, false)
    }
    pub(crate) fn muted(&self, size: f64) -> TextStyle<'static> {
        self.style(size, MUTED, false)
    }
    pub(crate) fn bold(&self, size: f64) -> TextStyle<'static> {
        self.style(size, INK, true)
    }
}

pub(crate) fn at(style: &TextStyle<'static>, h: HPos, v: VPos) -> TextStyle<'static> {
    style.pos(Pos::new(h, v))
}

/// Title and subtitle centered at the top of `root`.
pub(crate) fn header<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    title: &str,
    subtitle: &str,
    theme: &Theme,
) -> DrawResult
where
    DB::ErrorType: 'static,
{
    let w = root.dim_in_pixel().0 as i32;
    root.draw_text(
        title,
        &at(&theme.bold(21.0), HPos::Center, VPos::Top),
        (w / 2, 10),
    )?;
    root.draw_text(
        subtitle,
        &at(&theme.muted(14.0), HPos::Center, VPos::Top),
        (w / 2, 38),
    )?;
    Ok(())
}

// ---------------------------------------------------------------------------------------------
// Axis ranges and labels.

/// A non-empty range covering the finite `values`, padded by `pad` of its width on each side;
/// `default` when there is none. A zero-width range is widened around its value (10 % of it, or
/// half of `default`'s width at 0). `non_negative`: never below 0 when no value is.
pub(crate) fn span(
    values: impl IntoIterator<Item = f64>,
    default: (f64, f64),
    pad: f64,
    non_negative: bool,
) -> (f64, f64) {
    let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
    for v in values.into_iter().filter(|v| v.is_finite()) {
        lo = lo.min(v);
        hi = hi.max(v);
    }
    if !(lo.is_finite() && hi.is_finite()) {
        return default;
    }
    let data_lo = lo;
    let width = hi - lo;
    let scale = lo.abs().max(hi.abs());
    if width <= scale * 1e-6 {
        let center = (lo + hi) / 2.0;
        let half = if center.abs() > 1e-300 {
            center.abs() * 0.1
        } else {
            (default.1 - default.0) / 2.0
        };
        lo = center - half;
        hi = center + half;
    } else {
        lo -= width * pad;
        hi += width * pad;
    }
    if non_negative && data_lo >= 0.0 && lo < 0.0 {
        lo = 0.0;
    }
    if hi > lo && (hi - lo).is_finite() {
        (lo, hi)
    } else {
        default
    }
}

/// Tick labels rounded to the axis' resolution, trailing zeros trimmed; scientific notation for
/// axes whose values are all tiny or huge.
pub(crate) fn formatter(lo: f64, hi: f64) -> impl Fn(&f64) -> String {
    let magnitude = lo.abs().max(hi.abs());
    let scientific = magnitude > 0.0 && !(1e-4..1e6).contains(&magnitude);
    let decimals = (-((hi - lo) / 20.0).log10()).ceil().clamp(0.0, 9.0) as usize;
    move |v: &f64| {
        if scientific {
            sci(*v)
        } else {
            let s = format!("{:.*}", decimals, v);
            let s = if s.contains('.') {
                s.trim_end_matches('0').trim_end_matches('.').to_string()
            } else {
                s
            };
            if s == "-0" { "0".to_string() } else { s }
        }
    }
}

/// `2.5e-4`, `1e-3`.
pub(crate) fn sci(v: f64) -> String {
    if v == 0.0 {
        return "0".to_string();
    }
    let s = format!("{v:.1e}");
    s.replace(".0e", "e")
}

/// A value of a log axis (`v` = log10 of it): `0.001`, `0.02`, `1e-5`.
pub(crate) fn log_label(v: &f64) -> String {
    let x = 10f64.powf(*v);
    if (1e-4..1e4).contains(&x) {
        let digits = (3.0 - x.log10().floor()).clamp(0.0, 7.0) as usize;
        let s = format!("{:.*}", digits, x);
        if s.contains('.') {
            s.trim_end_matches('0').trim_end_matches('.').to_string()
        } else {
            s
        }
    } else {
        sci(x)
    }
}

/// How errors are placed on the y axis of the trade-off chart.
#[derive(Debug, Clone, Copy)]
pub(crate) enum YScale {
    Linear,
    /// log10, values below `floor` (zeros) drawn at `floor`.
    Log {
        floor: f64,
    },
}

impl YScale {
    pub(crate) fn map(self, e: f64) -> f64 {
        match self {
            YScale::Linear => e,
            YScale::Log { floor } => e.max(floor).log10(),
        }
    }
}

/// A tick-label formatter.
pub(crate) type Fmt<'a> = &'a dyn Fn(&f64) -> String;
/// A linear f64 × f64 chart.
pub(crate) type Chart2d<'a, DB> = ChartContext<'a, DB, Cartesian2d<RangedCoordf64, RangedCoordf64>>;

/// How to draw a chart's axes.
pub(crate) struct Axes<'a> {
    pub(crate) x_desc: &'a str,
    pub(crate) y_desc: &'a str,
    pub(crate) x_fmt: Fmt<'a>,
    pub(crate) y_fmt: Fmt<'a>,
    /// Most labels on x and y.
    pub(crate) labels: (usize, usize),
    pub(crate) label_size: f64,
    /// Light grid lines between two y labels.
    pub(crate) y_light_lines: usize,
}

pub(crate) fn mesh_style<DB: DrawingBackend>(
    chart: &mut Chart2d<'_, DB>,
    theme: &Theme,
    axes: &Axes<'_>,
) -> DrawResult
where
    DB::ErrorType: 'static,
{
    chart
        .configure_mesh()
        .x_desc(axes.x_desc)
        .y_desc(axes.y_desc)
        .axis_desc_style(theme.text(axes.label_size + 2.0))
        .label_style(theme.text(axes.label_size))
        .x_labels(axes.labels.0)
        .y_labels(axes.labels.1)
        .x_label_formatter(axes.x_fmt)
        .y_label_formatter(axes.y_fmt)
        .x_max_light_lines(2)
        .y_max_light_lines(axes.y_light_lines)
        .light_line_style(GRID_LIGHT)
        .bold_line_style(GRID_BOLD)
        .axis_style(MUTED)
        .draw()?;
    Ok(())
}

/// A legend row: a sample of the line/marker at `(x, y)` (vertical center), then the label.
#[derive(Debug, Clone, Copy)]
pub(crate) enum Sample {
    Line {
        color: RGBColor,
        width: u32,
        marker: bool,
    },
    Dashed {
        color: RGBColor,
        width: u32,
        dash: i32,
        gap: i32,
    },
    Dot {
        color: RGBColor,
        filled: bool,
    },
    Cross {
        color: RGBColor,
    },
    Ring {
        color: RGBColor,
    },
}

pub(crate) fn legend_row<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    (x, y): (i32, i32),
    sample: Sample,
    label: &str,
    style: &TextStyle<'static>,
) -> DrawResult
where
    DB::ErrorType: 'static,
{
    let (x0, x1) = (x, x + 26);
    match sample {
        Sample::Line {
            color,
            width,
            marker,
        } => {
            area.draw(&PathElement::new(
                vec![(x0, y), (x1, y)],
                color.stroke_width(width),
            ))?;
            if marker {
                area.draw(&Circle::new(((x0 + x1) / 2, y), 3, color.filled()))?;
            }
        }
        Sample::Dashed {
            color,
            width,
            dash,
            gap,
        } => {
            area.draw(&DashedPathElement::new(
                vec![(x0, y), (x1, y)],
                dash,
                gap,
                color.stroke_width(width),
            ))?;
        }
        Sample::Dot { color, filled } => {
            let style = if filled {
                color.filled()
            } else {
                color.stroke_width(2)
            };
            area.draw(&Circle::new(((x0 + x1) / 2, y), 4, style))?;
        }
        Sample::Cross { color } => {
            area.draw(&Cross::new(((x0 + x1) / 2, y), 4, color.stroke_width(2)))?;
        }
        Sample::Ring { color } => {
            area.draw(&Circle::new(((x0 + x1) / 2, y), 7, color.stroke_width(2)))?;
        }
    }
    area.draw_text(label, &at(style, HPos::Left, VPos::Center), (x1 + 8, y))?;
    Ok(())
}

/// Legend rows in a white box with a thin border; `(x, y)` is the top-left corner.
pub(crate) fn legend_box<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    (x, y): (i32, i32),
    width: i32,
    rows: &[(Sample, String)],
    theme: &Theme,
) -> DrawResult
where
    DB::ErrorType: 'static,
{
    let row_h = 20;
    let h = rows.len() as i32 * row_h + 10;
    area.draw(&Rectangle::new(
        [(x, y), (x + width, y + h)],
        WHITE.mix(0.9).filled(),
    ))?;
    area.draw(&Rectangle::new(
        [(x, y), (x + width, y + h)],
        GRID_BOLD.stroke_width(1),
    ))?;
    let style = theme.text(13.0);
    for (i, (sample, label)) in rows.iter().enumerate() {
        legend_row(
            area,
            (x + 10, y + 15 + i as i32 * row_h),
            *sample,
            label,
            &style,
        )?;
    }
    Ok(())
}

/// Text in the middle of a chart's plotting area (e.g. "no data").
pub(crate) fn note_center<DB: DrawingBackend, CT: CoordTranslate>(
    area: &DrawingArea<DB, CT>,
    lines: &[&str],
    theme: &Theme,
) -> DrawResult
where
    DB::ErrorType: 'static,
{
    let (xr, yr) = area.get_pixel_range();
    let (w, h) = (xr.end - xr.start, yr.end - yr.start);
    let root = area.strip_coord_spec();
    let style = at(&theme.style(15.0, WARN, false), HPos::Center, VPos::Center);
    let n = lines.len() as i32;
    for (i, line) in lines.iter().enumerate() {
        root.draw_text(line, &style, (w / 2, h / 2 + (2 * i as i32 - (n - 1)) * 11))?;
    }
    Ok(())
}

pub(crate) fn plural(n: usize) -> &'static str {
    if n == 1 { "" } else { "s" }
}

/// Milliseconds with 3 significant digits or 2 decimals.
pub(crate) fn fmt_ms(ms: f64) -> String {
    if ms >= 100.0 {
        format!("{ms:.0}")
    } else if ms >= 10.0 {
        format!("{ms:.1}")
    } else {
        format!("{ms:.2}")
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn spans_are_never_empty() {
        assert_eq!(span([], (0.0, 1.0), 0.1, true), (0.0, 1.0));
        let (lo, hi) = span([0.0, 0.0], (0.0, 0.01), 0.1, true);
        assert!(lo == 0.0 && hi > 0.0);
        let (lo, hi) = span([5.0], (0.0, 1.0), 0.1, true);
        assert!(lo < 5.0 && hi > 5.0);
        let (lo, hi) = span([1e6, 1e6 + 1e-9], (0.0, 1.0), 0.1, true);
        assert!(lo < 1e6 && hi > 1e6);
        let (lo, hi) = span([f64::NAN, 2.0, 4.0], (0.0, 1.0), 0.0, false);
        assert_eq!((lo, hi), (2.0, 4.0));
    }

    #[test]
    fn labels() {
        let f = formatter(0.0, 1.0);
        assert_eq!(f(&0.30000000000000004), "0.3");
        assert_eq!(f(&0.0), "0");
        let f = formatter(0.0, 2e-5);
        assert_eq!(f(&1e-5), "1e-5");
        assert_eq!(log_label(&-2.0), "0.01");
        assert_eq!(log_label(&-5.0), "1e-5");
        assert_eq!(fmt_ms(12.345), "12.3");
    }
}
