//! Chart 1: error vs frame time per node over Δn (the paper's Fig. 7), the selections at the
//! given budgets ringed and labelled, the predicted Pareto frontier dotted.

use plotters::coord::Shift;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, VPos};

use crate::Tradeoff;
use crate::style::DrawResult;
use crate::style::*;

/// Draw the trade-off chart: the header, the axes from the data's span, the node paths, the
/// frontier and the original's time, the selections, then the legend in its own column.
pub(crate) fn tradeoff<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    t: &Tradeoff,
    theme: &Theme,
) -> DrawResult
where
    DB::ErrorType: 'static,
{
    header(root, &t.title, &t.subtitle, theme)?;
    let (w, _) = root.dim_in_pixel();
    let (_, body) = root.split_vertically(64);
    let legend_w = 300;
    let (plot, legend) = body.split_horizontally(w as i32 - legend_w);
    let frame = Frame::of(t);
    let (x0, x1, y0, y1) = (frame.x.0, frame.x.1, frame.y.0, frame.y.1);
    let mut chart = ChartBuilder::on(&plot)
        .margin_top(6)
        .margin_left(8)
        .margin_right(18)
        .margin_bottom(8)
        .x_label_area_size(48)
        .y_label_area_size(78)
        .build_cartesian_2d(x0..x1, y0..y1)?;
    axes(&mut chart, &frame, theme)?;
    paths(&mut chart, t, &frame, theme)?;
    marks(&mut chart, t, &frame, theme)?;
    if t.paths.is_empty() {
        note_center(
            chart.plotting_area(),
            &["no measurements in this profile", "(no node was replayed)"],
            theme,
        )?;
    }
    draw_legend(&legend, &legend_rows(t), theme)
}

/// The plot's coordinates: the error scale (log when the positive errors span 30× or more) and
/// the x (ms) and y (scaled error) ranges of everything drawn.
struct Frame {
    scale: YScale,
    /// Whether an error is 0 (drawn at the bottom of a log scale).
    has_zero: bool,
    x: (f64, f64),
    y: (f64, f64),
}

impl Frame {
    fn of(t: &Tradeoff) -> Frame {
        let errors: Vec<f64> = t
            .paths
            .iter()
            .flat_map(|p| p.points.iter().map(|q| q.2))
            .chain(t.pareto.iter().map(|p| p.1))
            .collect();
        let positive: Vec<f64> = errors.iter().copied().filter(|e| *e > 0.0).collect();
        let (pmin, pmax) = positive
            .iter()
            .fold((f64::INFINITY, 0.0f64), |(a, b), &e| (a.min(e), b.max(e)));
        let has_zero = errors.iter().any(|e| *e <= 0.0);
        let scale = if positive.len() >= 2 && pmax / pmin >= 30.0 {
            YScale::Log { floor: pmin / 2.0 }
        } else {
            YScale::Linear
        };
        let xs = t
            .paths
            .iter()
            .flat_map(|p| p.points.iter().map(|q| q.1))
            .chain(t.pareto.iter().map(|p| p.0))
            .chain(t.original_ms);
        let x = span(xs, (0.0, 1.0), 0.06, true);
        let y = span(
            errors.iter().map(|e| scale.map(*e)),
            (0.0, 0.01),
            0.06,
            true,
        );
        Frame {
            scale,
            has_zero,
            x,
            y,
        }
    }

    /// A path point `(Δn, ms, error)` in the plot's coordinates.
    fn point(&self, q: &(u32, f64, f64)) -> (f64, f64) {
        (q.1, self.scale.map(q.2))
    }
}

/// The axes, their descriptions and labels (powers of ten on a log scale).
fn axes<DB: DrawingBackend>(chart: &mut Chart2d<'_, DB>, frame: &Frame, theme: &Theme) -> DrawResult
where
    DB::ErrorType: 'static,
{
    let ((x0, x1), (y0, y1)) = (frame.x, frame.y);
    let x_fmt = formatter(x0, x1);
    let lin_fmt = formatter(y0, y1);
    type BoxedFmt = Box<dyn Fn(&f64) -> String>;
    let (y_desc, y_fmt, y_labels): (String, BoxedFmt, usize) = match frame.scale {
        YScale::Linear => (
            "error: mean per-pixel L2 RGB distance".to_string(),
            Box::new(lin_fmt),
            8,
        ),
        YScale::Log { .. } => (
            format!(
                "error: mean per-pixel L2 RGB (log scale{})",
                if frame.has_zero { "; 0 at bottom" } else { "" }
            ),
            Box::new(log_label),
            ((y1 - y0).ceil() as usize + 1).clamp(3, 10),
        ),
    };
    mesh_style(
        chart,
        theme,
        &Axes {
            x_desc: "mean frame time (ms)",
            y_desc: &y_desc,
            x_fmt: &x_fmt,
            y_fmt: &*y_fmt,
            labels: (10, y_labels),
            label_size: 13.0,
            y_light_lines: if matches!(frame.scale, YScale::Log { .. }) {
                0
            } else {
                2
            },
        },
    )?;
    Ok(())
}

/// The node paths (grey, grey dashed when set aside), the predicted frontier dotted, the
/// original's frame time dashed, then the highlighted nodes in colour with Δn at their ends.
fn paths<DB: DrawingBackend>(
    chart: &mut Chart2d<'_, DB>,
    t: &Tradeoff,
    frame: &Frame,
    theme: &Theme,
) -> DrawResult
where
    DB::ErrorType: 'static,
{
    let ((x0, x1), (y0, y1)) = (frame.x, frame.y);
    let pt = |q: &(u32, f64, f64)| frame.point(q);
    // Unhighlighted usable nodes, thin grey; set-aside nodes, grey dashed.
    for p in t.paths.iter().filter(|p| p.color.is_none()) {
        let pts: Vec<(f64, f64)> = p.points.iter().map(pt).collect();
        if p.set_aside {
            chart.draw_series(DashedLineSeries::new(
                pts.clone(),
                5,
                4,
                GREY.stroke_width(1),
            ))?;
            chart.draw_series(pts.iter().map(|&q| Circle::new(q, 2, GREY.stroke_width(1))))?;
        } else {
            chart.draw_series(LineSeries::new(pts.clone(), GREY.mix(0.7).stroke_width(1)))?;
            chart.draw_series(pts.iter().map(|&q| Circle::new(q, 1, GREY.filled())))?;
        }
    }
    // Predicted frontier, dotted.
    if !t.pareto.is_empty() {
        let pts: Vec<(f64, f64)> = t
            .pareto
            .iter()
            .map(|p| (p.0, frame.scale.map(p.1)))
            .collect();
        chart.draw_series(DashedLineSeries::new(
            pts.clone(),
            2,
            4,
            INK.stroke_width(2),
        ))?;
    }
    // The original's frame time.
    if let Some(orig) = t.original_ms {
        chart.draw_series(DashedLineSeries::new(
            vec![(orig, y0), (orig, y1)],
            9,
            6,
            INK.stroke_width(2),
        ))?;
        let right = orig > x0 + 0.7 * (x1 - x0);
        let (h, dx) = if right {
            (HPos::Right, -6)
        } else {
            (HPos::Left, 6)
        };
        chart.draw_series(std::iter::once(
            EmptyElement::at((orig, y1))
                + Text::new(
                    format!("original {} ms", fmt_ms(orig)),
                    (dx, 6),
                    at(&theme.bold(13.0), h, VPos::Top),
                ),
        ))?;
    }
    // Highlighted nodes, colored, with Δn at the path ends.
    for p in t.paths.iter().filter(|p| p.color.is_some()) {
        let c = color(p.color.unwrap_or(0));
        let pts: Vec<(f64, f64)> = p.points.iter().map(pt).collect();
        chart.draw_series(LineSeries::new(pts.clone(), c.stroke_width(2)))?;
        chart.draw_series(pts.iter().map(|&q| Circle::new(q, 3, c.filled())))?;
        let style = theme.style(11.0, c, true);
        let ends: Vec<&(u32, f64, f64)> = match (p.points.first(), p.points.last()) {
            (Some(a), Some(b)) if a.0 != b.0 => vec![a, b],
            (Some(a), _) => vec![a],
            _ => vec![],
        };
        for q in ends {
            chart.draw_series(std::iter::once(
                EmptyElement::at(pt(q))
                    + Text::new(
                        format!("{}", q.0),
                        (5, -4),
                        at(&style, HPos::Left, VPos::Bottom),
                    ),
            ))?;
        }
    }
    Ok(())
}

/// The selections at the budgets: a black ring on the predicted point, labelled, the labels
/// alternately above and below so that neighbours do not overlap.
fn marks<DB: DrawingBackend>(
    chart: &mut Chart2d<'_, DB>,
    t: &Tradeoff,
    frame: &Frame,
    theme: &Theme,
) -> DrawResult
where
    DB::ErrorType: 'static,
{
    let (x0, x1) = frame.x;
    for (i, (ms, e, label)) in t.marks.iter().enumerate() {
        let q = (*ms, frame.scale.map(*e));
        chart.draw_series(std::iter::once(Circle::new(q, 8, INK.stroke_width(2))))?;
        let right = *ms > x0 + 0.6 * (x1 - x0);
        let (h, dx) = if right {
            (HPos::Right, -12)
        } else {
            (HPos::Left, 12)
        };
        // Alternate above and below, so neighbouring labels do not overlap.
        let (v, dy) = if i % 2 == 0 {
            (VPos::Bottom, -6)
        } else {
            (VPos::Top, 6)
        };
        chart.draw_series(std::iter::once(
            EmptyElement::at(q) + Text::new(label.clone(), (dx, dy), at(&theme.bold(12.0), h, v)),
        ))?;
    }
    Ok(())
}

/// The legend's rows: the highlighted nodes, the other and set-aside nodes, the frontier, the
/// selections and the original.
fn legend_rows(t: &Tradeoff) -> Vec<(Sample, String)> {
    let mut rows: Vec<(Sample, String)> = Vec::new();
    for p in t.paths.iter().filter(|p| p.color.is_some()) {
        rows.push((
            Sample::Line {
                color: color(p.color.unwrap_or(0)),
                width: 2,
                marker: true,
            },
            p.label.clone(),
        ));
    }
    if t.others > 0 {
        rows.push((
            Sample::Line {
                color: GREY,
                width: 1,
                marker: false,
            },
            format!("{} other usable node{} (grey)", t.others, plural(t.others)),
        ));
    }
    let aside = t.paths.iter().filter(|p| p.set_aside).count();
    let dashed_grey = Sample::Dashed {
        color: GREY,
        width: 1,
        dash: 5,
        gap: 4,
    };
    if aside > 0 && aside <= 3 {
        for p in t.paths.iter().filter(|p| p.set_aside) {
            rows.push((
                dashed_grey,
                format!("{} (set aside)", crate::truncate(&p.label, 26)),
            ));
        }
    } else if aside > 0 {
        rows.push((
            dashed_grey,
            format!("{aside} set-aside node{} (grey dashed)", plural(aside)),
        ));
    }
    if !t.pareto.is_empty() {
        rows.push((
            Sample::Dashed {
                color: INK,
                width: 2,
                dash: 2,
                gap: 4,
            },
            "predicted Pareto frontier".to_string(),
        ));
    }
    if !t.marks.is_empty() {
        rows.push((
            Sample::Ring { color: INK },
            "selection at a budget ε (predicted)".to_string(),
        ));
    }
    if let Some(orig) = t.original_ms {
        rows.push((
            Sample::Dashed {
                color: INK,
                width: 2,
                dash: 9,
                gap: 6,
            },
            format!("original shader ({} ms)", fmt_ms(orig)),
        ));
    }
    rows
}

/// The legend column: its head, the rows, and how to read the chart.
fn draw_legend<DB: DrawingBackend>(
    legend: &DrawingArea<DB, Shift>,
    rows: &[(Sample, String)],
    theme: &Theme,
) -> DrawResult
where
    DB::ErrorType: 'static,
{
    let head = at(&theme.bold(14.0), HPos::Left, VPos::Top);
    legend.draw_text("node (id: expression)", &head, (8, 8))?;
    let style = theme.text(12.5);
    for (i, (sample, label)) in rows.iter().enumerate() {
        legend_row(legend, (10, 40 + i as i32 * 22), *sample, label, &style)?;
    }
    let foot = 40 + rows.len() as i32 * 22 + 12;
    let notes = [
        "lower left is better: faster, less error;",
        "left of the dashed line = faster than the",
        "original; numbers on paths: Δn",
    ];
    for (i, line) in notes.iter().enumerate() {
        legend.draw_text(
            line,
            &at(&theme.muted(12.0), HPos::Left, VPos::Top),
            (10, foot + i as i32 * 17),
        )?;
    }
    Ok(())
}
