//! `reproj report`: one self-contained HTML page of a profile, for a shader author to look at.
//!
//! The page holds the trade-off chart (speedup vs error of every measured and predicted
//! (node, Δn)) with a budget slider that moves the selection live: the selector's choices are
//! precomputed here for every budget that matters ([`budgets`]) and embedded as JSON, so the page
//! runs the selector's own decisions, not a copy of its logic. For each distinct selection it shows
//! the reference, variant, error-map and hit-map frames rendered with the replay at report time
//! ([`frames`]); below, the model-validation charts of every profiled node and the table of fits.
//! Nothing is fetched: CSS and JS are inline, images are `data:` URIs.

pub mod base64;
pub mod budgets;
pub mod compare;
pub mod frames;
mod html;
pub mod metrics;
mod page;

use std::path::{Path, PathBuf};

use reproj_analyze::AnalyzeError;
use reproj_emit::resolve;
use reproj_models::Profile;
use reproj_replay::Renderer;

pub use compare::{CompareRun, load_compare};
pub use page::PAGE_SCHEMA_VERSION;

/// What can go wrong while building a report.
#[derive(Debug, thiserror::Error)]
pub enum ReportError {
    #[error(transparent)]
    Analyze(#[from] AnalyzeError),
    #[error(transparent)]
    Chart(#[from] reproj_charts::ChartError),
    #[error("cannot encode a frame as PNG: {0}")]
    Png(String),
    /// A compare run's files (`--compare DIR`).
    #[error(transparent)]
    Read(#[from] reproj_io::ReadError),
    #[error(transparent)]
    Input(#[from] reproj_io::InputError),
}

impl ReportError {
    /// The source diagnostic of a front-end error about a place in the shader.
    pub fn diagnostic(&self) -> Option<&reproj_front::SourceDiagnostic> {
        match self {
            ReportError::Analyze(e) => e.diagnostic(),
            _ => None,
        }
    }
}

impl From<reproj_front::FrontError> for ReportError {
    fn from(e: reproj_front::FrontError) -> Self {
        ReportError::Analyze(e.into())
    }
}

impl From<reproj_instance::InstanceError> for ReportError {
    fn from(e: reproj_instance::InstanceError) -> Self {
        ReportError::Analyze(e.into())
    }
}

impl From<reproj_emit::EmitError> for ReportError {
    fn from(e: reproj_emit::EmitError) -> Self {
        ReportError::Analyze(e.into())
    }
}

impl From<reproj_replay::ReplayError> for ReportError {
    fn from(e: reproj_replay::ReplayError) -> Self {
        ReportError::Analyze(e.into())
    }
}

impl ReportError {
    /// True when the error comes from the user's input rather than a bug or the machine.
    pub fn is_user_error(&self) -> bool {
        match self {
            ReportError::Analyze(e) => e.is_user_error(),
            ReportError::Chart(_) | ReportError::Png(_) => false,
            ReportError::Read(_) | ReportError::Input(_) => true,
        }
    }
}

/// Where the inputs are, and how much to render.
#[derive(Debug, Clone)]
pub struct ReportOptions {
    /// The session to render (`None`: the profile's, relative to the profile file).
    pub session: Option<PathBuf>,
    /// The shader (`None`: the profile's). It must be the profiled shader up to comments.
    pub shader: Option<PathBuf>,
    /// Most selections to render frames of; with more, these many spread over the budget range
    /// (the lowest and highest budget's always among them). The others show their numbers only.
    pub max_rendered: usize,
    /// How the rendered selections are timed against the original (one interleaved run).
    pub timing: reproj_bench::BenchOptions,
    /// Folders of `reproj compare` runs whose tables and crops the page shows.
    pub compare: Vec<PathBuf>,
}

impl Default for ReportOptions {
    fn default() -> Self {
        ReportOptions {
            session: None,
            shader: None,
            max_rendered: 8,
            timing: reproj_bench::BenchOptions::default(),
            compare: Vec::new(),
        }
    }
}

/// Which of `n` choices (by increasing budget) to render: all, or `max` spread evenly.
pub fn rendered_choices(n: usize, max: usize) -> Vec<usize> {
    if n <= max {
        return (0..n).collect();
    }
    if max <= 1 {
        return (0..max.min(n)).map(|_| n - 1).collect();
    }
    let mut v: Vec<usize> = (0..max).map(|i| i * (n - 1) / (max - 1)).collect();
    v.dedup();
    v
}

/// Build the page for the profile at `profile_path`: render every distinct selection with
/// `renderer`, telling `progress` what it does. Returns the HTML text.
pub fn report(
    profile: &Profile,
    profile_path: &Path,
    opts: &ReportOptions,
    renderer: &Renderer,
    progress: &mut dyn FnMut(&str),
) -> Result<String, ReportError> {
    // The compare runs first: a bad folder fails before anything renders.
    let compare = opts
        .compare
        .iter()
        .map(|d| load_compare(d))
        .collect::<Result<Vec<_>, _>>()?;
    let (_, loaded, shader) =
        reproj_emit::load_profiled(profile, profile_path, opts.shader.as_deref())?;
    let (nodes, sets) =
        reproj_emit::selector_records(profile, profile_path, reproj_models::Metric::L2)?;
    let records = budgets::Records { nodes, sets };
    let session_path = opts
        .session
        .clone()
        .unwrap_or_else(|| resolve(&profile.session.path, profile_path));
    let session = frames::session(&session_path)?;
    let budgets = budgets::budgets(profile, &records);
    progress(&format!(
        "{} budgets, {} distinct selections",
        budgets.entries.len(),
        budgets.choices.len()
    ));
    progress("rendering the original");
    let reference = frames::reference(renderer, &shader, profile, &session)?;
    let chosen = rendered_choices(budgets.choices.len(), opts.max_rendered);
    let mut rendered: Vec<Option<frames::Rendered>> = vec![None; budgets.choices.len()];
    for (k, &i) in chosen.iter().enumerate() {
        let c = &budgets.choices[i];
        progress(&format!(
            "[{}/{}] rendering {} ({}) at Δn = {}",
            k + 1,
            chosen.len(),
            budgets::label(c),
            c.strategy,
            c.delta_n
        ));
        rendered[i] = Some(frames::render_choice(
            renderer, &shader, &loaded, profile, &session, &reference, c,
        )?);
    }
    // Every rendered selection against the original in one interleaved run: the speeds the
    // page shows as measured.
    let timed_at: Vec<usize> = chosen
        .iter()
        .copied()
        .filter(|&i| rendered[i].is_some())
        .collect();
    if !timed_at.is_empty() {
        progress("timing the selections against the original, interleaved");
        let candidates: Vec<reproj_bench::Candidate> = timed_at
            .iter()
            .map(|&i| {
                let r = rendered[i].as_ref().expect("filtered");
                let c = &budgets.choices[i];
                reproj_bench::Candidate {
                    name: format!("{} Δn {}", budgets::label(c), c.delta_n),
                    subject: reproj_bench::Subject::Variant(r.input.clone()),
                }
            })
            .collect();
        let entry = shader.fragment_entry(Some(&profile.entry))?;
        let timed = reproj_bench::bench(
            renderer,
            reproj_bench::Baseline {
                shader: &shader,
                entry,
                reference: &reference,
            },
            &session,
            &candidates,
            &opts.timing,
            &mut |_| {},
        )?;
        for (&i, c) in timed_at.iter().zip(&timed.candidates) {
            if let Some(r) = rendered[i].as_mut() {
                r.speedup = c.speedup;
                r.speedup_ci95 = c.speedup_ci95;
                if let Some(ms) = c.median_ms {
                    r.report.frame_ms = ms;
                    r.original_ms = timed.baseline.median_ms;
                }
            }
        }
        // One line per kind of condition: with dozens of selections, "the machine was busy"
        // for each of them says nothing more than once.
        let mut said = Vec::new();
        for w in &timed.warnings {
            if reproj_bench::add_warning_once(&mut said, w) {
                progress(&format!("warning: {w}"));
            }
        }
    }
    progress("drawing the charts");
    let charts = page::Charts::draw(profile, &budgets, &chosen)?;
    Ok(page::html(&page::Page {
        profile,
        profile_path,
        shader: &shader,
        budgets: &budgets,
        records: &records,
        rendered: &rendered,
        charts: &charts,
        compare: &compare,
    }))
}

#[cfg(test)]
mod tests {
    #[test]
    fn rendered_choices_spread_over_the_range() {
        assert_eq!(super::rendered_choices(3, 8), [0, 1, 2]);
        assert_eq!(
            super::rendered_choices(45, 8),
            [0, 6, 12, 18, 25, 31, 37, 44]
        );
        assert_eq!(super::rendered_choices(45, 1), [44]);
        assert!(super::rendered_choices(45, 0).is_empty());
        assert!(super::rendered_choices(0, 8).is_empty());
    }
}
