//! reproj session replay: render a WGSL fragment shader, and cached variants of it, headlessly
//! with wgpu over a recorded *session*, and measure what the optimizer needs: per-frame error
//! against the original, hit rate, frame time.
//!
//! The scene it draws is `reproj-scene`'s (the session, meshes, textures, the shader's reflected
//! interface and its uniforms' bytes); the metrics and images it reports are `reproj-metrics`'s.
//! This crate is the GPU half: the only analysis crate that depends on wgpu.
//!
//! # Pieces
//!
//! Layered bottom-up, each module importing only from those above it in this list (and the
//! renderer's own submodules from their parent):
//!
//! - [`backend`]: the wgpu backends this build has ([`compiled_backends`]) and `--backend` names.
//! - [`jitter`]: sub-pixel offsets of the projection (Halton, fixed) for temporal upsampling and
//!   supersampled references.
//! - [`vertex`]: the generated vertex stage (invariant clip position, one output per fragment input,
//!   optionally the previous frame's clip position), with its transform uniforms in its own bind
//!   group: the lowest group index the fragment modules do not use.
//! - `error`: [`ReplayError`] (below everything).
//! - `gpu`: the adapter, device and queue every GPU module works on (`Gpu`: error scopes, host
//!   waits), which the [`Renderer`] derefs to.
//! - `readback`: the batched readback (`Staging`, `QueryKit`, `FrameBatch`).
//! - `assets`: the session's meshes and textures on the GPU, kept across replays.
//! - `reduce`: the [`Reference`] frames (kept on the GPU too) and the per-frame error reduction
//!   compute pass against them (one record per 8×8 block comes back).
//! - [`Renderer`] (`render/`): [`Renderer::render_original`] renders the reference frames,
//!   [`Renderer::render_variant`] runs a cached variant of any strategy (`docs/PASSES.md`) and
//!   compares it with the reference. Uniform fields are filled by name (`reproj_scene::uniforms`);
//!   a field, texture or vertex input the session does not provide is an error naming each one
//!   ([`ReplayError::MissingResources`]).
//! - The report ([`reproj_metrics::RenderReport`]): per-frame and mean error, PSNR, hit rate,
//!   frame time, adapter, timing method; for variants ꟻLIP and SSIM with their worst frames.
//!
//! # Example
//!
//! ```no_run
//! use reproj_replay::{Renderer, RendererOptions, RenderOptions, VariantInput};
//! use reproj_scene::Session;
//! let shader = reproj_front::load_file("shaders/marble.wgsl".as_ref()).unwrap();
//! let entry = shader.fragment_entry(None).unwrap();
//! let session = Session::load("sessions/marble.json").unwrap();
//! let renderer = Renderer::new(&RendererOptions::default()).unwrap();
//! let reference = renderer.render_original(&shader, entry, &session, &RenderOptions::default()).unwrap();
//! println!("{} ms/frame on {}", reference.report.frame_ms, reference.report.adapter.name);
//! let variant = VariantInput::from_dir("out/variant".as_ref(), 8).unwrap();
//! let report = renderer.render_variant(&shader, &session, &variant, &reference, &RenderOptions::default()).unwrap();
//! println!("error {} psnr {} hit rate {}", report.error, report.psnr, report.hit_rate);
//! ```
//!
//! # Metrics
//!
//! Error is the mean over **all** pixels of the frame (background included, where it is 0) of the
//! L2 distance between variant and reference RGB, both clamped to [0, 1] (linear RGB). PSNR is
//! `10 log10(1 / MSE)` with MSE over all pixels and the three channels, capped at 100 dB for
//! identical frames. Hit rate is hits / shaded pixels. Session summaries are means over frames:
//! error and PSNR over every frame, hit rate and frame time over frames 1.. (frame 0 has no cache
//! and pays shader compilation). ꟻLIP and SSIM compare the sRGB 8-bit frames over the covered
//! pixels, on the frames [`RenderOptions::perceptual_stride`] picks; a summary keeps the mean and
//! the worst frame.

mod error;

pub mod backend;
pub mod jitter;
pub mod vertex;

mod assets;
mod gpu;
mod readback;
mod reduce;
mod render;

pub use backend::{compiled_backends, parse_backends};
pub use jitter::Jitter;
pub use reduce::Reference;
pub use render::{
    FrameProgress, PerceptualOn, RenderOptions, Renderer, RendererOptions, UpsampleSpec, Upsampled,
    VariantInput, available_memory,
};

pub use error::ReplayError;
