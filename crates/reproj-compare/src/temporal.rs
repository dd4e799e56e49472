//! Temporal upsampling, what engines ship (FSR 2, TSR, Bevy's TAA): the original rendered at a
//! reduced resolution with a sub-pixel jitter, and one resolve pass at full resolution that
//! reprojects the history with the session's motion and accumulates the jittered samples into it
//! (`Renderer::render_upsampled`, docs/UPSAMPLING.md). Both passes are timed, against the original,
//! interleaved; the scale is searched by measurement as resize's is
//! ([`crate::resize::search_scale`]). [`composed`] draws reproj's chosen variant inside it (its
//! cache at the render resolution): the two speedups multiply where both hold.

use reproj_front::Shader;
use reproj_replay::{UpsampleSpec, VariantInput};

use crate::resize::{ResizeDetail, ResizeOptions, search_scale};
use crate::{CompareError, Ctx, MethodResult};

/// Search the scale, render and score: the detail, the chosen try's frames and its result.
pub(crate) fn temporal(
    ctx: &Ctx,
    shader: &Shader,
    entry: usize,
    opts: &ResizeOptions,
) -> Result<(ResizeDetail, Vec<Vec<f32>>, MethodResult), CompareError> {
    search_scale(
        ctx,
        opts,
        "temporal",
        (1.0 / ctx.target).sqrt(),
        |size| {
            let spec = UpsampleSpec::at(size);
            let up = ctx.renderer.render_upsampled(
                shader,
                entry,
                ctx.session,
                &spec,
                ctx.render_opts,
            )?;
            let candidate = reproj_bench::Candidate {
                name: "temporal".into(),
                subject: reproj_bench::Subject::Upsampled(spec),
            };
            Ok((up.frames, candidate))
        },
        "temporal upsampling (Halton jitter, reprojected and clipped history)",
    )
}

/// reproj composed with temporal upsampling: `variant` (reproj's choice, `speedup` alone) drawn
/// inside the upsampler, its scale searched from where the variant's own speedup leaves the
/// target (`√(speedup / target)`, at most 1) as resize's is.
pub(crate) fn composed(
    ctx: &Ctx,
    shader: &Shader,
    variant: &VariantInput,
    speedup: f64,
    opts: &ResizeOptions,
) -> Result<(ResizeDetail, Vec<Vec<f32>>, MethodResult), CompareError> {
    search_scale(
        ctx,
        opts,
        COMPOSED,
        (speedup.max(1e-3) / ctx.target).sqrt(),
        |size| {
            let spec = UpsampleSpec::at(size);
            let up = ctx.renderer.render_upsampled_variant(
                shader,
                ctx.session,
                variant,
                &spec,
                ctx.render_opts,
            )?;
            let candidate = reproj_bench::Candidate {
                name: COMPOSED.into(),
                subject: reproj_bench::Subject::UpsampledVariant(variant.clone(), spec),
            };
            Ok((up.frames, candidate))
        },
        "reproj's variant inside the temporal upsampler (its cache at the render resolution)",
    )
}

/// The composed method's name in the table.
pub const COMPOSED: &str = "reproj+temporal";
