//! `emit --verify`: re-render what `emit` chose over a session and record the measured error,
//! perceptual metrics and speed (the timing engine's interleaved estimate) beside the prediction.

use std::path::Path;

use reproj_instance::Variant;
use reproj_metrics::PSNR_CAP;
use reproj_models::Profile;
use reproj_replay::{RenderOptions, Renderer, VariantInput};
use reproj_scene::Session;

use crate::AnalyzeError;
use reproj_emit::{EmitReport, write_report};

/// Re-render the selection over `session`, record measured error and speedup in `report`, and
/// rewrite `out/report.json` (`out`: the directory [`reproj_emit::emit()`] wrote into; the shader is the one the
/// report names). The error comes from one replay of the whole session; the speed from the
/// timing engine (`reproj-bench`: original and variant interleaved, with an interval), under
/// `timing`.
pub fn verify(
    report: &mut EmitReport,
    out: &Path,
    variant: Option<&Variant>,
    (profile, profile_path): (&Profile, &Path),
    session: &Session,
    renderer: &Renderer,
    timing: &reproj_bench::BenchOptions,
) -> Result<(), AnalyzeError> {
    let opts = render_options(Some(
        profile
            .perceptual_stride
            .unwrap_or(crate::options::DEFAULT_PERCEPTUAL_STRIDE),
    ));
    let (shader, entry, reference) =
        original(report, (profile, profile_path), session, renderer, &opts)?;
    report.measured_original_ms = Some(reference.report.frame_ms);
    report.measured_on = Some(reproj_bench::Machine::of(renderer).describe());
    match variant {
        None => {
            // The original shader kept: nothing to race it against, so no speedup and no
            // interval (a 1.00x [1.00, 1.00] would read as a measurement).
            report.measured_error = Some(0.0);
            report.measured_psnr = Some(PSNR_CAP);
            report.measured_ms = Some(reference.report.frame_ms);
            report.measured_speedup = None;
            report.measured_speedup_ci95 = None;
        }
        Some(v) => {
            let mut input = VariantInput::new(
                v.passes.iter().map(|p| p.wgsl.clone()).collect(),
                v.manifest.clone(),
                report.delta_n.unwrap_or(1),
            );
            if report.adaptive.is_some() {
                // As a host applies the schedule: each frame's Δn from its measured motion.
                input.delta_n_per_frame =
                    reproj_emit::motion::adaptive_periods(&v.manifest.params, session);
            }
            let r = renderer.render_variant(&shader, session, &input, &reference, &opts)?;
            if let (Some(a), Some(periods)) = (report.adaptive.as_mut(), &input.delta_n_per_frame) {
                // Each band of the schedule promises the budget: the worst band's mean error.
                let mut by_period: std::collections::BTreeMap<u32, (f64, u32)> = Default::default();
                for fr in &r.frames {
                    if let Some(&dn) = periods.get(fr.frame as usize) {
                        let e = by_period.entry(dn).or_default();
                        e.0 += fr.error;
                        e.1 += 1;
                    }
                }
                let worst = by_period
                    .iter()
                    .map(|(&dn, &(sum, n))| (dn, sum / f64::from(n.max(1))))
                    .max_by(|a, b| a.1.total_cmp(&b.1));
                a.measured_worst_band = worst.map(|(dn, e)| reproj_emit::motion::BandError {
                    delta_n: dn,
                    frames: by_period[&dn].1,
                    error: e,
                });
            }
            report.measured_error = Some(r.error);
            report.measured_nonfinite_pixels = Some(r.nonfinite_pixels).filter(|&n| n > 0);
            report.measured_nonfinite_reference_pixels =
                Some(r.nonfinite_reference_pixels).filter(|&n| n > 0);
            report.measured_psnr = Some(r.psnr).filter(|p| p.is_finite());
            report.measured_flip = r.flip;
            report.measured_ssim = r.ssim;
            let timed = reproj_bench::bench(
                renderer,
                reproj_bench::Baseline {
                    shader: &shader,
                    entry,
                    reference: &reference,
                },
                session,
                &[reproj_bench::Candidate {
                    name: "the variant".into(),
                    subject: reproj_bench::Subject::Variant(input),
                }],
                timing,
                &mut |_| {},
            )?;
            let c = &timed.candidates[0];
            report.measured_original_ms = Some(timed.baseline.median_ms);
            report.measured_ms = c.median_ms;
            report.measured_speedup = c.speedup;
            report.measured_speedup_ci95 = c.speedup_ci95;
            report.measured_rounds = Some(timed.rounds);
            report.timing_warnings = timed.warnings;
        }
    }
    if let Some(w) = other_machine(&profile.machine, &reproj_bench::Machine::of(renderer)) {
        report.timing_warnings.insert(0, w);
    }
    Ok(write_report(report, out)?)
}

/// A warning where the profile was measured on another adapter or driver than `here`: the
/// strategies and filters it raced and the speeds it predicts come from there (lavapipe keeps
/// `2pass` in Mesa 22.3 and `fused` in Mesa 25 for marble, one adapter name for both). A profile
/// that names no driver (before version 11) is compared by its adapter alone.
pub(crate) fn other_machine(
    there: &reproj_models::profile::Machine,
    here: &reproj_bench::Machine,
) -> Option<String> {
    let same_driver = there.driver.as_deref().is_none_or(|d| d == here.driver);
    if there.adapter == here.adapter && same_driver {
        return None;
    }
    Some(format!(
        "the profile was measured on {}, this run on {}: the strategies and filters it raced and the speeds it predicts come from there; re-run `reproj analyze` on this machine to choose for it",
        there.device(),
        reproj_models::profile::device_name(&here.adapter, Some(&here.driver))
    ))
}

/// The runoff (`emit --verify`, [`reproj_emit::contenders`]): every contender timed against the
/// original in one interleaved run (`reproj-bench`, under `timing`), over `session` with the
/// profiled shader. Returns what the report keeps and the index of the contender to write: the
/// highest measured speedup — one run on this machine, the contenders side by side, is better
/// evidence than predictions each scaled to its own short race at another moment — or the
/// prediction's choice where no contender has a figure.
pub fn runoff(
    contenders: &[reproj_emit::Contender],
    report: &EmitReport,
    (profile, profile_path): (&Profile, &Path),
    session: &Session,
    renderer: &Renderer,
    timing: &reproj_bench::BenchOptions,
    progress: &mut dyn FnMut(&reproj_bench::Progress<'_>),
) -> Result<(reproj_emit::Runoff, usize), AnalyzeError> {
    let (shader, entry, reference) = original(
        report,
        (profile, profile_path),
        session,
        renderer,
        &render_options(None),
    )?;
    let candidates: Vec<reproj_bench::Candidate> = contenders
        .iter()
        .map(|c| reproj_bench::Candidate {
            name: format!("node {} at Δn {}", c.node, c.selection.delta_n),
            subject: reproj_bench::Subject::Variant(VariantInput::new(
                c.variant.passes.iter().map(|p| p.wgsl.clone()).collect(),
                c.variant.manifest.clone(),
                c.selection.delta_n,
            )),
        })
        .collect();
    let timed = reproj_bench::bench(
        renderer,
        reproj_bench::Baseline {
            shader: &shader,
            entry,
            reference: &reference,
        },
        session,
        &candidates,
        timing,
        progress,
    )?;
    let predicted = contenders
        .iter()
        .position(|c| c.chosen_by_prediction)
        .unwrap_or(0);
    let winner = timed
        .candidates
        .iter()
        .enumerate()
        .filter_map(|(i, c)| Some((i, c.speedup?)))
        .max_by(|a, b| a.1.total_cmp(&b.1))
        .map_or(predicted, |(i, _)| i);
    let entries = contenders
        .iter()
        .zip(&timed.candidates)
        .enumerate()
        .map(|(i, (c, t))| reproj_emit::RunoffEntry {
            node: c.node.clone(),
            strategy: c.selection.strategy.clone(),
            delta_n: c.selection.delta_n,
            predicted_error: c.selection.predicted_error,
            predicted_speedup: c.selection.predicted_speedup,
            predicted_speedup_ci95: c.selection.predicted_speedup_ci95,
            measured_speedup: t.speedup,
            measured_speedup_ci95: t.speedup_ci95,
            predicted_choice: c.chosen_by_prediction,
            written: i == winner,
        })
        .collect();
    Ok((
        reproj_emit::Runoff {
            rounds: timed.rounds,
            entries,
            changed: winner != predicted,
        },
        winner,
    ))
}

/// A whole-session replay that keeps its frames (the reference variants replay against), with the
/// perceptual metrics on every `perceptual_stride`-th frame where given.
fn render_options(perceptual_stride: Option<u32>) -> RenderOptions {
    RenderOptions {
        png_dir: None,
        max_frames: None,
        first_frame: 0,
        timing_only: false,
        classify: false,
        raw_frames: false,
        perceptual_stride,
    }
}

/// The shader `report` names (the profiled one, read as the profile says) as WGSL, its profiled
/// entry point, and its reference replay over `session`.
fn original(
    report: &EmitReport,
    (profile, profile_path): (&Profile, &Path),
    session: &Session,
    renderer: &Renderer,
    opts: &RenderOptions,
) -> Result<(reproj_front::Shader, usize, reproj_replay::Reference), AnalyzeError> {
    let input = reproj_emit::profile_shader_input(profile, profile_path)?;
    let shader =
        reproj_front::load_file_with(Path::new(&report.shader), None, &input)?.to_wgsl()?;
    let entry = shader.fragment_entry(Some(&profile.entry))?;
    let reference = renderer.render_original(&shader, entry, session, opts)?;
    Ok((shader, entry, reference))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn here(driver: &str) -> reproj_bench::Machine {
        reproj_bench::Machine {
            adapter: "llvmpipe (LLVM 15.0.6, 256 bits)".into(),
            device_type: "Cpu".into(),
            cpu_rasterizer: true,
            lp_num_threads: Some("2".into()),
            cpus: 2,
            driver: driver.into(),
        }
    }

    fn there(adapter: &str, driver: Option<&str>) -> reproj_models::profile::Machine {
        reproj_models::profile::Machine {
            adapter: adapter.into(),
            backend: "Vulkan".into(),
            timing_method: "timestamp-queries".into(),
            cpu_cores: 2,
            lp_num_threads: Some("2".into()),
            cpu_rasterizer: true,
            driver: driver.map(Into::into),
            clock: None,
        }
    }

    /// One adapter name, two drivers that choose differently: the driver tells them apart.
    #[test]
    fn a_profile_from_another_driver_is_named() {
        let llvmpipe = "llvmpipe (LLVM 15.0.6, 256 bits)";
        let mesa22 = "Mesa 22.3.6 (LLVM 15.0.6)";
        assert_eq!(
            other_machine(&there(llvmpipe, Some(mesa22)), &here(mesa22)),
            None
        );
        // Before version 11 a profile names no driver: the adapter alone decides.
        assert_eq!(other_machine(&there(llvmpipe, None), &here(mesa22)), None);
        let w = other_machine(
            &there(llvmpipe, Some("Mesa 25.0.7 (LLVM 15.0.6)")),
            &here(mesa22),
        )
        .unwrap();
        assert!(w.contains("Mesa 25.0.7") && w.contains(mesa22), "{w}");
        let w = other_machine(&there("NVIDIA H200", Some("570.0")), &here(mesa22)).unwrap();
        assert!(
            w.contains("NVIDIA H200, 570.0") && w.contains("reproj analyze"),
            "{w}"
        );
    }
}
