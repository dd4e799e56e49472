//! reproj's own choice at the target speedup: among the profile's error-vs-time Pareto frontier
//! of single nodes (`reproj_select::pareto`, the models `emit` selects with, L2 error) and its
//! measured node sets at every Δn, the point with the least predicted error whose predicted
//! speedup reaches the target, or the fastest point when none does. With an error budget instead,
//! the choice is `emit`'s (`reproj_select::select_with_sets`) and its predicted speedup becomes
//! every method's target. At a target speedup the point is then steered by measurement, as
//! resizing's scale is ([`steer`]): the models' speed on this machine is checked against an
//! interleaved race and the frontier asked again. It is instanced like `emit` does (several nodes
//! in one payload for a set) and rendered with the replay, so its speedup and error are measured
//! in the same run as the other methods'.

use std::path::Path;

use reproj_emit::{EmitError, Profiled, VariantSpec, resolve};
use reproj_front::Loaded;
use reproj_instance::InstanceOptions;
use reproj_models::Profile;
use reproj_replay::{RenderOptions, VariantInput};
use serde::{Deserialize, Serialize};

use crate::{CompareError, Ctx, MethodResult, Scores, Target};

mod search;

use search::{Candidates, Point, at_speedup, under_budget};
pub(crate) use search::{along, steer};

/// What reproj chose.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ReprojDetail {
    pub profile: String,
    /// Node id, `"root"`, or a set's member ids joined by `+` (`"22+39"`).
    pub node: String,
    pub text: String,
    pub strategy: String,
    pub delta_n: u32,
    pub predicted_error: f64,
    /// Profile's original frame time / predicted frame time.
    pub predicted_speedup: f64,
    /// At a target speedup, the points raced on the way ([`steer`]), the reported one among them
    /// unless a rematch replaced it; empty with an error budget (compare.json version 4).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub tries: Vec<ReprojTry>,
    /// At a target speedup, where the final interleaved run put reproj and resizing further apart
    /// than `CompareOptions::equal_time`: reproj moved to resizing's speed in that run, and every
    /// method timed again (compare.json version 5; absent where they were level).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub rematch: Option<Rematch>,
}

/// reproj moved to resizing's speed after the final run put them apart
/// ([`ReprojDetail::rematch`]); the point reported is the new one.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Rematch {
    /// Resizing's speedup in that run: the speed reproj was moved to.
    pub to_speedup: f64,
    /// reproj's speedup in that run, at the point `tries` kept.
    pub from_speedup: f64,
    /// The speedup asked of the profile's models for it: `to_speedup` scaled by that point's
    /// predicted over measured speedup.
    pub asked: f64,
    /// Whether that is another point (rendered, scored and timed again with every method); where
    /// it is the reported point itself, nothing changed.
    pub moved: bool,
}

/// One point [`steer`] raced against the original.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ReprojTry {
    pub node: String,
    pub strategy: String,
    pub delta_n: u32,
    pub predicted_error: f64,
    pub predicted_speedup: f64,
    /// Measured in the search's short interleaved race (0 when it gave no finite figure), or in
    /// two of them pooled when the first left in doubt whether the try is within the tolerance.
    pub speedup: f64,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub speedup_ci95: Option<[f64; 2]>,
    /// How many races the figures pool: 1, or 2 when the first was in doubt (absent before).
    #[serde(default = "crate::ctx::one_race")]
    pub races: u32,
}

pub(crate) struct ReprojRun {
    pub(crate) detail: ReprojDetail,
    /// The variant rendered, for the final interleaved timing.
    pub(crate) input: VariantInput,
    pub(crate) result: MethodResult,
    pub(crate) crop_frame: Vec<f32>,
}

/// reproj's choice before rendering: the profiled node or set and where on its models.
#[derive(Clone, Copy)]
pub(crate) struct Planned<'p> {
    pick: Profiled<'p>,
    delta_n: u32,
    predicted_error: f64,
    /// The profile's original frame time / `predicted_ms`.
    pub(crate) predicted_speedup: f64,
}

/// Choose reproj's (node or set, Δn) from the profile: for a target speedup, the point with the
/// least predicted error that reaches it among the single nodes' frontier and the sets' points
/// (the fastest when none does, [`at_speedup`]); for an error budget, what `emit --max-error`
/// selects ([`under_budget`]).
pub(crate) fn plan<'p>(
    loaded: &Loaded,
    profile: &'p Profile,
    profile_path: &Path,
    target: Target,
    max_delta_n: u32,
) -> Result<Planned<'p>, CompareError> {
    if !reproj_emit::is_profiled_shader(profile, &loaded.shader.to_wgsl()?) {
        return Err(EmitError::Stale {
            path: resolve(&profile.shader.path, profile_path),
            what: "shader".into(),
        }
        .into());
    }
    let c = Candidates::of(profile);
    let point =
        match target {
            Target::Speedup(target) => {
                at_speedup(&c, profile, target, max_delta_n).ok_or_else(|| {
                    CompareError::NoSelection {
                        path: profile_path.to_owned(),
                    }
                })?
            }
            Target::Budget(max_error) => under_budget(&c, profile, max_error, max_delta_n)
                .map_err(|reason| CompareError::KeepsOriginal {
                    path: profile_path.to_owned(),
                    max_error: max_error.get(),
                    reason,
                })?,
        };
    Ok(Planned::at(point, profile))
}

impl<'p> Planned<'p> {
    /// Whether this is the point `detail` reports (same node or set, strategy and Δn).
    pub(crate) fn same_point(&self, detail: &ReprojDetail) -> bool {
        self.pick.name() == detail.node
            && self.pick.strategy_name() == detail.strategy
            && self.delta_n == detail.delta_n
    }

    /// The point `(pick, Δn, predicted error, predicted ms)` of `profile`'s models.
    fn at((pick, delta_n, predicted_error, predicted_ms): Point<'p>, profile: &Profile) -> Self {
        Planned {
            pick,
            delta_n,
            predicted_error,
            predicted_speedup: profile.original.frame_ms / predicted_ms,
        }
    }
}

/// The planned point instanced as `emit` would write it, ready to render.
fn variant(
    loaded: &Loaded,
    profile: &Profile,
    profile_path: &Path,
    planned: &Planned<'_>,
) -> Result<VariantInput, CompareError> {
    let spec = VariantSpec::of(profile, profile_path, planned.pick, planned.delta_n)?;
    let variant = spec.instance(&loaded.shader, loaded, &InstanceOptions::default())?;
    Ok(VariantInput::new(
        variant.passes.iter().map(|p| p.wgsl.clone()).collect(),
        variant.manifest.clone(),
        planned.delta_n,
    ))
}

/// Instance and render the planned variant; `crop` is the frame kept for the crops, `tries` what
/// [`steer`] raced on the way to it.
pub(crate) fn reproj(
    ctx: &Ctx,
    loaded: &Loaded,
    (profile, profile_path): (&Profile, &Path),
    planned: &Planned<'_>,
    tries: Vec<ReprojTry>,
    crop: u32,
) -> Result<ReprojRun, CompareError> {
    let shader = &loaded.shader;
    let pick = planned.pick;
    let node_name = pick.name();
    let input = variant(loaded, profile, profile_path, planned)?;
    let tmp = tempfile::tempdir().map_err(|e| CompareError::Internal {
        what: "cannot make a temporary directory".into(),
        message: e.to_string(),
    })?;
    let render = RenderOptions {
        png_dir: Some(tmp.path().to_owned()),
        raw_frames: true,
        // Scored below with the other methods' scorer (ꟻLIP on the GPU), once.
        perceptual_stride: None,
        ..ctx.render_opts.clone()
    };
    let r = ctx
        .renderer
        .render_variant(shader, ctx.session, &input, ctx.reference, &render)?;
    ctx.progress.step("reproj");
    // Every frame came back raw: the crop, ꟻLIP, and the figures the GPU reduction does not
    // make (the still/moving split, the supersampled reference).
    let read_raw = |f: usize| -> Result<Vec<f32>, CompareError> {
        let raw = tmp.path().join(format!("frame_{f:03}.f32"));
        let bytes = std::fs::read(&raw).map_err(|e| CompareError::Internal {
            what: format!("cannot read {}", raw.display()),
            message: e.to_string(),
        })?;
        Ok(bytes
            .chunks_exact(4)
            .map(|b| f32::from_le_bytes([b[0], b[1], b[2], b[3]]))
            .collect())
    };
    let frames = (0..r.frames.len())
        .map(read_raw)
        .collect::<Result<Vec<_>, _>>()?;
    let crop_frame = frames[(crop as usize).min(frames.len() - 1)].clone();
    let scored = ctx.score(&frames, true)?;
    drop(frames);
    // Its speed comes from the comparison's final interleaved run (`time_methods`): none here.
    Ok(ReprojRun {
        input,
        detail: ReprojDetail {
            profile: profile_path.display().to_string(),
            node: node_name.clone(),
            text: pick.text(),
            strategy: pick.strategy_name().to_owned(),
            delta_n: planned.delta_n,
            predicted_error: planned.predicted_error,
            predicted_speedup: planned.predicted_speedup,
            tries,
            rematch: None,
        },
        result: MethodResult {
            speedup_ci95: None,
            method: "reproj".into(),
            frame_ms: 0.0,
            speedup: 0.0,
            reached_target: false,
            scores: Scores {
                error: r.error,
                psnr: if r.psnr.is_finite() {
                    r.psnr
                } else {
                    reproj_metrics::PSNR_CAP
                },
                flip: scored.flip,
                split: scored.split,
                supersampled: scored.supersampled,
            },
            setting: format!(
                "{} {node_name} cached at Δn = {} ({}, k = {})",
                if matches!(pick, Profiled::Set(_)) {
                    "nodes"
                } else {
                    "node"
                },
                planned.delta_n,
                pick.strategy_name(),
                pick.block(profile)
            ),
        },
        crop_frame,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn reported(node: &str, strategy: &str) -> ReprojDetail {
        ReprojDetail {
            profile: "marble_small.profile.json".into(),
            node: node.into(),
            text: String::new(),
            strategy: strategy.into(),
            delta_n: 4,
            predicted_error: 0.0,
            predicted_speedup: 0.0,
            tries: Vec::new(),
            rematch: None,
        }
    }

    /// `along` stays on the reported node's curve: the least period whose predicted speedup
    /// reaches the speed asked (a faster ask never a shorter period), the fastest period where
    /// none does, and nothing for a node or strategy the profile does not hold.
    #[test]
    fn along_takes_the_least_period_of_the_reported_node_that_reaches_the_speed() {
        let profile: Profile = serde_json::from_str(include_str!(
            "../../../reproj-report/tests/data/marble_small.profile.json"
        ))
        .unwrap();
        let node = reported("697", "2pass");
        let at = |target: f64| along(&profile, &node, target, 50).unwrap();
        let slowest = at(0.0);
        let fastest = at(1e9);
        assert!(
            slowest.delta_n < fastest.delta_n,
            "{} {}",
            slowest.delta_n,
            fastest.delta_n
        );
        let mut last = slowest.delta_n;
        for i in 0..=20 {
            let target = slowest.predicted_speedup
                + (fastest.predicted_speedup - slowest.predicted_speedup) * f64::from(i) / 20.0;
            let p = at(target);
            assert_eq!(
                (p.pick.name(), p.pick.strategy_name()),
                ("697".into(), "2pass")
            );
            assert!(
                p.predicted_speedup >= target - 1e-12,
                "Δn {}: {} for {target}",
                p.delta_n,
                p.predicted_speedup
            );
            assert!(p.delta_n >= last, "Δn {} after {last}", p.delta_n);
            // The least such period: asking for its own speed gives it back.
            assert_eq!(at(p.predicted_speedup).delta_n, p.delta_n);
            last = p.delta_n;
        }
        assert!(along(&profile, &reported("697", "fused"), 2.0, 50).is_none());
        assert!(along(&profile, &reported("1", "2pass"), 2.0, 50).is_none());
    }
}
