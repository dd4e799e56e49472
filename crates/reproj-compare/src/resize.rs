//! Reduced-resolution rendering (dynamic resizing, Montrym et al. 1997): the original rendered at
//! `scale` × the session's resolution and upsampled bilinearly to full size. The scale is searched
//! by measurement: each try is timed against the original, interleaved (`reproj-bench`; raced
//! twice, pooled, where one race cannot place it against the target); frame
//! time is taken to follow the pixel count, so each try moves the scale by the square root of the
//! missed speedup ratio; the try closest to the target (in log ratio) is kept. The upsampling runs on the CPU and is not in the measured time (on a GPU it is one
//! full-screen bilinear pass).

use reproj_front::Shader;
use serde::{Deserialize, Serialize};

use crate::{CompareError, Ctx, MethodResult};

/// Options of the resize search.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ResizeOptions {
    /// Most scales to render.
    pub tries: usize,
    /// Stop when the measured speedup is within this fraction of the target.
    pub tolerance: f64,
    /// Smallest side of the reduced frame, pixels.
    pub min_side: u32,
}

impl Default for ResizeOptions {
    fn default() -> Self {
        ResizeOptions {
            tries: 4,
            tolerance: 0.05,
            min_side: 8,
        }
    }
}

/// One rendered scale.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ResizeTry {
    /// Linear scale of the resolution.
    pub scale: f64,
    pub resolution: [u32; 2],
    /// Median block time of the try in its interleaved run, ms per frame.
    pub frame_ms: f64,
    /// Its speedup over the original in that run, and the 95 % interval.
    pub speedup: f64,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub speedup_ci95: Option<[f64; 2]>,
    /// How many races the figures pool: 1, or 2 when the first could not place the try against
    /// the target ([`crate::ctx::in_doubt`]; absent before: 1).
    #[serde(default = "crate::ctx::one_race")]
    pub races: u32,
    /// Mean per-pixel L2 error of the upsampled frames.
    pub error: f64,
}

/// The resize search.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ResizeDetail {
    /// Every try, in order.
    pub tries: Vec<ResizeTry>,
    /// Index of the reported try.
    pub chosen: usize,
}

/// Search the scale, render, upsample and score: the detail, the chosen try's upsampled frames
/// and its result.
pub(crate) fn resize(
    ctx: &Ctx,
    shader: &Shader,
    entry: usize,
    opts: &ResizeOptions,
) -> Result<(ResizeDetail, Vec<Vec<f32>>, MethodResult), CompareError> {
    let [w, h] = ctx.session.resolution;
    search_scale(
        ctx,
        opts,
        "resize",
        (1.0 / ctx.target).sqrt(),
        |size| {
            let mut session = ctx.session.clone();
            session.resolution = size;
            let frames = ctx.render_shader(shader, entry, &session)?;
            let up = frames
                .iter()
                .map(|f| upsample_bilinear(f, size, [w, h]))
                .collect();
            let candidate = Ctx::shader_candidate("resize", shader.clone(), entry, Some(session));
            Ok((up, candidate))
        },
        "bilinear upsampling",
    )
}

/// The same speed as `resize`'s chosen try (the same low-resolution frames, rendered again), its
/// frames upsampled edge-adaptively ([`crate::easu`]) instead of bilinearly: the frames and the
/// result, whose speed the final timing copies from resize's.
pub(crate) fn edge_adaptive(
    ctx: &Ctx,
    shader: &Shader,
    entry: usize,
    detail: &ResizeDetail,
    resize: &MethodResult,
) -> Result<(Vec<Vec<f32>>, MethodResult), CompareError> {
    let t = &detail.tries[detail.chosen];
    let mut session = ctx.session.clone();
    session.resolution = t.resolution;
    let up: Vec<Vec<f32>> = ctx
        .render_shader(shader, entry, &session)?
        .iter()
        .map(|f| crate::easu::upsample_edge_adaptive(f, t.resolution, ctx.session.resolution))
        .collect();
    ctx.progress.step("edge-adaptive upsampling");
    let result = MethodResult {
        method: "easu".into(),
        scores: ctx.score(&up, true)?,
        setting: resize.setting.replace(
            "bilinear upsampling",
            "edge-adaptive upsampling (EASU-like)",
        ),
        ..resize.clone()
    };
    Ok((up, result))
}

/// The scale search every reduced-resolution method shares: from the scale the pixel count
/// predicts, each try rendered by `render` (its frames at full resolution and the candidate that
/// times it) and raced against the original, the next scale moved by √(measured / target), until a
/// try lands within the tolerance. The try closest to the target (in log ratio) is reported as
/// method `name`, its setting ending in `upsampling`'s words.
pub(crate) fn search_scale(
    ctx: &Ctx,
    opts: &ResizeOptions,
    name: &str,
    start: f64,
    mut render: impl FnMut([u32; 2]) -> Result<(Vec<Vec<f32>>, reproj_bench::Candidate), CompareError>,
    upsampling: &str,
) -> Result<(ResizeDetail, Vec<Vec<f32>>, MethodResult), CompareError> {
    let [w, h] = ctx.session.resolution;
    let mut scale = start.clamp(0.01, 1.0);
    let mut tries: Vec<ResizeTry> = Vec::new();
    let mut best: Option<(usize, Vec<Vec<f32>>)> = None;
    let miss = |s: f64| (s.max(1e-9) / ctx.target).ln().abs();
    for _ in 0..opts.tries.max(1) {
        let size = [
            scaled(w, scale, opts.min_side),
            scaled(h, scale, opts.min_side),
        ];
        if tries.iter().any(|t| t.resolution == size) {
            break;
        }
        let (up, candidate) = render(size)?;
        let (timed, races) = ctx.race_try(candidate, opts.tolerance)?;
        let speedup = timed.map_or(0.0, |e| e.speedup);
        let error = ctx.score(&up, false)?.error;
        ctx.progress
            .step(&format!("{name} {}×{}: {speedup:.2}×", size[0], size[1]));
        tries.push(ResizeTry {
            scale,
            resolution: size,
            frame_ms: timed.map_or(0.0, |e| e.candidate_ms),
            speedup,
            speedup_ci95: timed.map(|e| e.ci95),
            races,
            error,
        });
        let i = tries.len() - 1;
        if best
            .as_ref()
            .is_none_or(|(b, _)| miss(speedup) < miss(tries[*b].speedup))
        {
            best = Some((i, up));
        }
        if miss(speedup) <= (1.0 + opts.tolerance).ln() {
            break;
        }
        // Frame time ~ pixels ~ scale²: move the scale by √(measured / target).
        let next = (scale * (speedup.max(1e-3) / ctx.target).sqrt()).clamp(0.01, 1.0);
        if (next - scale).abs() < 1e-6 {
            break;
        }
        scale = next;
    }
    let (chosen, frames) = best.expect("at least one try");
    let t = &tries[chosen];
    let scores = ctx.score(&frames, true)?;
    let result = MethodResult {
        speedup_ci95: t.speedup_ci95,
        method: name.into(),
        frame_ms: t.frame_ms,
        speedup: t.speedup,
        reached_target: t.speedup >= ctx.target,
        scores,
        setting: format!(
            "{}×{} ({:.0} % of each side), {upsampling}",
            t.resolution[0],
            t.resolution[1],
            t.scale * 100.0
        ),
    };
    Ok((ResizeDetail { tries, chosen }, frames, result))
}

fn scaled(side: u32, scale: f64, min: u32) -> u32 {
    ((f64::from(side) * scale).round() as u32).clamp(min.min(side), side)
}

/// Bilinear upsampling of an RGBA f32 frame (`from` = `[width, height]`, row-major, top row
/// first) to `to`, with pixel centers aligned (`x_src = (x + ½)·w_src/w − ½`) and edges clamped.
pub fn upsample_bilinear(src: &[f32], from: [u32; 2], to: [u32; 2]) -> Vec<f32> {
    let [sw, sh] = from.map(|v| v as usize);
    let [dw, dh] = to.map(|v| v as usize);
    let mut out = vec![0.0f32; dw * dh * 4];
    let axis = |d: usize, dn: usize, sn: usize| {
        let x = ((d as f64 + 0.5) * sn as f64 / dn as f64 - 0.5).clamp(0.0, (sn - 1) as f64);
        let i = (x.floor() as usize).min(sn - 1);
        let j = (i + 1).min(sn - 1);
        (i, j, (x - i as f64) as f32)
    };
    for y in 0..dh {
        let (y0, y1, fy) = axis(y, dh, sh);
        for x in 0..dw {
            let (x0, x1, fx) = axis(x, dw, sw);
            let px = |xx: usize, yy: usize, c: usize| src[(yy * sw + xx) * 4 + c];
            for c in 0..4 {
                let top = px(x0, y0, c) * (1.0 - fx) + px(x1, y0, c) * fx;
                let bottom = px(x0, y1, c) * (1.0 - fx) + px(x1, y1, c) * fx;
                out[(y * dw + x) * 4 + c] = top * (1.0 - fy) + bottom * fy;
            }
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn upsampling_keeps_constants_and_interpolates_between_centers() {
        let c = upsample_bilinear(&[0.25, 0.5, 0.75, 1.0].repeat(4), [2, 2], [5, 3]);
        let want = [0.25, 0.5, 0.75, 1.0];
        assert!(
            c.chunks(4)
                .all(|p| p.iter().zip(want).all(|(a, b)| (a - b).abs() < 1e-6))
        );
        // A 2×1 ramp 0 → 1 upsampled to 4×1: centers at −0.25, 0.25, 0.75, 1.25 source pixels.
        let ramp = [0.0, 0.0, 0.0, 1.0, 1.0, 1.0, 1.0, 1.0];
        let r = upsample_bilinear(&ramp, [2, 1], [4, 1]);
        let red: Vec<f32> = r.chunks(4).map(|p| p[0]).collect();
        for (r, w) in red.iter().zip([0.0, 0.25, 0.75, 1.0]) {
            assert!((r - w).abs() < 1e-6, "{red:?}");
        }
    }

    #[test]
    fn scaled_sides_stay_in_range() {
        assert_eq!(scaled(256, 0.5, 8), 128);
        assert_eq!(scaled(256, 0.001, 8), 8);
        assert_eq!(scaled(4, 0.5, 8), 4);
        assert_eq!(scaled(256, 1.0, 8), 256);
    }
}
