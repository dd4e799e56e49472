//! The page: its data (the budgets' choices, the chart's points, each selection's numbers, as one
//! JSON object, schema `reproj.report-page`), its HTML (selection frames, charts and the table of
//! fits written here), and its script and style (`page.js`, `page.css`, inlined).

use std::fmt::Write as _;
use std::path::Path;

use reproj_charts::{ChartOptions, Figure, Png};
use reproj_models::Profile;
use reproj_models::profile::{NodeProfile, NodeStatus};
use reproj_select::{DEFAULT_MAX_DELTA_N, DEFAULT_MIN_DELTA_N, candidates};
use serde::Serialize;

use crate::base64::png_uri;
use crate::budgets::{BudgetEntry, Budgets, Records, label};
use crate::frames::Rendered;
use crate::html::{esc, num};
use crate::metrics::{self, Metric};
use crate::{ReportError, frames::FrameImages};

/// Version of the page's embedded JSON (`<script id="data">`, schema `reproj.report-page`).
/// Version 2: each choice's `reconstruct` (its node's filter, profile version 9).
pub const PAGE_SCHEMA_VERSION: u32 = 2;

const SCRIPT: &str = include_str!("page.js");
const STYLE: &str = include_str!("page.css");

/// The charts drawn by `reproj-charts`, as PNG.
pub(crate) struct Charts {
    tradeoff: Png,
    hitrate: Png,
    models: Png,
}

impl Charts {
    /// The trade-off chart marks the rendered selections (`marked`: indices into the choices),
    /// each at the lowest budget that selects it.
    pub(crate) fn draw(
        profile: &Profile,
        budgets: &Budgets,
        marked: &[usize],
    ) -> Result<Charts, ReportError> {
        let opts = ChartOptions {
            budgets: marked.iter().map(|&i| budgets.first_budget[i]).collect(),
        };
        Ok(Charts {
            tradeoff: reproj_charts::png(profile, Figure::Tradeoff, &opts)?,
            hitrate: reproj_charts::png(profile, Figure::HitRate, &opts)?,
            models: reproj_charts::png(profile, Figure::Models, &opts)?,
        })
    }
}

/// Everything the page shows.
pub(crate) struct Page<'a> {
    pub(crate) profile: &'a Profile,
    pub(crate) profile_path: &'a Path,
    pub(crate) shader: &'a reproj_front::Shader,
    pub(crate) budgets: &'a Budgets,
    /// What the budgets were chosen from (the chart's points are its nodes).
    pub(crate) records: &'a Records,
    /// One per `budgets.choices`, in order; `None`: not rendered (over the limit).
    pub(crate) rendered: &'a [Option<Rendered>],
    pub(crate) charts: &'a Charts,
    /// `reproj compare` runs shown on the page.
    pub(crate) compare: &'a [crate::CompareRun],
}

#[derive(Serialize)]
struct Data<'a> {
    schema: &'static str,
    version: u32,
    /// `[lowest, highest]` budget of the slider, log scale.
    range: [f64; 2],
    original_ms: f64,
    entries: &'a [BudgetEntry],
    choices: Vec<ChoiceView>,
    points: Vec<Point>,
}

#[derive(Serialize)]
struct ChoiceView {
    node_id: u32,
    /// `node 680`, `set 680+697`.
    label: String,
    /// A set's members (empty for one node).
    members: Vec<u32>,
    root: bool,
    text: String,
    line: u32,
    col: u32,
    /// The node's source line.
    source: String,
    strategy: String,
    /// Its reconstruction filter (the node's own, else the profile's).
    reconstruct: String,
    delta_n: u32,
    predicted_error: f64,
    predicted_ms: f64,
    predicted_speedup: f64,
    /// Its 95 % interval, where the profile timed the node interleaved (version 7 on).
    predicted_speedup_ci95: Option<[f64; 2]>,
    /// Rendered by the report (`None`: not rendered).
    measured: Option<Measured>,
    /// Measured by `analyze` at this Δn, when it was one of the profiled periods.
    profiled: Option<Vec<Metric>>,
}

#[derive(Serialize)]
struct Measured {
    metrics: Vec<Metric>,
    frame_ms: f64,
    original_ms: f64,
    /// Timed interleaved with the original (`reproj-bench`), with its 95 % interval.
    speedup: Option<f64>,
    speedup_ci95: Option<[f64; 2]>,
}

#[derive(Serialize)]
struct Point {
    node: u32,
    strategy: String,
    delta_n: u32,
    error: f64,
    speedup: f64,
    /// Measured by `analyze` (else predicted by the models).
    measured: bool,
}

/// Below this R² a node's timing fit is labelled weak in the table of fits.
const WEAK_TIME_R2: f64 = 0.5;

fn sci(v: Option<f64>) -> String {
    v.filter(|v| v.is_finite())
        .map_or_else(|| "–".to_string(), |v| format!("{v:.3e}"))
}

fn node_of<'p>(profile: &'p Profile, id: u32, strategy: &str) -> Option<&'p NodeProfile> {
    profile
        .nodes
        .iter()
        .find(|n| n.id == id && n.strategy == strategy)
}

fn data<'a>(p: &'a Page<'_>) -> Data<'a> {
    let profile = p.profile;
    let original_ms = profile.original.frame_ms;
    let speedup = |ms: f64| if ms > 0.0 { original_ms / ms } else { 0.0 };
    let lines: Vec<&str> = p.shader.source.lines().collect();
    let choices = p
        .budgets
        .choices
        .iter()
        .zip(p.rendered)
        .map(|(c, r)| {
            // A set is shown at its first member's line; its filter is the profile's.
            let node = if c.members.is_empty() {
                node_of(profile, c.node_id, &c.strategy)
            } else {
                profile.nodes.iter().find(|n| n.id == c.node_id)
            };
            let line = node.map_or(0, |n| n.line);
            ChoiceView {
                node_id: c.node_id,
                label: label(c),
                members: c.members.clone(),
                root: node.is_some_and(|n| n.root),
                text: c.node_text.clone(),
                line,
                col: node.map_or(0, |n| n.col),
                source: lines
                    .get((line as usize).saturating_sub(1))
                    .map_or_else(String::new, |l| l.trim_end().to_string()),
                strategy: c.strategy.clone(),
                reconstruct: node
                    .filter(|_| c.members.is_empty())
                    .map_or(profile.reconstruct.as_str(), |n| n.reconstruct_in(profile))
                    .to_string(),
                delta_n: c.delta_n,
                predicted_error: c.predicted_error,
                predicted_ms: c.predicted_ms,
                predicted_speedup: c.predicted_speedup,
                predicted_speedup_ci95: c.predicted_speedup_ci95,
                measured: r.as_ref().map(|r| Measured {
                    metrics: metrics::of_render(&r.report),
                    frame_ms: r.report.frame_ms,
                    original_ms: r.original_ms,
                    speedup: r.speedup,
                    speedup_ci95: r.speedup_ci95,
                }),
                profiled: node.filter(|_| c.members.is_empty()).and_then(|n| {
                    n.measurements
                        .iter()
                        .find(|m| m.delta_n == c.delta_n)
                        .map(metrics::of_measurement)
                }),
            }
        })
        .collect();
    let mut points: Vec<Point> = candidates(
        &p.records.nodes,
        &profile.hit_rate,
        DEFAULT_MIN_DELTA_N,
        DEFAULT_MAX_DELTA_N,
    )
    .into_iter()
    .map(|c| Point {
        node: c.node_id,
        strategy: c.strategy,
        delta_n: c.delta_n,
        error: c.predicted_error,
        speedup: speedup(c.predicted_ms),
        measured: false,
    })
    .collect();
    for n in &profile.nodes {
        for m in &n.measurements {
            if m.error.is_finite() && m.frame_ms.is_finite() && m.frame_ms > 0.0 {
                points.push(Point {
                    node: n.id,
                    strategy: n.strategy.clone(),
                    delta_n: m.delta_n,
                    error: m.error,
                    speedup: speedup(m.frame_ms),
                    measured: true,
                });
            }
        }
    }
    Data {
        schema: "reproj.report-page",
        version: PAGE_SCHEMA_VERSION,
        range: p.budgets.range,
        original_ms,
        entries: &p.budgets.entries,
        choices,
        points,
    }
}

/// The whole page.
pub(crate) fn html(p: &Page<'_>) -> String {
    let profile = p.profile;
    let name = Path::new(&profile.shader.path).file_name().map_or_else(
        || "shader".to_string(),
        |n| n.to_string_lossy().into_owned(),
    );
    let json = serde_json::to_string(&data(p))
        .expect("the page data serializes")
        .replace("</", "<\\/");
    // The slider starts at the budget of the middle selection (or the middle of the range).
    let start = p
        .budgets
        .first_budget
        .get(p.budgets.first_budget.len() / 2)
        .copied()
        .unwrap_or((p.budgets.range[0] * p.budgets.range[1]).sqrt());
    let mut h = String::new();
    let _ = write!(
        h,
        r#"<!doctype html>
<html lang="en"><head><meta charset="utf-8">
<meta name="viewport" content="width=device-width, initial-scale=1">
<title>reproj report — {name}</title>
<style>{STYLE}</style></head>
<body data-start-budget="{start}">
<header><h1>reproj report — {name}</h1>
<p class="muted">{profile_path} · {w}×{hgt}, {frames} frames · {adapter} · original {orig:.3} ms/frame · {nodes} nodes profiled</p></header>
<section id="tradeoff"><h2>Choose an error budget</h2>
<div class="controls"><label for="budget">error budget ε (mean per-pixel L2, log scale)</label>
<input type="range" id="budget" min="0" max="10000" step="1" value="5000">
<output id="budget-value" for="budget"></output></div>
<div class="row"><svg id="chart" viewBox="0 0 640 420" role="img" aria-label="speedup vs error"></svg>
<div id="selection" class="card">
<div class="sel-head"><span id="sel-node"></span> <span id="sel-strategy" class="tag"></span> <span id="sel-dn"></span></div>
<div id="sel-text" class="code"></div>
<pre id="sel-source"></pre>
<table id="sel-numbers"></table>
<p id="sel-reason" class="muted"></p>
</div></div>
<div id="frames"><p id="frames-note" class="muted"></p>
"#,
        profile_path = esc(&p.profile_path.display().to_string()),
        w = profile.resolution[0],
        hgt = profile.resolution[1],
        frames = profile.frames,
        adapter = esc(&profile.machine.device()),
        orig = profile.original.frame_ms,
        nodes = profile.nodes.len(),
    );
    for (k, r) in p.rendered.iter().enumerate() {
        let c = &p.budgets.choices[k];
        // Selections over the `--max-rendered` limit have no group: the page shows the nearest one.
        if let Some(r) = r {
            let _ = writeln!(
                h,
                r#"<div class="choice-frames" data-choice="{k}" data-label="{} (Δn = {})" hidden>"#,
                label(c),
                c.delta_n
            );
            for f in &r.frames {
                frame_row(&mut h, f, c.delta_n);
            }
            h.push_str("</div>\n");
        }
    }
    h.push_str(
        r#"<div class="choice-frames" data-choice="original" hidden><p class="muted">The original shader is kept at this budget: nothing to compare.</p></div>
</div></section>
"#,
    );
    let _ = write!(
        h,
        r#"<section id="models"><h2>Model validation, every profiled node</h2>
<p class="muted">Dots: measured at the training Δn; crosses: held-out Δn; lines: the fitted models.</p>
<img class="chart" alt="model validation" src="{}">
</section>
"#,
        png_uri(&p.charts.models.bytes)
    );
    fits(&mut h, profile);
    crate::compare::section(&mut h, p.compare);
    let _ = write!(
        h,
        r#"<section id="more"><h2>Trade-off and hit rate</h2>
<img class="chart" alt="error vs frame time, selections marked" src="{}">
<img class="chart" alt="hit rate vs refresh period" src="{}">
</section>
<script type="application/json" id="data">{json}</script>
<script>{SCRIPT}</script>
</body></html>
"#,
        png_uri(&p.charts.tradeoff.bytes),
        png_uri(&p.charts.hitrate.bytes),
    );
    h
}

fn frame_row(h: &mut String, f: &FrameImages, delta_n: u32) {
    let img = |h: &mut String, src: &[u8], alt: &str, caption: &str| {
        let _ = write!(
            h,
            r#"<figure><img alt="{alt}" src="{}"><figcaption>{caption}</figcaption></figure>"#,
            png_uri(src)
        );
    };
    let _ = write!(
        h,
        r#"<div class="frame-row"><h3>frame {} ({}), error {:.5}</h3><div class="quad">"#,
        f.index, f.why, f.error
    );
    img(h, &f.reference, "reference", "reference (original shader)");
    img(
        h,
        &f.variant,
        "variant",
        &format!("variant, Δn = {delta_n}"),
    );
    img(
        h,
        &f.errmap,
        "error map",
        "error map (per-pixel L2; colour bar below)",
    );
    if let Some(hit) = &f.hitmap {
        img(
            h,
            hit,
            "hit map",
            "hit map: green hit, red miss, blue refresh",
        );
    }
    h.push_str("</div></div>\n");
}

/// The table of fits: per node, the error model, the timing model and the held-out checks; the
/// hit-rate model; each node's measurements in a fold.
fn fits(h: &mut String, profile: &Profile) {
    let hr = &profile.hit_rate;
    let _ = write!(
        h,
        r#"<section id="fits"><h2>Fits</h2>
<p>Hit rate γ(Δn) = µ(1 − 1/Δn): µ = {}, R² = {}, {} samples, {}.</p>
<table class="fits"><thead><tr><th>node</th><th>expression</th><th>strategy</th><th>filter</th><th>status</th>
<th>α</th><th>λ</th><th>error R²</th><th>error RMS</th>
<th>E[hit] ms/px</th><th>E[miss] ms/px</th><th>E[overhead] ms</th><th>time R²</th><th>held-out time error</th>
<th>held-out checks (Δn: error measured / predicted; ms measured / predicted)</th></tr></thead><tbody>
"#,
        num(hr.mu, 3),
        num(hr.r2, 3),
        hr.n_samples,
        if hr.is_usable() {
            "usable"
        } else {
            "not usable"
        },
    );
    for n in &profile.nodes {
        fit_row(h, profile, n);
    }
    h.push_str("</tbody></table>\n");
    for n in profile.nodes.iter().filter(|n| !n.measurements.is_empty()) {
        measurements(h, n);
    }
    h.push_str("</section>\n");
}

/// A node's row of the fits table: its status (a weak timing fit said), its filter (with its
/// race's note), its models' parameters and quality, its held-out checks.
fn fit_row(h: &mut String, profile: &Profile, n: &NodeProfile) {
    let status = match &n.status {
        // A timing fit that explains little of the frame times is no "ok" for the speed.
        NodeStatus::Ok => match n.timing_fit.r2.filter(|r2| *r2 < WEAK_TIME_R2) {
            Some(r2) => format!(
                "ok for the error; timing fit weak (R² {r2:.3}): the speed leans on the interleaved race"
            ),
            None => "ok".to_string(),
        },
        NodeStatus::SetAside { reason } => format!("set aside: {reason}"),
    };
    // The reconstruction filter, with what its race measured where one was run.
    let filter = match profile
        .filter_probes
        .iter()
        .find(|p| p.node == n.id && p.note.is_some())
    {
        Some(p) => format!(
            "{} ({})",
            n.reconstruct_in(profile),
            p.note.as_deref().unwrap_or_default()
        ),
        None => n.reconstruct_in(profile).to_string(),
    };
    // The strategy with its refresh block, and what the block race measured where one was run.
    let block = n.block.unwrap_or(profile.block);
    let strategy = match profile
        .block_probes
        .iter()
        .find(|p| p.node == n.id && p.note.is_some())
    {
        Some(p) => format!(
            "{} k={block} ({})",
            n.strategy,
            p.note.as_deref().unwrap_or_default()
        ),
        None => format!("{} k={block}", n.strategy),
    };
    let e = &n.error_fit;
    let t = &n.timing_fit;
    let holdout: Vec<String> = n
        .holdout
        .iter()
        .map(|c| {
            format!(
                "{}: {} / {}; {} / {}",
                c.delta_n,
                num(Some(c.measured_error), 5),
                num(c.predicted_error, 5),
                num(Some(c.measured_ms), 2),
                num(c.predicted_ms, 2)
            )
        })
        .collect();
    let _ = writeln!(
        h,
        r#"<tr class="{cls}"><td>{id}{root}</td><td class="code">{text}</td><td>{strategy}</td><td>{filter}</td><td>{status}</td><td>{alpha}</td><td>{lambda}</td><td>{er2}</td><td>{erms}</td><td>{hit}</td><td>{miss}</td><td>{over}</td><td>{tr2}</td><td>{hold}</td><td>{checks}</td></tr>"#,
        cls = if n.status == NodeStatus::Ok {
            "ok"
        } else {
            "aside"
        },
        id = n.id,
        root = if n.root { " (root)" } else { "" },
        text = esc(&n.text),
        strategy = esc(&strategy),
        filter = esc(&filter),
        status = esc(&status),
        alpha = num(e.alpha, 5),
        lambda = num(e.lambda, 4),
        er2 = num(e.r2, 3),
        erms = sci(e.rms_residual),
        hit = sci(t.hit_ms),
        miss = sci(t.miss_ms),
        over = num(t.overhead_ms, 3),
        tr2 = num(t.r2, 3),
        hold = t
            .holdout_mean_relative_error
            .filter(|v| v.is_finite())
            .map_or_else(|| "–".to_string(), |v| format!("{:.1} %", v * 100.0)),
        checks = esc(&holdout.join(" · ")),
    );
}

/// A node's measurements, one row per Δn, in a fold.
fn measurements(h: &mut String, n: &NodeProfile) {
    let names: Vec<&'static str> = n
        .measurements
        .first()
        .map(|m| metrics::of_measurement(m).iter().map(|x| x.name).collect())
        .unwrap_or_default();
    let _ = write!(
        h,
        r#"<details><summary>node {} measurements ({})</summary><table class="fits"><thead><tr><th>Δn</th>"#,
        n.id,
        n.measurements.len()
    );
    for name in &names {
        let _ = write!(h, "<th>{name}</th>");
    }
    h.push_str("<th>hit rate</th><th>frame ms</th></tr></thead><tbody>");
    let mut ms: Vec<_> = n.measurements.iter().collect();
    ms.sort_by_key(|m| m.delta_n);
    for m in ms {
        let _ = write!(h, "<tr><td>{}</td>", m.delta_n);
        for x in metrics::of_measurement(m) {
            let _ = write!(
                h,
                "<td>{} {}</td>",
                num(x.value, x.decimals as usize),
                x.unit
            );
        }
        let _ = write!(
            h,
            "<td>{:.3}</td><td>{:.3}</td></tr>",
            m.hit_rate, m.frame_ms
        );
    }
    h.push_str("</tbody></table></details>\n");
}
