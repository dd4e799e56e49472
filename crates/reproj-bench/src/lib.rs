//! reproj's timing engine: the one place a speed figure is measured.
//!
//! A speedup is a ratio of two timings, and on a shared machine (or a GPU whose clocks move) two
//! replays taken at different moments measure the load as much as the shader. So [`bench`] renders
//! the baseline (the original shader) and every candidate (a variant, or another shader) in
//! *rounds*: each round picks a window of the session, and each subject renders that window as one
//! short block — its first frame discarded (shader compilation, a variant's empty cache), the rest
//! timed by the renderer's GPU timestamps — in an order that alternates between rounds. Each round
//! gives one paired ratio per candidate; [`reproj_models::speedup`] turns the ratios into a
//! Hodges–Lehmann estimate with a bootstrap 95 % interval, decides when to stop (interval within
//! ±3 % or the time cap) and says what it saw of the machine (the baseline's own time moving, other
//! processes busy, a wide interval) as warnings. The per-block figures are kept in the result.
//!
//! Analyze, `emit --verify`, `compare`, `render` and `reproj bench` all measure through here.

use std::time::Instant;

use reproj_front::Shader;
use reproj_models::speedup::{
    self, Conditions, SpeedupEstimate, StopRule, Subject as Slot, block_ms, round_order, stratum,
    window_start,
};
pub use reproj_models::speedup::{DEFAULT_SETTLE, Settle, Settling};
use reproj_replay::{Reference, RenderOptions, Renderer, ReplayError, VariantInput};
use reproj_scene::Session;
use serde::{Deserialize, Serialize};

mod limit;
mod settle;

pub use limit::{Limit, limit_of};

/// Schema name and version of [`BenchReport`] (`docs/SCHEMAS.md`).
pub const BENCH_SCHEMA: &str = "reproj.bench";
pub const BENCH_VERSION: u32 = 2;

/// Timed frames per block by default (after the discarded first frame).
pub const DEFAULT_BLOCK_FRAMES: u32 = 12;

/// What a candidate renders.
// A run holds a handful of candidates: their size does not matter.
#[allow(clippy::large_enum_variant)]
#[derive(Debug, Clone)]
pub enum Subject {
    /// A cached variant of the baseline shader.
    Variant(VariantInput),
    /// Another shader (a hand-optimized version, the original itself for the A/A check, or a
    /// simplified one): its fragment entry point `entry`, over the same session or over
    /// `session` (the same frames at another resolution: `compare`'s resize).
    Shader {
        shader: Box<Shader>,
        entry: usize,
        session: Option<Box<Session>>,
    },
    /// The baseline shader's temporal upsampling ([`Renderer::render_upsampled`]): drawn at a
    /// lower resolution with a jitter and resolved to the session's, both passes timed.
    Upsampled(reproj_replay::UpsampleSpec),
    /// A cached variant of the baseline shader drawn inside the temporal upsampler
    /// ([`Renderer::render_upsampled_variant`]): its passes and the resolve timed.
    UpsampledVariant(VariantInput, reproj_replay::UpsampleSpec),
}

/// One candidate, named as the report will name it.
#[derive(Debug, Clone)]
pub struct Candidate {
    pub name: String,
    pub subject: Subject,
}

/// The baseline: the original shader, and its reference frames over the whole session (a
/// variant's replay compares against them).
#[derive(Debug, Clone, Copy)]
pub struct Baseline<'a> {
    pub shader: &'a Shader,
    pub entry: usize,
    pub reference: &'a Reference,
}

/// How to measure.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BenchOptions {
    /// Timed frames per block (each block renders one more, discarded).
    pub block_frames: u32,
    /// Rounds and time.
    pub stop: StopRule,
    /// Use only the session's first N frames for the windows.
    pub max_frames: Option<u32>,
    /// Render the baseline until the device's clock has settled before the first round
    /// (`None`: time at once).
    pub settle: Option<Settle>,
}

impl Default for BenchOptions {
    fn default() -> Self {
        BenchOptions {
            block_frames: DEFAULT_BLOCK_FRAMES,
            stop: StopRule::default(),
            max_frames: None,
            settle: Some(DEFAULT_SETTLE),
        }
    }
}

/// Where a run stands, after each round.
#[derive(Debug, Clone)]
pub struct Progress<'a> {
    pub rounds: u32,
    pub seconds: f64,
    pub estimates: &'a [Option<SpeedupEstimate>],
}

/// The machine the figures come from: what a reader needs to compare them with others.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Machine {
    pub adapter: String,
    /// The adapter's device type as wgpu reports it (`Cpu` for lavapipe).
    pub device_type: String,
    /// A CPU rasterizer (lavapipe, llvmpipe): its figures say nothing of a GPU's.
    pub cpu_rasterizer: bool,
    /// `LP_NUM_THREADS` as set for this process (lavapipe's rasterizer threads), if set.
    pub lp_num_threads: Option<String>,
    /// Cores the process may use.
    pub cpus: u32,
    /// The driver and its version as the adapter reports them (`Mesa 22.3.6 (LLVM 15.0.6)`);
    /// empty where it reports none (and in reports written before it was recorded).
    #[serde(default, skip_serializing_if = "String::is_empty")]
    pub driver: String,
}

impl Machine {
    /// The machine `renderer` runs on.
    pub fn of(renderer: &Renderer) -> Machine {
        let a = renderer.adapter();
        let cpu = a.is_cpu_rasterizer();
        Machine {
            adapter: a.name.clone(),
            device_type: a.device_type.clone(),
            cpu_rasterizer: cpu,
            lp_num_threads: std::env::var("LP_NUM_THREADS").ok(),
            cpus: std::thread::available_parallelism().map_or(1, |n| n.get() as u32),
            driver: driver_of(a),
        }
    }

    /// One line for the reader: `llvmpipe (LLVM 15), Mesa 22.3.6 (LLVM 15), LP_NUM_THREADS=2, 2
    /// cores — a CPU rasterizer: GPU figures differ`.
    pub fn describe(&self) -> String {
        let mut s = format!(
            "{}, LP_NUM_THREADS={}, {} cores",
            reproj_models::profile::device_name(&self.adapter, Some(&self.driver)),
            self.lp_num_threads.as_deref().unwrap_or("unset"),
            self.cpus
        );
        if self.cpu_rasterizer {
            s.push_str(" — measured on a CPU rasterizer: GPU figures differ");
        }
        s
    }
}

/// The driver and its version as `adapter` reports them: its `driver_info` (`Mesa 22.3.6 (LLVM
/// 15.0.6)`), else its driver's name, else empty. An adapter's name alone does not tell drivers
/// apart (lavapipe is `llvmpipe (LLVM 15.0.6, 256 bits)` in Mesa 22.3 and in Mesa 25, which differ
/// in what they skip).
pub fn driver_of(adapter: &reproj_metrics::AdapterReport) -> String {
    if adapter.driver_info.trim().is_empty() {
        adapter.driver.trim().to_string()
    } else {
        adapter.driver_info.trim().to_string()
    }
}

/// The baseline's figures.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct BaselineFigure {
    /// Median of the block figures, ms per frame.
    pub median_ms: f64,
    /// Each round's block figure (trimmed mean of its timed frames), in round order.
    pub blocks_ms: Vec<f64>,
    /// Each round's window (0 to 3, the quarters of the session), in round order.
    pub windows: Vec<u32>,
}

/// One candidate's figures.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct CandidateFigure {
    pub name: String,
    /// Median of the block figures, ms per frame (`null` when no frame time was usable).
    pub median_ms: Option<f64>,
    /// Baseline time over candidate time (above 1: faster), Hodges–Lehmann over the rounds.
    pub speedup: Option<f64>,
    /// Its 95 % interval (percentile bootstrap).
    pub speedup_ci95: Option<[f64; 2]>,
    pub rounds: u32,
    /// Rounds whose ratio lies far from the others (counted, kept in the robust estimate).
    pub outliers: u32,
    pub blocks_ms: Vec<f64>,
}

/// What a run measured (`reproj.bench` v1, `docs/SCHEMAS.md`).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct BenchReport {
    pub schema: String,
    pub version: u32,
    pub machine: Machine,
    /// Timed frames per block, and the frames the windows were drawn from.
    pub block_frames: u32,
    pub session_frames: u32,
    pub rounds: u32,
    pub seconds: f64,
    /// Share of the CPU other processes used while measuring (Linux; `null` elsewhere).
    pub others_cpu: Option<f64>,
    pub baseline: BaselineFigure,
    pub candidates: Vec<CandidateFigure>,
    /// What the baseline's settling saw before the first round (version 2; absent where the run
    /// was told not to settle, and in older reports).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub settling: Option<Settling>,
    /// Empty when the run was clean.
    pub warnings: Vec<String>,
}

/// Add `warning` to `seen` unless one of its kind (the text before its first `:`) is there
/// already: runs that time many candidates one after another (analyze's races, compare's
/// searches) say each kind of condition once. Whether it was added.
pub fn add_warning_once(seen: &mut Vec<String>, warning: &str) -> bool {
    let kind = warning.split(':').next().unwrap_or(warning);
    if seen.iter().any(|o| o.starts_with(kind)) {
        return false;
    }
    seen.push(warning.to_owned());
    true
}

impl BenchReport {
    /// Candidate `i`'s estimate, when it has one.
    pub fn estimate(&self, i: usize) -> Option<SpeedupEstimate> {
        let c = self.candidates.get(i)?;
        Some(SpeedupEstimate {
            speedup: c.speedup?,
            ci95: c.speedup_ci95?,
            rounds: c.rounds,
            outliers: c.outliers,
            baseline_ms: self.baseline.median_ms,
            candidate_ms: c.median_ms?,
        })
    }

    /// Candidate `i`'s estimate from this run's rounds and those of candidate `j` of `other`, a
    /// second run of the same candidate against the same baseline over the same windows: the
    /// rounds of both, each in its window, in one estimate ([`speedup::estimate`]). `None` when
    /// no round has figures.
    pub fn pooled_estimate(
        &self,
        i: usize,
        other: &BenchReport,
        j: usize,
    ) -> Option<SpeedupEstimate> {
        let (a, b) = (self.candidates.get(i)?, other.candidates.get(j)?);
        let strata: Vec<u32> = [&self.baseline.windows, &other.baseline.windows]
            .into_iter()
            .flatten()
            .copied()
            .collect();
        let base: Vec<f64> = [&self.baseline.blocks_ms, &other.baseline.blocks_ms]
            .into_iter()
            .flatten()
            .copied()
            .collect();
        let cand: Vec<f64> = [&a.blocks_ms, &b.blocks_ms]
            .into_iter()
            .flatten()
            .copied()
            .collect();
        if strata.len() != base.len() || base.len() != cand.len() {
            return None;
        }
        speedup::estimate(&strata, &base, &cand)
    }
}

/// Measure every candidate against the baseline, interleaved (see the crate docs). `progress` is
/// called after each round.
pub fn bench(
    renderer: &Renderer,
    baseline: Baseline<'_>,
    session: &Session,
    candidates: &[Candidate],
    opts: &BenchOptions,
    progress: &mut dyn FnMut(&Progress<'_>),
) -> Result<BenchReport, ReplayError> {
    let frames = opts
        .max_frames
        .map_or(session.frames, |m| m.min(session.frames))
        .min(baseline.reference.frames.len() as u32)
        .max(1);
    // One discarded frame ahead of the timed ones, when the session has room for it.
    let timed = opts
        .block_frames
        .max(1)
        .min(frames.saturating_sub(1).max(1));
    let warm = u32::from(frames > timed);
    let block_len = timed + warm;
    let scene = Scene {
        renderer,
        baseline,
        session,
        candidates,
    };

    // Warm-up, not recorded: every subject builds its pipelines once; then the baseline renders
    // until the device's clock has settled.
    for who in round_order(0, candidates.len()) {
        scene.block(who, 0, block_len.min(2))?;
    }
    let settling = match opts.settle {
        Some(s) => Some(scene.settle(&s, window_start(0, frames, block_len), block_len, warm)?),
        None => None,
    };
    let t0 = Instant::now();
    let cpu0 = cpu_ticks();
    let mut runs = Runs {
        strata: Vec::new(),
        baseline: Vec::new(),
        candidates: vec![Vec::new(); candidates.len()],
        estimates: vec![None; candidates.len()],
    };
    loop {
        let round = runs.strata.len() as u32;
        let start = window_start(round, frames, block_len);
        let mut got: Vec<(Slot, f64)> = Vec::new();
        for who in round_order(round, candidates.len()) {
            let ms = scene.block(who, start, block_len)?;
            let figure = block_ms(&ms[(warm as usize).min(ms.len())..]).unwrap_or(f64::NAN);
            got.push((who, figure));
        }
        runs.record(stratum(round), got);
        let seconds = t0.elapsed().as_secs_f64();
        let rounds = runs.strata.len() as u32;
        progress(&Progress {
            rounds,
            seconds,
            estimates: &runs.estimates,
        });
        if opts.stop.done(rounds, seconds, &runs.estimates) {
            break;
        }
    }
    let others_cpu = match (cpu0, cpu_ticks()) {
        (Some(a), Some(b)) => others_share(a, b),
        _ => None,
    };
    let mut report = runs.report(
        renderer,
        candidates,
        opts,
        [timed, frames],
        t0.elapsed().as_secs_f64(),
        others_cpu,
    );
    if let Some(w) = settling.as_ref().and_then(Settling::warning) {
        report.warnings.insert(0, w);
    }
    report.settling = settling;
    Ok(report)
}

/// What renders a block: the renderer, the baseline and the candidates over the session.
struct Scene<'a> {
    renderer: &'a Renderer,
    baseline: Baseline<'a>,
    session: &'a Session,
    candidates: &'a [Candidate],
}

impl Scene<'_> {
    /// Render `who` over frames `first..first + len`, timing only: each frame's time, ms.
    fn block(&self, who: Slot, first: u32, len: u32) -> Result<Vec<f64>, ReplayError> {
        let o = RenderOptions {
            png_dir: None,
            max_frames: Some(len),
            first_frame: first,
            timing_only: true,
            classify: false,
            raw_frames: false,
            perceptual_stride: None,
        };
        let (r, b, session) = (self.renderer, self.baseline, self.session);
        let recs = match who {
            Slot::Baseline => {
                r.render_original(b.shader, b.entry, session, &o)?
                    .report
                    .frames
            }
            Slot::Candidate(i) => match &self.candidates[i].subject {
                Subject::Variant(v) => {
                    r.render_variant(b.shader, session, v, b.reference, &o)?
                        .frames
                }
                Subject::Shader {
                    shader,
                    entry,
                    session: own,
                } => {
                    r.render_original(shader, *entry, own.as_deref().unwrap_or(session), &o)?
                        .report
                        .frames
                }
                Subject::Upsampled(spec) => {
                    r.render_upsampled(b.shader, b.entry, session, spec, &o)?
                        .report
                        .frames
                }
                Subject::UpsampledVariant(v, spec) => {
                    r.render_upsampled_variant(b.shader, session, v, spec, &o)?
                        .report
                        .frames
                }
            },
        };
        Ok(recs.iter().map(|r| r.frame_ms).collect())
    }
}

/// The block figures of a run so far, and the candidates' estimates from them.
struct Runs {
    strata: Vec<u32>,
    baseline: Vec<f64>,
    candidates: Vec<Vec<f64>>,
    estimates: Vec<Option<SpeedupEstimate>>,
}

impl Runs {
    /// Add one round, measured on window `stratum`, and estimate again.
    fn record(&mut self, stratum: u32, got: Vec<(Slot, f64)>) {
        for (who, figure) in got {
            match who {
                Slot::Baseline => self.baseline.push(figure),
                Slot::Candidate(i) => self.candidates[i].push(figure),
            }
        }
        self.strata.push(stratum);
        for (e, c) in self.estimates.iter_mut().zip(&self.candidates) {
            *e = speedup::estimate(&self.strata, &self.baseline, c);
        }
    }

    /// The report of the finished run, with its warnings.
    fn report(
        self,
        renderer: &Renderer,
        candidates: &[Candidate],
        opts: &BenchOptions,
        [timed, frames]: [u32; 2],
        seconds: f64,
        others_cpu: Option<f64>,
    ) -> BenchReport {
        let rounds = self.strata.len() as u32;
        let named: Vec<(String, Option<SpeedupEstimate>)> = candidates
            .iter()
            .zip(&self.estimates)
            .map(|(c, e)| (c.name.clone(), *e))
            .collect();
        let mut warnings = speedup::condition_warnings(
            &self.strata,
            &self.baseline,
            &named,
            &Conditions { others_cpu },
        );
        let wide = self
            .estimates
            .iter()
            .flatten()
            .any(|e| e.half_width() > opts.stop.target_half_width);
        if wide {
            let limit = if rounds >= opts.stop.max_rounds.max(1) {
                Limit::Rounds
            } else {
                Limit::Time
            };
            let target = opts.stop.target_half_width * 100.0;
            warnings.push(limit::wide_warning(limit, target, rounds, seconds));
        }
        let finite_median = |v: &[f64]| {
            let f: Vec<f64> = v.iter().copied().filter(|x| x.is_finite()).collect();
            (!f.is_empty()).then(|| speedup::median(&f))
        };
        BenchReport {
            schema: BENCH_SCHEMA.into(),
            version: BENCH_VERSION,
            machine: Machine::of(renderer),
            block_frames: timed,
            session_frames: frames,
            rounds,
            seconds,
            others_cpu,
            baseline: BaselineFigure {
                median_ms: finite_median(&self.baseline).unwrap_or(0.0),
                blocks_ms: self.baseline,
                windows: self.strata,
            },
            candidates: candidates
                .iter()
                .zip(&self.estimates)
                .zip(self.candidates)
                .map(|((c, e), blocks)| CandidateFigure {
                    name: c.name.clone(),
                    median_ms: finite_median(&blocks),
                    speedup: e.map(|e| e.speedup),
                    speedup_ci95: e.map(|e| e.ci95),
                    rounds: e.map_or(0, |e| e.rounds),
                    outliers: e.map_or(0, |e| e.outliers),
                    blocks_ms: blocks,
                })
                .collect(),
            settling: None,
            warnings,
        }
    }
}

/// CPU time counters: (all CPUs busy, all CPUs total, this process), in clock ticks.
type Ticks = (u64, u64, u64);

/// The machine's and this process's CPU time so far (Linux `/proc`; `None` elsewhere).
fn cpu_ticks() -> Option<Ticks> {
    let stat = std::fs::read_to_string("/proc/stat").ok()?;
    let cpu: Vec<u64> = stat
        .lines()
        .next()?
        .split_whitespace()
        .skip(1)
        .filter_map(|x| x.parse().ok())
        .collect();
    if cpu.len() < 4 {
        return None;
    }
    // user nice system idle iowait irq softirq steal ...
    let total: u64 = cpu.iter().take(8).sum();
    let idle = cpu[3] + cpu.get(4).copied().unwrap_or(0);
    let own = std::fs::read_to_string("/proc/self/stat").ok()?;
    // Fields after the command name (which may hold spaces, in parentheses).
    let rest = &own[own.rfind(')')? + 2..];
    let f: Vec<&str> = rest.split_whitespace().collect();
    // utime and stime are fields 14 and 15 of the line: 11 and 12 after the name.
    let me = f.get(11)?.parse::<u64>().ok()? + f.get(12)?.parse::<u64>().ok()?;
    Some((total - idle, total, me))
}

/// Share of all CPU time between `a` and `b` that other processes used.
fn others_share(a: Ticks, b: Ticks) -> Option<f64> {
    let total = b.1.checked_sub(a.1)?;
    if total == 0 {
        return None;
    }
    let busy = b.0.saturating_sub(a.0);
    let me = b.2.saturating_sub(a.2);
    Some((busy.saturating_sub(me) as f64 / total as f64).clamp(0.0, 1.0))
}

#[cfg(test)]
mod tests;
