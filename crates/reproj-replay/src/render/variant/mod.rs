//! The variant loop: render a cached variant of any strategy and compare it with the reference.
//!
//! In phases, a file each: `plan.rs` (checks and the passes' stages, before any GPU object),
//! `gpu.rs` (targets, bindings, pipelines, the empty cache), `frames.rs` (the frame loop; the
//! sampled frames' ꟻLIP and SSIM scored beside it, `../score.rs`).

use std::collections::BTreeSet;
use std::path::Path;

use reproj_front::Shader;
use reproj_instance::Reprojection;

use crate::error::ReplayError;
use crate::reduce::FrameErrors;
use crate::vertex;
use reproj_metrics::l2;
use reproj_metrics::output;
use reproj_metrics::{FrameRecord, RenderReport};
use reproj_scene::reflect::{self, Interface};
use reproj_scene::session::Session;

use super::*;

mod frames;
mod gpu;
pub(super) mod motion;
mod plan;

use frames::FrameLoop;
pub(in crate::render) use gpu::{BuiltVariant, VariantGpu};
pub(in crate::render) use plan::VariantPlan;

/// Hits, misses (recomputes, refreshes included) and shaded pixels of one frame.
pub(super) struct Counts {
    pub(super) hits: u64,
    pub(super) misses: u64,
    pub(super) shaded: u64,
}

/// The frame's counts from its occlusion queries (one per pass, in pass order) and, for the
/// fused strategy whose one pass cannot count hits apart, the classification map.
pub(super) fn counts_of(
    strategy: reproj_instance::Strategy,
    occ: &[u64],
    hit_px: Option<u64>,
) -> Counts {
    use reproj_instance::Strategy;
    let at = |i: usize| occ.get(i).copied().unwrap_or(0);
    match strategy {
        Strategy::ThreePass => Counts {
            hits: at(0),
            misses: at(1),
            shaded: at(2),
        },
        Strategy::TwoPass => Counts {
            hits: at(0),
            misses: at(1),
            shaded: at(0) + at(1),
        },
        Strategy::Fused => {
            let hits = hit_px.unwrap_or(0).min(at(0));
            Counts {
                hits,
                misses: at(0) - hits,
                shaded: at(0),
            }
        }
    }
}

impl Renderer {
    /// Render a cached variant of any strategy over the session (see `docs/PASSES.md`) and compare
    /// each frame with `reference` (from [`Renderer::render_original`] on the same session).
    ///
    /// Per frame, the manifest's passes in order as `reproj-runtime` records them, each with its
    /// color targets (frame color, current payload, current depth copy: cleared or loaded as
    /// listed) and depth state; then the current payload and depth copy become the previous ones.
    /// Frame 0 runs with Δn = 1; `clock` is the frame index.
    pub fn render_variant(
        &self,
        shader: &Shader,
        session: &Session,
        variant: &VariantInput,
        reference: &Reference,
        opts: &RenderOptions,
    ) -> Result<RenderReport, ReplayError> {
        self.render_variant_with(shader, session, variant, reference, opts, &())
    }

    /// [`Renderer::render_variant`], telling `progress` as frames come back. In phases: the plan
    /// (checks, the passes' stages; nothing allocated), the GPU objects, the empty cache, the
    /// frame loop (the sampled frames' perceptual metrics scored beside it, `score.rs`).
    pub fn render_variant_with(
        &self,
        shader: &Shader,
        session: &Session,
        variant: &VariantInput,
        reference: &Reference,
        opts: &RenderOptions,
        progress: &dyn FrameProgress,
    ) -> Result<RenderReport, ReplayError> {
        let plan = self.plan_variant(shader, session, variant, Some(reference), opts)?;
        let gpu = self.variant_gpu(session, variant, &plan, false)?;
        let m = &variant.manifest;
        let mut report = self.new_report("variant", shader, &m.entry, session);
        report.node = Some(m.node.id.clone());
        report.delta_n = Some(variant.delta_n);
        report.block = Some(variant.block);
        report.depth_epsilon = Some(variant.depth_epsilon);
        let run = FrameLoop {
            session,
            variant,
            reference,
            opts,
            progress,
            plan: &plan,
            gpu: &gpu,
        };
        self.variant_frames(&run, &mut report)?;
        report.summarize();
        Ok(report)
    }
}

/// A runtime error of drawing the variant `label`, named.
pub(in crate::render) fn runtime_error(
    label: &str,
    e: reproj_runtime::RuntimeError,
) -> ReplayError {
    ReplayError::Variant {
        message: format!("{label}: {e}"),
    }
}
