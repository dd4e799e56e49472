//! `analyze`: replay the session for the original shader and for the variants of the chosen nodes
//! at every training and held-out Δn, fit the models, and gather everything into a [`Profile`].
//!
//! This file holds the orchestration and the set-up phases (the nodes, the journal, the
//! reference); `ceiling.rs` measures the most caching can give here (and stops where it cannot
//! pay); `node.rs` replays one node (its strategy race, then the winner's periods);
//! `profile.rs` fits the models and fills the profile.

mod ceiling;
mod node;
mod profile;
mod shape;

use std::time::Instant;

use reproj_models::profile::{AnalysisTime, OriginalRecord, Shard};
use reproj_models::{Profile, content_hash};
use reproj_replay::{RenderOptions, Renderer};

use crate::AnalyzeError;
pub use crate::input::{AnalyzeInput, Progress, Silent};
use crate::journal::Journal;
pub use crate::options::{
    AnalyzeOptions, DEFAULT_HOLDOUT, DEFAULT_PERCEPTUAL_FRAMES, DEFAULT_PERCEPTUAL_STRIDE,
    DEFAULT_RACE, DEFAULT_TRAIN, Extension, ExtensionStop, Sampling, next_extension,
};
use crate::options::{check_periods, period_plan};
use crate::prune::profile_candidates;
use crate::replayer::{Replayer, finite, mean};
use node::replay_nodes;
use profile::{Measured, fit_nodes, profile};

/// Profile the shader over the session. Phases: the nodes and the journal, the reference, the
/// ceiling ([`ceiling::measure_ceiling`]: where even that cannot pay, no node is replayed), the
/// replays node by node ([`replay_nodes`]), the fits ([`fit_nodes`]), the sets, then the
/// profile ([`profile`]).
pub fn analyze(
    input: &AnalyzeInput,
    renderer: &Renderer,
    opts: &AnalyzeOptions,
    progress: &dyn Progress,
) -> Result<Profile, AnalyzeError> {
    let started = Instant::now();
    let period_warnings = check_periods(
        opts,
        opts.max_frames
            .map_or(input.session.frames, |m| m.min(input.session.frames)),
    )?;
    for w in &period_warnings {
        progress.note(&format!("warning: {w}"));
    }
    let ids = node_ids(input, opts)?;
    // The longest training period first: it is the fastest a variant gets, so a node whose variant is
    // slower than the original even there can never be chosen and is set aside at once.
    let longest = *opts.delta_n_train.iter().max().expect("checked above");
    let plan = period_plan(opts, longest);
    if opts.strategies.is_empty() {
        return Err(AnalyzeError::Options("no strategy to profile".into()));
    }
    let extra = opts.strategies.len() - 1;
    let session_frames = opts
        .max_frames
        .map_or(input.session.frames, |m| m.min(input.session.frames))
        .max(1);
    let stride = opts
        .perceptual_stride
        .unwrap_or(session_frames.div_ceil(DEFAULT_PERCEPTUAL_FRAMES));
    let journal = open_journal(input, renderer, opts, &ids, stride, progress)?;
    // Per node: each strategy instanced (or pruned), the race, the longest period and the plan.
    progress.start(3 + (ids.len() * (3 + plan.len() + extra)) as u64);
    let (reference, render_opts, time) = render_reference(input, renderer, opts, stride)?;
    progress.step("original");
    let (mut original, mean_pixels) = original_record(&reference, progress);
    let mut journal = journal;
    if let Some(j) = &mut journal {
        // A resumed run keeps the first run's original times: they decide what is set aside.
        original = j.original(original)?;
    }
    let mut rp = Replayer {
        renderer,
        input,
        reference: &reference,
        render_opts,
        opts,
        progress,
        journal,
        time,
        original_ms: original.frame_ms,
        longest,
        timing_warnings: Vec::new(),
        clock: None,
    };
    let ceiling = if opts.ceiling {
        ceiling::measure_ceiling(&mut rp)?
    } else {
        None
    };
    // Where it pays, said before the long part (where it does not, the summary says why).
    if let Some(c) = ceiling.as_ref().filter(|c| c.pays) {
        progress.note(&c.to_string());
    }
    let pays = ceiling.as_ref().is_none_or(|c| c.pays);
    let replays = if pays {
        replay_nodes(&mut rp, &ids, &plan)?
    } else {
        node::Replays::default()
    };
    let t = Instant::now();
    let (hit_rate, nodes) = fit_nodes(&rp, &replays.raws, mean_pixels);
    rp.time.fitting_s += t.elapsed().as_secs_f64();
    let sets = match &opts.sets {
        // A shard sees only its part of the nodes: sets are searched over whole analyses.
        Some(set_opts) if pays && ids.len() > 1 && opts.shard.is_none() => {
            crate::sets::analyze_sets(&mut rp, &nodes, &hit_rate, mean_pixels, set_opts)?
        }
        _ => Vec::new(),
    };
    progress.finish();
    if let Some(j) = &rp.journal {
        progress.note(&format!(
            "replayed {}, reused {} recorded by an earlier run; raced {}, reused {}",
            j.recorded, j.reused, j.races_recorded, j.races_reused
        ));
    }
    let mut time = rp.time;
    time.total_s = started.elapsed().as_secs_f64();
    Ok(profile(
        input,
        renderer,
        opts,
        Measured {
            frames: reference.frames.len() as u32,
            stride,
            original,
            hit_rate,
            nodes,
            replays,
            sets,
            time,
            timing_warnings: rp.timing_warnings,
            clock: rp.clock,
            ceiling,
        },
    ))
}

/// The nodes to profile: `--nodes` checked against the table (the root added), or the pruned
/// candidates; a shard's share of them.
fn node_ids(input: &AnalyzeInput, opts: &AnalyzeOptions) -> Result<Vec<u32>, AnalyzeError> {
    let ids = match &opts.nodes {
        Some(ids) => {
            let mut ids = ids.clone();
            for id in &ids {
                match input.table.get(*id) {
                    None => {
                        return Err(AnalyzeError::Options(format!(
                            "no node {id} in {}",
                            input.table.shader
                        )));
                    }
                    Some(n) if !n.cacheable => {
                        return Err(AnalyzeError::Options(format!(
                            "node {id} (`{}`) is culled as {}",
                            n.text,
                            n.reason.map_or("?", |r| r.as_str())
                        )));
                    }
                    _ => {}
                }
            }
            ids.push(input.table.root().id);
            ids.sort_unstable();
            ids.dedup();
            ids
        }
        None => profile_candidates(input.table, &opts.prune),
    };
    let ids: Vec<u32> = match opts.shard {
        None => ids,
        Some(Shard { index, count }) => ids
            .into_iter()
            .enumerate()
            .filter(|(p, _)| *p as u32 % count == index)
            .map(|(_, id)| id)
            .collect(),
    };
    Ok(ids)
}

/// The journal of this analysis (`--journal`), keyed by everything a replay's result depends
/// on, with a note when it resumes.
fn open_journal(
    input: &AnalyzeInput,
    renderer: &Renderer,
    opts: &AnalyzeOptions,
    ids: &[u32],
    stride: u32,
    progress: &dyn Progress,
) -> Result<Option<Journal>, AnalyzeError> {
    let Some(j) = &opts.journal else {
        return Ok(None);
    };
    let key = content_hash(
        format!(
            "{} {} {:?} {:?} {ids:?} {:?} {:?} {:?} {:?} {} {:?} {} {:?} {}",
            content_hash(input.shader.source.as_bytes()),
            content_hash(input.session_bytes),
            opts.delta_n_train,
            opts.delta_n_holdout,
            opts.strategies,
            opts.block,
            opts.instance,
            opts.max_frames,
            renderer.adapter().name,
            renderer.timing_method(),
            stride,
            opts.probe_frames,
            input.norm.unroll.max_trip,
        )
        .as_bytes(),
    );
    let (journal, note) = Journal::open(j, &key)?;
    if let Some(note) = note {
        progress.note(&note);
    }
    if journal.len() > 0 {
        progress.note(&format!(
            "resuming: {} replays already done in {} (--fresh starts over)",
            journal.len(),
            j.path.display()
        ));
    }
    Ok(Some(journal))
}

/// The original's reference replay over the session (the options every whole-session replay
/// shares), and the time it took.
fn render_reference(
    input: &AnalyzeInput,
    renderer: &Renderer,
    opts: &AnalyzeOptions,
    stride: u32,
) -> Result<(reproj_replay::Reference, RenderOptions, AnalysisTime), AnalyzeError> {
    let render_opts = RenderOptions {
        png_dir: None,
        max_frames: opts.max_frames,
        first_frame: 0,
        timing_only: false,
        classify: false,
        raw_frames: false,
        perceptual_stride: Some(stride),
    };
    let mut time = AnalysisTime::default();
    let t = Instant::now();
    let entry = input.shader.fragment_entry(Some(&input.norm.entry))?;
    let reference = renderer.render_original(input.shader, entry, input.session, &render_opts)?;
    time.reference_s = t.elapsed().as_secs_f64();
    Ok((reference, render_opts, time))
}

/// The original's record from its reference replay (frame 0, which compiles shaders, left out)
/// and its mean shaded pixels; a warning when it renders non-finite pixels.
fn original_record(
    reference: &reproj_replay::Reference,
    progress: &dyn Progress,
) -> (OriginalRecord, f64) {
    let original_frames: Vec<_> = reference.report.frames.iter().skip(1).collect();
    let mean_pixels = mean(original_frames.iter().map(|f| f.shaded as f64));
    let original = OriginalRecord {
        frame_ms: finite(reference.report.frame_ms),
        mean_pixels,
        frame_times_ms: original_frames.iter().map(|f| finite(f.frame_ms)).collect(),
        nonfinite_pixels: reference.report.nonfinite_pixels,
    };
    if let Some(first) = reference.report.frames.iter().find(|f| f.nonfinite > 0) {
        progress.note(&format!(
            "warning: the original shader renders {} pixels that are NaN or infinite over the session (first in frame {}); they are left out of every error measured, and the profile records them",
            reference.report.nonfinite_pixels, first.frame
        ));
    }
    (original, mean_pixels)
}
