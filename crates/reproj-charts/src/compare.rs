//! The equal-time comparison chart of `reproj compare` (the paper's Fig. 10 as numbers): error
//! against measured speedup, one series per method (reduced resolution, code simplification,
//! reprojection), the target speedup as a dashed line. Its data and its drawing live here.

use plotters::coord::Shift;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, VPos};

use crate::style::{
    Axes, DrawResult, Sample, Theme, at, color, formatter, header, legend_row, mesh_style,
};
use crate::{ChartError, Png, encode_png, font};

/// One measured point of one method.
#[derive(Debug, Clone, PartialEq)]
pub struct ComparePoint {
    /// Measured speedup over the original (original frame time / method's frame time).
    pub speedup: f64,
    /// Mean per-pixel L2 error against the original.
    pub error: f64,
}

/// One method's points, in the order they were tried; the last is the one reported.
#[derive(Debug, Clone, PartialEq)]
pub struct CompareSeries {
    pub method: String,
    pub points: Vec<ComparePoint>,
}

/// What the chart shows.
#[derive(Debug, Clone, PartialEq)]
pub struct Compare {
    pub title: String,
    pub subtitle: String,
    /// The speedup every method aims at.
    pub target: f64,
    pub series: Vec<CompareSeries>,
}

const SIZE: (u32, u32) = (900, 600);

/// The chart as an SVG document and as a PNG (with the font warnings of [`crate::Png`]).
pub fn compare_chart(data: &Compare) -> Result<(String, Png), ChartError> {
    let draw_err = |message: String| ChartError::Draw {
        chart: "compare",
        message,
    };
    let mut svg = String::new();
    {
        let root = SVGBackend::with_string(&mut svg, SIZE).into_drawing_area();
        draw(&root, data, &Theme).map_err(|e| draw_err(e.to_string()))?;
        root.present().map_err(|e| draw_err(e.to_string()))?;
    }
    let font = font::font();
    let mut rgb = vec![255u8; SIZE.0 as usize * SIZE.1 as usize * 3];
    {
        let backend = crate::glyph::GlyphBitmap::new(
            BitMapBackend::with_buffer(&mut rgb, SIZE),
            font.fonts.as_ref(),
        );
        let root = backend.into_drawing_area();
        draw(&root, data, &Theme).map_err(|e| draw_err(e.to_string()))?;
        root.present().map_err(|e| draw_err(e.to_string()))?;
    }
    let bytes = encode_png(&rgb, SIZE).map_err(|message| ChartError::Png {
        path: "compare.png".into(),
        message,
    })?;
    Ok((
        svg,
        Png {
            bytes,
            size: SIZE,
            warnings: font.warnings.clone(),
        },
    ))
}

fn draw<DB: DrawingBackend>(root: &DrawingArea<DB, Shift>, c: &Compare, theme: &Theme) -> DrawResult
where
    DB::ErrorType: 'static,
{
    root.fill(&WHITE)?;
    header(root, &c.title, &c.subtitle, theme)?;
    let (_, body) = root.split_vertically(64);
    let points = || c.series.iter().flat_map(|s| s.points.iter());
    let finite = |v: f64| v.is_finite().then_some(v);
    let x_hi = points()
        .filter_map(|p| finite(p.speedup))
        .chain([c.target])
        .fold(1.0f64, f64::max)
        * 1.15;
    let y_hi = points()
        .filter_map(|p| finite(p.error))
        .fold(0.0f64, f64::max)
        .max(1e-6)
        * 1.15;
    let mut chart = ChartBuilder::on(&body)
        .margin_top(6)
        .margin_left(8)
        .margin_right(24)
        .margin_bottom(8)
        .x_label_area_size(48)
        .y_label_area_size(80)
        .build_cartesian_2d(0.0..x_hi, 0.0..y_hi)?;
    let x_fmt = formatter(0.0, x_hi);
    let y_fmt = formatter(0.0, y_hi);
    mesh_style(
        &mut chart,
        theme,
        &Axes {
            x_desc: "measured speedup over the original (×)",
            y_desc: "mean per-pixel L2 error",
            x_fmt: &x_fmt,
            y_fmt: &y_fmt,
            labels: (10, 10),
            label_size: 13.0,
            y_light_lines: 2,
        },
    )?;
    chart.draw_series(DashedLineSeries::new(
        vec![(c.target, 0.0), (c.target, y_hi)],
        6,
        5,
        RGBColor(0x60, 0x60, 0x60).stroke_width(1),
    ))?;
    for (i, s) in c.series.iter().enumerate() {
        let col = color(i);
        let pts: Vec<(f64, f64)> = s
            .points
            .iter()
            .filter(|p| p.speedup.is_finite() && p.error.is_finite())
            .map(|p| (p.speedup, p.error))
            .collect();
        chart.draw_series(LineSeries::new(pts.clone(), col.mix(0.5).stroke_width(1)))?;
        chart.draw_series(
            pts.iter()
                .map(|&p| Circle::new(p, 3, col.mix(0.5).filled())),
        )?;
        if let Some(&last) = pts.last() {
            chart.draw_series(std::iter::once(
                EmptyElement::at(last)
                    + Circle::new((0, 0), 6, col.filled())
                    + Text::new(
                        s.method.clone(),
                        (8, -4),
                        at(&theme.style(13.0, col, true), HPos::Left, VPos::Bottom),
                    ),
            ))?;
        }
    }
    let area = chart.plotting_area().strip_coord_spec();
    for (i, s) in c.series.iter().enumerate() {
        legend_row(
            &area,
            (16, 16 + 20 * i as i32),
            Sample::Line {
                color: color(i),
                width: 2,
                marker: true,
            },
            &s.method,
            &theme.text(13.0),
        )?;
    }
    Ok(())
}
