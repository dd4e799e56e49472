//! Chart 3, model validation (paper Fig. 6), as small multiples: for every usable node (every node
//! with measurements when none is usable), predicted vs measured error and frame time over Δn, held-out
//! Δn marked apart. Four nodes per row; each node is an error panel above a time panel.

use std::collections::{BTreeMap, BTreeSet};

use plotters::coord::Shift;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, VPos};
use reproj_models::profile::{Measurement, NodeProfile, NodeStatus};
use reproj_models::{Profile, predicted_frame_ms};
use reproj_select::DEFAULT_MAX_DELTA_N;

use crate::style::{
    Axes, DrawResult, INK, MUTED, Sample, Theme, WARN, at, color, formatter, header, legend_row,
    mesh_style, span,
};
use crate::{finite_pos, node_label, setting, shader_name, truncate, usable};

/// Width of the chart, pixels.
const WIDTH: u32 = 1200;
/// Nodes per row.
const COLUMNS: usize = 4;
/// Height of the header and legend, pixels.
const HEAD: u32 = 88;
/// Height of one node's two panels, pixels.
const ROW: u32 = 592;

/// One node of chart 3 (Fig. 6).
#[derive(Debug, Clone)]
pub(crate) struct ModelPanel {
    pub(crate) label: String,
    pub(crate) color: usize,
    /// `(Δn, value, held out)`.
    pub(crate) error_measured: Vec<(f64, f64, bool)>,
    pub(crate) error_curve: Vec<(f64, f64)>,
    /// Why there is no error curve.
    pub(crate) error_note: Option<String>,
    pub(crate) time_measured: Vec<(f64, f64, bool)>,
    pub(crate) time_curve: Vec<(f64, f64)>,
    pub(crate) time_note: Option<String>,
}

/// Chart 3 (Fig. 6).
#[derive(Debug, Clone)]
pub(crate) struct Models {
    pub(crate) title: String,
    pub(crate) subtitle: String,
    pub(crate) panels: Vec<ModelPanel>,
    pub(crate) original_ms: Option<f64>,
    pub(crate) max_delta_n: f64,
}

/// The nodes shown: every usable one (every one with measurements when none is usable), in
/// increasing static cost.
fn model_nodes(profile: &Profile) -> Vec<&NodeProfile> {
    let with: Vec<&NodeProfile> = profile
        .nodes
        .iter()
        .filter(|n| n.measurements.iter().any(usable))
        .collect();
    let ok: Vec<&NodeProfile> = with
        .iter()
        .copied()
        .filter(|n| n.status == NodeStatus::Ok)
        .collect();
    let mut pool = if ok.is_empty() { with } else { ok };
    pool.sort_by(|a, b| a.cost.total_cmp(&b.cost).then(a.id.cmp(&b.id)));
    pool
}

/// The chart's size in pixels: one row of panels per [`COLUMNS`] nodes.
pub(crate) fn size(m: &Models) -> (u32, u32) {
    let rows = m.panels.len().div_ceil(COLUMNS).max(1) as u32;
    (WIDTH, HEAD + rows * ROW)
}

/// `colors`: palette index of the nodes that have one in the trade-off chart.
pub(crate) fn models(profile: &Profile, colors: &BTreeMap<u32, usize>) -> Models {
    let train: BTreeSet<u32> = profile.delta_n_train.iter().copied().collect();
    let holdout: BTreeSet<u32> = profile.delta_n_holdout.iter().copied().collect();
    let is_held = |dn: u32| holdout.contains(&dn) && !train.contains(&dn);
    let nodes = model_nodes(profile);
    let max_dn = nodes
        .iter()
        .flat_map(|n| n.measurements.iter().map(|m| m.delta_n))
        .max()
        .unwrap_or(0)
        .max(DEFAULT_MAX_DELTA_N);
    let grid: Vec<f64> = (0..=200)
        .map(|i| 1.0 + (f64::from(max_dn) - 1.0) * f64::from(i) / 200.0)
        .collect();
    let mean_pixels = profile.original.mean_pixels;
    let mut next_color = colors.values().max().map_or(0, |c| c + 1);
    let panels = nodes
        .iter()
        .map(|n| {
            let color = colors.get(&n.id).copied().unwrap_or_else(|| {
                next_color += 1;
                next_color - 1
            });
            let ms: Vec<&Measurement> = n.measurements.iter().filter(|m| usable(m)).collect();
            let error_curve: Vec<(f64, f64)> = grid
                .iter()
                .filter_map(|&dn| {
                    n.error_fit
                        .predict(dn)
                        .filter(|e| e.is_finite())
                        .map(|e| (dn, e))
                })
                .collect();
            let time_curve: Vec<(f64, f64)> = grid
                .iter()
                .filter_map(|&dn| {
                    predicted_frame_ms(&n.timing_fit, &profile.hit_rate, dn, mean_pixels)
                        .filter(|t| t.is_finite())
                        .map(|t| (dn, t))
                })
                .collect();
            let error_note = match (&n.error_fit.status, error_curve.is_empty()) {
                (reproj_models::ErrorFitStatus::Failed { reason }, _) => {
                    Some(truncate(&format!("error fit failed: {reason}"), 60))
                }
                (_, true) => Some("no error model".to_string()),
                _ => None,
            };
            let time_note = if time_curve.is_empty() {
                Some(if n.timing_fit.is_usable() {
                    "no hit-rate model: no prediction".to_string()
                } else {
                    "timing fit not usable".to_string()
                })
            } else {
                None
            };
            ModelPanel {
                label: node_label(n, 30),
                color,
                error_measured: ms
                    .iter()
                    .map(|m| (f64::from(m.delta_n), m.error, is_held(m.delta_n)))
                    .collect(),
                error_curve,
                error_note,
                time_measured: ms
                    .iter()
                    .map(|m| (f64::from(m.delta_n), m.frame_ms, is_held(m.delta_n)))
                    .collect(),
                time_curve,
                time_note,
            }
        })
        .collect();
    Models {
        title: format!("Model validation — {}", shader_name(profile)),
        subtitle: setting(profile),
        panels,
        original_ms: finite_pos(profile.original.frame_ms),
        max_delta_n: f64::from(max_dn),
    }
}

/// Draw the chart.
pub(crate) fn draw<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    m: &Models,
    theme: &Theme,
) -> DrawResult
where
    DB::ErrorType: 'static,
{
    header(root, &m.title, &m.subtitle, theme)?;
    // Legend line under the header.
    let (w, _) = root.dim_in_pixel();
    let rows = [
        (
            Sample::Line {
                color: INK,
                width: 2,
                marker: false,
            },
            "model prediction",
        ),
        (
            Sample::Dot {
                color: INK,
                filled: true,
            },
            "measured (training Δn)",
        ),
        (Sample::Cross { color: INK }, "measured (held-out Δn)"),
        (
            Sample::Dashed {
                color: MUTED,
                width: 1,
                dash: 6,
                gap: 5,
            },
            "original shader",
        ),
    ];
    let style = theme.text(13.0);
    let item_w = 230;
    let start = (w as i32 - item_w * rows.len() as i32) / 2;
    for (i, (sample, label)) in rows.iter().enumerate() {
        legend_row(
            root,
            (start + i as i32 * item_w, 72),
            *sample,
            label,
            &style,
        )?;
    }
    let (_, body) = root.split_vertically(HEAD);
    let cols = m.panels.len().clamp(1, COLUMNS);
    let rows = m.panels.len().div_ceil(COLUMNS).max(1);
    let areas = body.split_evenly((2 * rows, cols));
    if m.panels.is_empty() {
        let empty = ModelPanel {
            label: String::new(),
            color: 0,
            error_measured: Vec::new(),
            error_curve: Vec::new(),
            error_note: Some("no node has measurements".to_string()),
            time_measured: Vec::new(),
            time_curve: Vec::new(),
            time_note: Some("no node has measurements".to_string()),
        };
        panel(
            &areas[0],
            &empty,
            Quantity::Error,
            None,
            m.max_delta_n,
            theme,
        )?;
        panel(
            &areas[1],
            &empty,
            Quantity::Time,
            m.original_ms,
            m.max_delta_n,
            theme,
        )?;
        return Ok(());
    }
    for (i, p) in m.panels.iter().enumerate() {
        let (row, col) = (i / cols, i % cols);
        let error = 2 * row * cols + col;
        panel(
            &areas[error],
            p,
            Quantity::Error,
            None,
            m.max_delta_n,
            theme,
        )?;
        panel(
            &areas[error + cols],
            p,
            Quantity::Time,
            m.original_ms,
            m.max_delta_n,
            theme,
        )?;
    }
    Ok(())
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Quantity {
    Error,
    Time,
}

fn panel<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    p: &ModelPanel,
    q: Quantity,
    original_ms: Option<f64>,
    max_delta_n: f64,
    theme: &Theme,
) -> DrawResult
where
    DB::ErrorType: 'static,
{
    let c = color(p.color);
    let (measured, curve, note, desc) = match q {
        Quantity::Error => (
            &p.error_measured,
            &p.error_curve,
            &p.error_note,
            "error (L2 RGB)",
        ),
        Quantity::Time => (
            &p.time_measured,
            &p.time_curve,
            &p.time_note,
            "frame time (ms)",
        ),
    };
    let (pw, _) = area.dim_in_pixel();
    let top = if q == Quantity::Error { 24 } else { 6 };
    if q == Quantity::Error {
        area.draw_text(
            &p.label,
            &at(&theme.style(13.5, c, true), HPos::Center, VPos::Top),
            (pw as i32 / 2, 4),
        )?;
    }
    let x1 = max_delta_n.max(2.0) * 1.04;
    let ys = measured
        .iter()
        .map(|v| v.1)
        .chain(curve.iter().map(|v| v.1))
        .chain(original_ms.filter(|_| q == Quantity::Time));
    let default = if q == Quantity::Error {
        (0.0, 0.01)
    } else {
        (0.0, 1.0)
    };
    let (y0, y1) = span(ys, default, 0.08, true);
    let mut chart = ChartBuilder::on(area)
        .margin_top(top)
        .margin_left(4)
        .margin_right(14)
        .margin_bottom(6)
        .x_label_area_size(38)
        .y_label_area_size(64)
        .build_cartesian_2d(0.0..x1, y0..y1)?;
    let x_fmt = formatter(0.0, x1);
    let y_fmt = formatter(y0, y1);
    mesh_style(
        &mut chart,
        theme,
        &Axes {
            x_desc: "Δn",
            y_desc: desc,
            x_fmt: &x_fmt,
            y_fmt: &y_fmt,
            labels: (6, 6),
            label_size: 12.0,
            y_light_lines: 2,
        },
    )?;
    if let Some(orig) = original_ms.filter(|_| q == Quantity::Time) {
        chart.draw_series(DashedLineSeries::new(
            vec![(0.0, orig), (x1, orig)],
            6,
            5,
            MUTED.stroke_width(1),
        ))?;
    }
    if !curve.is_empty() {
        chart.draw_series(LineSeries::new(curve.iter().copied(), c.stroke_width(2)))?;
    }
    chart.draw_series(
        measured
            .iter()
            .filter(|v| !v.2)
            .map(|v| Circle::new((v.0, v.1), 4, c.filled())),
    )?;
    chart.draw_series(
        measured
            .iter()
            .filter(|v| v.2)
            .map(|v| Cross::new((v.0, v.1), 5, INK.stroke_width(2))),
    )?;
    if let Some(note) = note {
        let (xr, yr) = chart.plotting_area().get_pixel_range();
        let base = area.get_base_pixel();
        area.draw_text(
            note,
            &at(&theme.style(12.0, WARN, false), HPos::Left, VPos::Top),
            (xr.start - base.0 + 6, yr.start - base.1 + 6),
        )?;
    }
    Ok(())
}
