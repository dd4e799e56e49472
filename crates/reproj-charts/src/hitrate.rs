//! Chart 2: measured hit rate vs Δn and the fitted `µ(1 − 1/Δn)` (the paper's Fig. 5).

use plotters::coord::Shift;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, VPos};

use crate::HitRate;
use crate::style::DrawResult;
use crate::style::*;

pub(crate) fn hit_rate<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    h: &HitRate,
    theme: &Theme,
) -> DrawResult
where
    DB::ErrorType: 'static,
{
    header(root, &h.title, &h.subtitle, theme)?;
    let (_, body) = root.split_vertically(64);
    let x1 = h.max_delta_n.max(2.0) * 1.03;
    let mut chart = ChartBuilder::on(&body)
        .margin_top(6)
        .margin_left(8)
        .margin_right(24)
        .margin_bottom(8)
        .x_label_area_size(48)
        .y_label_area_size(70)
        .build_cartesian_2d(0.0..x1, 0.0..1.05)?;
    let x_fmt = formatter(0.0, x1);
    let y_fmt = formatter(0.0, 1.05);
    mesh_style(
        &mut chart,
        theme,
        &Axes {
            x_desc: "refresh period Δn (frames)",
            y_desc: "hit rate (hits / shaded pixels)",
            x_fmt: &x_fmt,
            y_fmt: &y_fmt,
            labels: (12, 11),
            label_size: 13.0,
            y_light_lines: 2,
        },
    )?;
    let train_color = PALETTE[0];
    let held_color = PALETTE[1];
    let fit_color = PALETTE[3];
    if let Some(mu) = h.mu {
        let curve: Vec<(f64, f64)> = (0..=400)
            .map(|i| 1.0 + (x1 - 1.0) * f64::from(i) / 400.0)
            .map(|dn| (dn, mu * (1.0 - 1.0 / dn)))
            .collect();
        chart.draw_series(LineSeries::new(curve, fit_color.stroke_width(2)))?;
        chart.draw_series(DashedLineSeries::new(
            vec![(0.0, mu), (x1, mu)],
            6,
            5,
            fit_color.mix(0.6).stroke_width(1),
        ))?;
        chart.draw_series(std::iter::once(
            EmptyElement::at((x1, mu))
                + Text::new(
                    format!("µ = {mu:.3}"),
                    (-6, -4),
                    at(
                        &theme.style(13.0, fit_color, true),
                        HPos::Right,
                        VPos::Bottom,
                    ),
                ),
        ))?;
    }
    chart.draw_series(
        h.train
            .iter()
            .map(|&p| Circle::new(p, 4, train_color.mix(0.55).filled())),
    )?;
    chart.draw_series(
        h.holdout
            .iter()
            .map(|&p| Circle::new(p, 5, held_color.stroke_width(2))),
    )?;
    if h.train.is_empty() && h.holdout.is_empty() {
        note_center(
            chart.plotting_area(),
            &["no hit-rate measurements in this profile"],
            theme,
        )?;
    }
    let mut rows = Vec::new();
    if !h.train.is_empty() {
        rows.push((
            Sample::Dot {
                color: train_color,
                filled: true,
            },
            "measured, training Δn (one per node)".to_string(),
        ));
    }
    if !h.holdout.is_empty() {
        rows.push((
            Sample::Dot {
                color: held_color,
                filled: false,
            },
            "measured, held-out Δn".to_string(),
        ));
    }
    if h.mu.is_some() {
        rows.push((
            Sample::Line {
                color: fit_color,
                width: 2,
                marker: false,
            },
            "model µ(1 − 1/Δn)".to_string(),
        ));
    }
    if !rows.is_empty() {
        let (xr, yr) = chart.plotting_area().get_pixel_range();
        let (bx, by) = (xr.end - 330, yr.end - 20 - (rows.len() as i32 * 20 + 10));
        legend_box(root, (bx, by), 320, &rows, theme)?;
    }
    Ok(())
}
