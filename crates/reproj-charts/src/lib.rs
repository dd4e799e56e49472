//! The analysis charts of a profile, as SVG and PNG, after the paper's figures (seeds 002):
//!
//! - `{stem}.tradeoff`: error vs frame time, one path per node over Δn (Fig. 7), the original
//!   shader's frame time as a dashed vertical line and the models' predicted Pareto frontier
//!   (`reproj_select::pareto`) dotted;
//! - `{stem}.hitrate`: measured hit rate vs Δn and the fitted `µ(1 − 1/Δn)` (Fig. 5);
//! - `{stem}.models`: for every usable node (small multiples), predicted vs measured error and
//!   frame time over Δn, held-out Δn marked apart (Fig. 6; [`models`](crate::models)).
//!
//! The trade-off chart marks what the selector (`reproj_select::select`, as `reproj emit` runs it)
//! chooses at the budgets of [`ChartOptions`], labelled with the budgets.
//!
//! Text: SVG always has it (`<text>` elements; the viewer picks the font). PNG text needs a font
//! file, found at run time (see [`font_path`], env `REPROJ_FONT`) and drawn with ab_glyph; with
//! none the PNGs are drawn without text and [`ChartPaths::warnings`] says so. No system font
//! library (fontconfig, font-kit) is used.
//!
//! Every chart is drawn whatever the profile holds (no node, no measurement, all errors 0, one Δn,
//! identical times): empty data give an empty, labeled chart, never a panic or an empty axis.

mod caption;
mod compare;
mod draw;
mod font;
mod glyph;
mod hitrate;
mod models;
mod style;
mod tradeoff;

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};

use reproj_models::profile::{Measurement, NodeProfile, NodeStatus};
use reproj_models::{HitRateStatus, Profile};
use reproj_select::{
    Budget, DEFAULT_MAX_DELTA_N, DEFAULT_MIN_DELTA_N, NodeRecord, SelectOptions, Selection,
    SetRecord, pareto, select_with_sets,
};

pub use caption::{Caption, draw_captions};
pub use compare::{Compare, ComparePoint, CompareSeries, compare_chart};
pub use font::{FONT_ENV, font_path};

/// Files written by [`write_charts`].
#[derive(Debug, Clone, PartialEq, Eq, Default)]
pub struct ChartPaths {
    /// `{stem}.tradeoff.svg`, `{stem}.hitrate.svg`, `{stem}.models.svg`.
    pub svg: Vec<PathBuf>,
    /// The same charts as PNG.
    pub png: Vec<PathBuf>,
    /// Non-fatal remarks, e.g. no font was found so the PNGs have no text.
    pub warnings: Vec<String>,
    /// The font file used for PNG text, if any.
    pub font: Option<PathBuf>,
}

/// Why the charts could not be written.
#[derive(Debug, thiserror::Error)]
pub enum ChartError {
    /// Writing a file failed (the previous file, if any, is kept).
    #[error(transparent)]
    Write(#[from] reproj_io::WriteError),
    /// plotters failed to draw a chart.
    #[error("cannot draw the {chart} chart: {message}")]
    Draw {
        /// Which chart.
        chart: &'static str,
        /// plotters' error.
        message: String,
    },
    /// The PNG encoder failed.
    #[error("cannot encode {path} as PNG: {message}")]
    Png {
        /// The file.
        path: PathBuf,
        /// The encoder's error.
        message: String,
    },
}

/// Size of the trade-off and hit-rate charts, pixels.
const SIZE: (u32, u32) = (900, 600);
/// More nodes than this: only the best [`HIGHLIGHTED`] get a color and a legend entry.
const MAX_LEGEND_NODES: usize = 12;
/// Nodes highlighted when there are more than [`MAX_LEGEND_NODES`].
const HIGHLIGHTED: usize = 8;

/// What to draw beyond the profile.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct ChartOptions {
    /// Error budgets whose selections the trade-off chart marks (`reproj emit --max-error`).
    pub budgets: Vec<f64>,
}

/// One of the charts.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Figure {
    /// Error vs frame time per node, the selections marked.
    Tradeoff,
    /// Hit rate vs Δn.
    HitRate,
    /// Predicted vs measured error and time, every usable node.
    Models,
}

impl Figure {
    /// Every chart, in the order [`write_charts`] writes them.
    pub const ALL: [Figure; 3] = [Figure::Tradeoff, Figure::HitRate, Figure::Models];

    /// The name in file names: `{stem}.{name}.png`.
    pub fn name(self) -> &'static str {
        match self {
            Figure::Tradeoff => "tradeoff",
            Figure::HitRate => "hitrate",
            Figure::Models => "models",
        }
    }
}

/// A chart as PNG bytes, from [`png`].
#[derive(Debug, Clone)]
pub struct Png {
    pub bytes: Vec<u8>,
    /// `(width, height)` in pixels.
    pub size: (u32, u32),
    /// Non-fatal remarks (no font: no text).
    pub warnings: Vec<String>,
}

/// One chart of `profile` as PNG, in memory (for pages that embed it).
pub fn png(profile: &Profile, figure: Figure, opts: &ChartOptions) -> Result<Png, ChartError> {
    let font = font::font();
    let (chart, size) = charts(profile, opts)
        .into_iter()
        .find(|c| c.0 == figure)
        .map(|c| (c.1, c.2))
        .expect("every figure is drawn");
    let rgb = draw::render_rgb(&chart, size, font.fonts.as_ref()).map_err(|message| {
        ChartError::Draw {
            chart: figure.name(),
            message,
        }
    })?;
    let bytes = encode_png(&rgb, size).map_err(|message| ChartError::Png {
        path: PathBuf::from(figure.name()),
        message,
    })?;
    Ok(Png {
        bytes,
        size,
        warnings: font.warnings.clone(),
    })
}

/// Every chart's data and size.
fn charts(profile: &Profile, opts: &ChartOptions) -> Vec<(Figure, draw::Chart, (u32, u32))> {
    let tradeoff = tradeoff(profile, &opts.budgets);
    // A node keeps its color from chart to chart.
    let colors: BTreeMap<u32, usize> = tradeoff
        .paths
        .iter()
        .filter_map(|p| p.color.map(|c| (p.id, c)))
        .collect();
    let models = models::models(profile, &colors);
    let models_size = models::size(&models);
    vec![
        (Figure::Tradeoff, draw::Chart::Tradeoff(tradeoff), SIZE),
        (
            Figure::HitRate,
            draw::Chart::HitRate(hit_rate(profile)),
            SIZE,
        ),
        (Figure::Models, draw::Chart::Models(models), models_size),
    ]
}

/// Write the analysis charts next to the profile: `{stem}.tradeoff.{svg,png}`,
/// `{stem}.hitrate.{svg,png}`, `{stem}.models.{svg,png}` in `dir` (created if missing), all or
/// none ([`reproj_io::write_files`]).
pub fn write_charts(
    profile: &Profile,
    dir: &Path,
    stem: &str,
    opts: &ChartOptions,
) -> Result<ChartPaths, ChartError> {
    let font = font::font();
    let mut paths = write_charts_with(profile, dir, stem, opts, font.fonts.as_ref())?;
    paths.warnings.extend(font.warnings.iter().cloned());
    paths.font = font.path.clone();
    Ok(paths)
}

/// [`write_charts`] with the given fonts for PNG text (none: as when no font file exists).
fn write_charts_with(
    profile: &Profile,
    dir: &Path,
    stem: &str,
    opts: &ChartOptions,
    fonts: Option<&font::Fonts>,
) -> Result<ChartPaths, ChartError> {
    let mut out = ChartPaths::default();
    let mut files = Vec::new();
    for (figure, chart, size) in &charts(profile, opts) {
        let name = figure.name();
        let svg_path = dir.join(format!("{stem}.{name}.svg"));
        let svg = draw::render_svg(chart, *size).map_err(|message| ChartError::Draw {
            chart: name,
            message,
        })?;
        files.push((svg_path.clone(), svg.into_bytes()));
        out.svg.push(svg_path);

        let png_path = dir.join(format!("{stem}.{name}.png"));
        let rgb = draw::render_rgb(chart, *size, fonts).map_err(|message| ChartError::Draw {
            chart: name,
            message,
        })?;
        let png = encode_png(&rgb, *size).map_err(|message| ChartError::Png {
            path: png_path.clone(),
            message,
        })?;
        files.push((png_path.clone(), png));
        out.png.push(png_path);
    }
    // All the charts or none: a failure keeps every chart of the previous run.
    reproj_io::write_files(&files)?;
    Ok(out)
}

/// Encode an RGB8 buffer as PNG.
pub(crate) fn encode_png(rgb: &[u8], (w, h): (u32, u32)) -> Result<Vec<u8>, String> {
    use image::ImageEncoder;
    let mut bytes = Vec::new();
    image::codecs::png::PngEncoder::new(&mut bytes)
        .write_image(rgb, w, h, image::ExtendedColorType::Rgb8)
        .map_err(|e| e.to_string())?;
    Ok(bytes)
}

// ---------------------------------------------------------------------------------------------
// What each chart shows, taken from the profile (pure data; `draw` turns it into pictures).

/// One node's measured path over Δn.
#[derive(Debug, Clone)]
pub(crate) struct NodePath {
    pub(crate) id: u32,
    pub(crate) label: String,
    /// Palette index; `None`: drawn thin grey without a legend entry.
    pub(crate) color: Option<usize>,
    pub(crate) set_aside: bool,
    /// `(Δn, frame ms, error)`, sorted by Δn.
    pub(crate) points: Vec<(u32, f64, f64)>,
}

/// Chart 1 (Fig. 7).
#[derive(Debug, Clone)]
pub(crate) struct Tradeoff {
    pub(crate) title: String,
    pub(crate) subtitle: String,
    /// Colored (legend) paths first, then the thin grey and set-aside ones.
    pub(crate) paths: Vec<NodePath>,
    /// Paths drawn thin grey without a legend entry (usable nodes not among the best).
    pub(crate) others: usize,
    /// Predicted frontier: `(ms, error, Δn, node id)`, by increasing time.
    pub(crate) pareto: Vec<(f64, f64, u32, u32)>,
    pub(crate) original_ms: Option<f64>,
    /// The selections at the chart's budgets, predicted: `(ms, error, label)`.
    pub(crate) marks: Vec<(f64, f64, String)>,
}

/// Chart 2 (Fig. 5).
#[derive(Debug, Clone)]
pub(crate) struct HitRate {
    pub(crate) title: String,
    pub(crate) subtitle: String,
    /// `(Δn, hit rate)` at training Δn.
    pub(crate) train: Vec<(f64, f64)>,
    /// `(Δn, hit rate)` at held-out Δn.
    pub(crate) holdout: Vec<(f64, f64)>,
    pub(crate) mu: Option<f64>,
    pub(crate) max_delta_n: f64,
}

pub(crate) fn finite_pos(v: f64) -> Option<f64> {
    (v.is_finite() && v > 0.0).then_some(v)
}

/// `"id: text"`, whitespace collapsed, at most `max` characters.
pub(crate) fn node_label(node: &NodeProfile, max: usize) -> String {
    let text: String = node.text.split_whitespace().collect::<Vec<_>>().join(" ");
    let root = if node.root { " (root)" } else { "" };
    let strategy = if node.strategy == "3pass" {
        String::new()
    } else {
        format!(" [{}]", node.strategy)
    };
    truncate(&format!("{}{root}{strategy}: {text}", node.id), max)
}

/// At most `max` characters, with an ellipsis when cut.
pub(crate) fn truncate(s: &str, max: usize) -> String {
    if s.chars().count() <= max {
        s.to_string()
    } else {
        let mut t: String = s.chars().take(max.saturating_sub(1)).collect();
        t.push('…');
        t
    }
}

/// A measurement that can be drawn: finite, non-negative time and error.
pub(crate) fn usable(m: &Measurement) -> bool {
    m.frame_ms.is_finite() && m.frame_ms >= 0.0 && m.error.is_finite() && m.error >= 0.0
}

pub(crate) fn shader_name(profile: &Profile) -> String {
    Path::new(&profile.shader.path)
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .filter(|n| !n.is_empty())
        .unwrap_or_else(|| "shader".to_string())
}

pub(crate) fn setting(profile: &Profile) -> String {
    let adapter = if profile.machine.adapter.is_empty() {
        "unknown adapter".to_string()
    } else {
        truncate(&profile.machine.adapter, 40)
    };
    format!(
        "{}×{}, {} frames, {adapter}",
        profile.resolution[0], profile.resolution[1], profile.frames
    )
}

/// The selector's records of the profile: its usable nodes and sets, as `reproj emit` builds them
/// (`reproj_select::profile_records`). Every node has an L2 model (`NodeProfile::fit`), so the
/// builder's only error, a missing model, cannot happen here.
fn records(profile: &Profile) -> (Vec<NodeRecord>, Vec<SetRecord>) {
    let keep = |_: &NodeProfile| true;
    reproj_select::profile_records(profile, reproj_models::Metric::L2, None, &keep, true)
        .map(|r| (r.nodes, r.sets))
        .unwrap_or_default()
}

/// The selections at `budgets` (emit's selector, sets included): one mark per distinct choice,
/// labelled with its budgets.
fn marks(profile: &Profile, budgets: &[f64]) -> Vec<(f64, f64, String)> {
    let (nodes, sets) = records(profile);
    /// (node, members, strategy, Δn), predicted ms and error, the budgets that choose it.
    type Marked = ((u32, Vec<u32>, String, u32), f64, f64, Vec<f64>);
    let mut marks: Vec<Marked> = Vec::new();
    for &budget in budgets {
        // A budget that is none (negative, not finite) selects nothing.
        let Ok(max_error) = Budget::new(budget) else {
            continue;
        };
        let Selection::Node(c) = select_with_sets(
            &nodes,
            &sets,
            &profile.hit_rate,
            profile.original.frame_ms,
            &SelectOptions::new(max_error),
        ) else {
            continue;
        };
        let key = (c.node_id, c.members.clone(), c.strategy.clone(), c.delta_n);
        match marks.iter_mut().find(|m| m.0 == key) {
            Some(m) => m.3.push(budget),
            None => marks.push((
                key,
                c.predicted_ms,
                c.predicted_error.max(0.0),
                vec![budget],
            )),
        }
    }
    marks
        .into_iter()
        .map(|((id, members, _, dn), ms, error, budgets)| {
            let budgets: Vec<String> = budgets.iter().map(|b| significant(*b)).collect();
            let what = if members.is_empty() {
                format!("node {id}")
            } else {
                let ids: Vec<String> = members.iter().map(u32::to_string).collect();
                format!("set {}", ids.join("+"))
            };
            (
                ms,
                error,
                format!("ε ≤ {}: {what}, Δn {dn}", budgets.join(", ")),
            )
        })
        .collect()
}

/// `v` with three significant digits, trailing zeros trimmed: `0.002`, `0.0127`, `0.1`.
fn significant(v: f64) -> String {
    if !(v.is_finite() && v > 0.0) {
        return format!("{v}");
    }
    let decimals = (2.0 - v.log10().floor()).clamp(0.0, 12.0) as usize;
    let s = format!("{v:.decimals$}");
    if s.contains('.') {
        s.trim_end_matches('0').trim_end_matches('.').to_string()
    } else {
        s
    }
}

/// The trade-off chart's data: every node's measured path, the predicted frontier, the
/// original's time and the selections at `budgets`; the best nodes highlighted
/// ([`highlighted`]).
fn tradeoff(profile: &Profile, budgets: &[f64]) -> Tradeoff {
    let original_ms = finite_pos(profile.original.frame_ms);
    let pareto: Vec<(f64, f64, u32, u32)> = pareto(
        &records(profile).0,
        &profile.hit_rate,
        DEFAULT_MIN_DELTA_N,
        DEFAULT_MAX_DELTA_N,
    )
    .into_iter()
    .filter(|p| p.predicted_ms.is_finite() && p.predicted_error.is_finite())
    .map(|p| {
        (
            p.predicted_ms,
            p.predicted_error.max(0.0),
            p.delta_n,
            p.node_id,
        )
    })
    .collect();
    let ok: Vec<&NodeProfile> = profile
        .nodes
        .iter()
        .filter(|n| n.status == NodeStatus::Ok && !measured_points(n).is_empty())
        .collect();
    let aside: Vec<&NodeProfile> = profile
        .nodes
        .iter()
        .filter(|n| n.status != NodeStatus::Ok && !measured_points(n).is_empty())
        .collect();
    let chosen = highlighted(&ok, &pareto);
    let path = |n: &NodeProfile, color: Option<usize>, set_aside: bool| NodePath {
        id: n.id,
        label: node_label(n, 38),
        color,
        set_aside,
        points: measured_points(n),
    };
    let mut paths = Vec::new();
    // Colored first (in id order), so they get stable colors; then the others below them.
    for n in ok.iter().filter(|n| chosen.contains(&n.id)) {
        paths.push(path(n, Some(paths.len()), false));
    }
    let mut others = 0;
    for n in ok.iter().filter(|n| !chosen.contains(&n.id)) {
        others += 1;
        paths.push(path(n, None, false));
    }
    for n in &aside {
        paths.push(path(n, None, true));
    }
    let usable_nodes = profile
        .nodes
        .iter()
        .filter(|n| n.status == NodeStatus::Ok)
        .count();
    Tradeoff {
        title: format!(
            "Error vs frame time per cached node — {}",
            shader_name(profile)
        ),
        subtitle: format!(
            "{}; {} nodes ({usable_nodes} usable); one path per node over Δn (numbers: Δn at the ends)",
            setting(profile),
            profile.nodes.len()
        ),
        paths,
        others,
        pareto,
        original_ms,
        marks: marks(profile, budgets),
    }
}

/// A node's usable measurements as `(Δn, ms, error)`, by Δn.
fn measured_points(n: &NodeProfile) -> Vec<(u32, f64, f64)> {
    let mut v: Vec<(u32, f64, f64)> = n
        .measurements
        .iter()
        .filter(|m| usable(m))
        .map(|m| (m.delta_n, m.frame_ms, m.error))
        .collect();
    v.sort_by_key(|p| p.0);
    v
}

/// The nodes drawn in colour: all of them when the legend holds them, else the best ones: most
/// points on the predicted and on the measured frontier, then lowest normalized distance to the
/// lower left.
fn highlighted(ok: &[&NodeProfile], pareto: &[(f64, f64, u32, u32)]) -> BTreeSet<u32> {
    if ok.len() <= MAX_LEGEND_NODES {
        return ok.iter().map(|n| n.id).collect();
    }
    let all: Vec<(u32, f64, f64)> = ok
        .iter()
        .flat_map(|n| measured_points(n).into_iter().map(|(_, t, e)| (n.id, t, e)))
        .collect();
    let mut on_front: BTreeMap<u32, usize> = BTreeMap::new();
    for &(id, t, e) in &all {
        let dominated = all
            .iter()
            .any(|&(_, t2, e2)| t2 <= t && e2 <= e && (t2 < t || e2 < e));
        if !dominated {
            *on_front.entry(id).or_default() += 1;
        }
    }
    for p in pareto {
        *on_front.entry(p.3).or_default() += 1;
    }
    let (tmax, emax) = all
        .iter()
        .fold((0.0f64, 0.0f64), |(a, b), p| (a.max(p.1), b.max(p.2)));
    let closeness = |n: &NodeProfile| -> f64 {
        measured_points(n)
            .iter()
            .map(|&(_, t, e)| {
                t / if tmax > 0.0 { tmax } else { 1.0 } + e / if emax > 0.0 { emax } else { 1.0 }
            })
            .fold(f64::INFINITY, f64::min)
    };
    let mut ranked: Vec<(usize, f64, u32)> = ok
        .iter()
        .map(|n| {
            (
                on_front.get(&n.id).copied().unwrap_or(0),
                closeness(n),
                n.id,
            )
        })
        .collect();
    ranked.sort_by(|a, b| b.0.cmp(&a.0).then(a.1.total_cmp(&b.1)).then(a.2.cmp(&b.2)));
    ranked.iter().take(HIGHLIGHTED).map(|r| r.2).collect()
}

fn hit_rate(profile: &Profile) -> HitRate {
    let holdout: BTreeSet<u32> = profile.delta_n_holdout.iter().copied().collect();
    let mut train = Vec::new();
    let mut held = Vec::new();
    let mut max_dn = 0u32;
    for m in profile.nodes.iter().flat_map(|n| &n.measurements) {
        if !(m.hit_rate.is_finite() && m.delta_n >= 1) {
            continue;
        }
        max_dn = max_dn.max(m.delta_n);
        let p = (f64::from(m.delta_n), m.hit_rate.clamp(0.0, 1.0));
        if holdout.contains(&m.delta_n) && !profile.delta_n_train.contains(&m.delta_n) {
            held.push(p);
        } else {
            train.push(p);
        }
    }
    let fit = &profile.hit_rate;
    let mu = if fit.is_usable() {
        fit.mu.filter(|m| m.is_finite())
    } else {
        None
    };
    let fit_text = match (&fit.status, mu) {
        (HitRateStatus::Failed { reason }, _) => format!("fit failed: {reason}"),
        (_, None) => "no fit".to_string(),
        (status, Some(mu)) => {
            let r2 = fit
                .r2
                .filter(|r| r.is_finite())
                .map_or_else(|| "n/a".to_string(), |r| format!("{r:.3}"));
            let clamped = if matches!(status, HitRateStatus::Clamped { .. }) {
                " (clamped)"
            } else {
                ""
            };
            format!("µ = {mu:.3}{clamped}, R² = {r2}")
        }
    };
    HitRate {
        title: format!("Hit rate vs refresh period: γ(Δn) = µ(1 − 1/Δn), {fit_text}"),
        subtitle: format!(
            "{} — {}; {} measurements over {} nodes",
            shader_name(profile),
            setting(profile),
            train.len() + held.len(),
            profile
                .nodes
                .iter()
                .filter(|n| !n.measurements.is_empty())
                .count()
        ),
        train,
        holdout: held,
        mu,
        max_delta_n: f64::from(max_dn.max(DEFAULT_MAX_DELTA_N)),
    }
}

#[cfg(test)]
mod tests;
