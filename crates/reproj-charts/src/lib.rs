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
mod data;
mod draw;
mod font;
mod glyph;
mod hitrate;
mod models;
mod style;
mod tradeoff;

use data::{HitRate, Tradeoff, hit_rate, tradeoff};
#[cfg(test)]
use data::{records, significant};

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use reproj_models::Profile;
use reproj_models::profile::{Measurement, NodeProfile};

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

#[cfg(test)]
mod tests;
