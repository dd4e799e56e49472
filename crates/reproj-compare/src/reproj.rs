//! reproj's own choice at the target speedup: from the profile's error-vs-time Pareto frontier
//! (`reproj_select::pareto`, the models `emit` selects with, L2 error), the point with the least
//! predicted error whose predicted speedup reaches the target, or the fastest point when none
//! does. With an error budget instead, the choice is `emit`'s (`reproj_select::select`) and its
//! predicted speedup becomes every method's target. It is instanced like `emit` does and rendered with the replay, so its speedup and error
//! are measured in the same run as the other methods'.

use std::path::Path;

use reproj_analyze::emit::{ir_hash, resolve};
use reproj_front::Loaded;
use reproj_instance::{InstanceOptions, NodeSelector, Strategy, instance};
use reproj_models::content_hash;
use reproj_models::profile::{NodeProfile, NodeStatus};
use reproj_models::{Metric, Profile};
use reproj_replay::{RenderOptions, VariantInput};
use reproj_select::{DEFAULT_MIN_DELTA_N, NodeRecord, SelectOptions, Selection, pareto, select};
use serde::{Deserialize, Serialize};

use crate::{CompareError, Ctx, MethodResult, Scores, Target};

/// What reproj chose.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ReprojDetail {
    pub profile: String,
    /// Node id, or `"root"`.
    pub node: String,
    pub text: String,
    pub strategy: String,
    pub delta_n: u32,
    pub predicted_error: f64,
    /// Profile's original frame time / predicted frame time.
    pub predicted_speedup: f64,
}

pub(crate) struct ReprojRun {
    pub(crate) detail: ReprojDetail,
    pub(crate) result: MethodResult,
    pub(crate) crop_frame: Vec<f32>,
}

/// reproj's choice before rendering: the profiled node and where on its models.
pub(crate) struct Planned<'p> {
    node: &'p NodeProfile,
    delta_n: u32,
    predicted_error: f64,
    /// The profile's original frame time / `predicted_ms`.
    pub(crate) predicted_speedup: f64,
}

/// Choose reproj's (node, Δn) from the profile: for a target speedup, the frontier point with the
/// least predicted error that reaches it (the fastest when none does); for an error budget, what
/// `emit --max-error` selects.
pub(crate) fn plan<'p>(
    loaded: &Loaded,
    profile: &'p Profile,
    profile_path: &Path,
    target: Target,
    max_delta_n: u32,
) -> Result<Planned<'p>, CompareError> {
    let shader = &loaded.shader;
    let fresh = match &profile.shader.ir_hash {
        Some(h) => ir_hash(shader) == *h,
        None => content_hash(shader.source.as_bytes()) == profile.shader.hash,
    };
    if !fresh {
        return Err(reproj_analyze::AnalyzeError::Stale {
            path: resolve(&profile.shader.path, profile_path),
            what: "shader".into(),
        }
        .into());
    }
    let usable: Vec<_> = profile
        .nodes
        .iter()
        .filter(|n| n.status == NodeStatus::Ok)
        .collect();
    let records: Vec<NodeRecord> = usable
        .iter()
        .filter_map(|n| {
            Some(NodeRecord {
                id: n.id,
                text: n.text.clone(),
                strategy: n.strategy.clone(),
                error: n.fit(Metric::L2)?.clone(),
                timing: n.timing_fit.clone(),
                mean_pixels: profile.original.mean_pixels,
            })
        })
        .collect();
    let original_ms = profile.original.frame_ms;
    let speedup = |ms: f64| original_ms / ms;
    let (node_id, strategy, delta_n, predicted_error, predicted_ms) = match target {
        Target::Speedup(target) => {
            let front = pareto(
                &records,
                &profile.hit_rate,
                DEFAULT_MIN_DELTA_N,
                max_delta_n,
            );
            let choice = front
                .iter()
                .filter(|p| speedup(p.predicted_ms) >= target)
                .min_by(|a, b| a.predicted_error.total_cmp(&b.predicted_error))
                .or_else(|| {
                    front
                        .iter()
                        .max_by(|a, b| speedup(a.predicted_ms).total_cmp(&speedup(b.predicted_ms)))
                })
                .ok_or_else(|| CompareError::NoSelection {
                    path: profile_path.to_owned(),
                })?;
            (
                choice.node_id,
                choice.strategy.clone(),
                choice.delta_n,
                choice.predicted_error,
                choice.predicted_ms,
            )
        }
        Target::Budget(max_error) => {
            let opts = SelectOptions {
                max_error,
                min_delta_n: DEFAULT_MIN_DELTA_N,
                max_delta_n,
            };
            match select(&records, &profile.hit_rate, original_ms, &opts) {
                Selection::Node(c) => (
                    c.node_id,
                    c.strategy,
                    c.delta_n,
                    c.predicted_error,
                    c.predicted_ms,
                ),
                Selection::Original { reason } => {
                    return Err(CompareError::KeepsOriginal {
                        path: profile_path.to_owned(),
                        max_error,
                        reason: reason.to_string(),
                    });
                }
            }
        }
    };
    let node = usable
        .iter()
        .find(|n| n.id == node_id && n.strategy == strategy)
        .expect("the choice comes from the profile's nodes");
    Ok(Planned {
        node,
        delta_n,
        predicted_error,
        predicted_speedup: speedup(predicted_ms),
    })
}

/// Instance and render the planned variant; `crop` is the frame kept for the crops.
pub(crate) fn reproj(
    ctx: &Ctx,
    loaded: &Loaded,
    profile: &Profile,
    profile_path: &Path,
    planned: &Planned<'_>,
    crop: u32,
) -> Result<ReprojRun, CompareError> {
    let shader = &loaded.shader;
    let node = planned.node;
    let strategy: Strategy =
        node.strategy
            .parse()
            .map_err(|e: String| reproj_analyze::AnalyzeError::BadProfile {
                path: profile_path.to_owned(),
                message: format!("node {}: {e}", node.id),
            })?;
    let variant = instance(
        shader,
        &loaded.norm,
        &loaded.table,
        if node.root {
            NodeSelector::Root
        } else {
            NodeSelector::Id(node.id)
        },
        &InstanceOptions {
            strategy,
            delta_n: planned.delta_n,
            block: node.block.unwrap_or(profile.block),
            depth_epsilon: profile.depth_epsilon,
            ..Default::default()
        },
    )?;
    let input = VariantInput::new(
        variant.passes.iter().map(|p| p.wgsl.clone()).collect(),
        variant.manifest.clone(),
        planned.delta_n,
    );
    let tmp = tempfile::tempdir().map_err(|e| CompareError::Internal {
        what: "cannot make a temporary directory".into(),
        message: e.to_string(),
    })?;
    let render = RenderOptions {
        png_dir: Some(tmp.path().to_owned()),
        raw_frames: true,
        perceptual_stride: Some(ctx.stride),
        ..ctx.render_opts.clone()
    };
    let r = ctx
        .renderer
        .render_variant(shader, ctx.session, &input, ctx.reference, &render)?;
    ctx.progress.step("reproj");
    let raw = tmp.path().join(format!("frame_{crop:03}.f32"));
    let bytes = std::fs::read(&raw).map_err(|e| CompareError::Internal {
        what: format!("cannot read {}", raw.display()),
        message: e.to_string(),
    })?;
    let crop_frame: Vec<f32> = bytes
        .chunks_exact(4)
        .map(|b| f32::from_le_bytes([b[0], b[1], b[2], b[3]]))
        .collect();
    let measured = ctx.speedup(r.frame_ms);
    let node_name = if node.root {
        "root".to_string()
    } else {
        node.id.to_string()
    };
    Ok(ReprojRun {
        detail: ReprojDetail {
            profile: profile_path.display().to_string(),
            node: node_name.clone(),
            text: node.text.clone(),
            strategy: node.strategy.clone(),
            delta_n: planned.delta_n,
            predicted_error: planned.predicted_error,
            predicted_speedup: planned.predicted_speedup,
        },
        result: MethodResult {
            method: "reproj".into(),
            frame_ms: r.frame_ms,
            speedup: measured,
            reached_target: measured >= ctx.target,
            scores: Scores {
                error: r.error,
                psnr: if r.psnr.is_finite() {
                    r.psnr
                } else {
                    reproj_replay::metrics::PSNR_CAP
                },
                flip: r.flip.map(|f| f.mean),
            },
            setting: format!(
                "node {node_name} cached at Δn = {} ({})",
                planned.delta_n, node.strategy
            ),
        },
        crop_frame,
    })
}
