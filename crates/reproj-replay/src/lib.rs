//! reproj session replay: render a WGSL fragment shader, and cached variants of it, headlessly
//! with wgpu over a recorded *session*, and measure what the optimizer needs: per-frame error
//! against the original, hit rate, frame time.
//!
//! # Pieces
//!
//! - [`Session`] (`session/`, schema in `SESSION.md`): resolution, frames, geometry, camera and
//!   light paths, uniform values, textures, samplers, and which vertex attribute feeds each
//!   fragment `@location`.
//! - [`reflect`]: the fragment entry point's interface from the naga module: inputs, uniform structs
//!   with their layouts, textures, samplers, by group and binding. Uniform fields are filled by name:
//!   `camera_pos`, `light_pos`, `time` (seconds), `frame` and `resolution` automatically unless the
//!   session's `uniforms` gives them; every other field from `uniforms`. A field, texture or vertex
//!   input the session does not provide is an error naming each one ([`ReplayError::MissingResources`]).
//! - [`scene`]: the CPU-side data of a frame a host writes to the shader's own uniform buffers
//!   (GPU-free; the renderer uses it, and so can a host that renders a session itself, like
//!   `examples/host`).
//! - [`vertex`]: the generated vertex stage (invariant clip position, one output per fragment input,
//!   optionally the previous frame's clip position), with its transform uniforms in its own bind
//!   group: the lowest group index the fragment modules do not use.
//! - [`Renderer`]: wgpu device (Vulkan: the backends built in are [`compiled_backends`]);
//!   [`Renderer::render_original`] renders the reference frames, [`Renderer::render_variant`] runs a
//!   cached variant of any strategy (`docs/PASSES.md`) and compares it with the reference.
//! - [`RenderReport`]: per-frame and mean error, PSNR, hit rate, frame time, adapter, timing method;
//!   for variants ꟻLIP and SSIM ([`perceptual`]) with their worst frames.
//! - [`output`]: PNG frames, hit maps and error maps.
//!
//! # Example
//!
//! ```no_run
//! use reproj_replay::{Renderer, RendererOptions, RenderOptions, Session, VariantInput};
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

// The GPU half (feature `gpu`, on by default): the renderer, the GPU error reduction, the
// perceptual metrics (nv-flip) and image output. The rest is GPU-free.
#[cfg(feature = "gpu")]
mod assets;
#[cfg(feature = "gpu")]
pub mod backend;
mod gltf;
pub mod mesh;
pub mod metrics;
#[cfg(feature = "gpu")]
pub mod output;
#[cfg(feature = "gpu")]
pub mod perceptual;
#[cfg(feature = "gpu")]
mod reduce;
pub mod reflect;
#[cfg(feature = "gpu")]
mod render;
pub mod scene;
pub mod session;
pub mod textures;
pub mod vertex;

#[cfg(feature = "gpu")]
pub use backend::{compiled_backends, parse_backends};
pub use metrics::{
    AdapterReport, FrameError, FrameRecord, RENDER_REPORT_SCHEMA, RENDER_REPORT_VERSION,
    RenderReport, TimingMethod,
};
#[cfg(feature = "gpu")]
pub use render::{
    FrameProgress, Reference, RenderOptions, Renderer, RendererOptions, VariantInput,
};
pub use session::{Session, SessionError};

use std::path::PathBuf;

/// Everything that can go wrong replaying a session. Each variant renders as one clear message.
#[derive(Debug, thiserror::Error)]
pub enum ReplayError {
    #[error(
        "no GPU adapter found for backends {backends} (on a machine without a GPU driver install Mesa's software Vulkan driver: apt-get install mesa-vulkan-drivers)"
    )]
    NoAdapter { backends: String },
    /// A backend name that is not a wgpu backend, or one this build does not have.
    #[error(
        "{origin}: backend `{name}` {reason} (this reproj has: {compiled}; accepted names: {accepted})"
    )]
    Backend {
        /// Where the list came from: `--backend` or `WGPU_BACKEND`.
        origin: String,
        name: String,
        reason: String,
        compiled: String,
        accepted: String,
    },
    #[error("cannot open the GPU device on {adapter}: {message}")]
    Device { adapter: String, message: String },
    #[error(transparent)]
    Session(#[from] SessionError),
    /// The shader declares resources the session does not provide.
    #[error("the session provides no {what}: {}", names.join(", "))]
    MissingResources { what: String, names: Vec<String> },
    #[error("unsupported: {what}")]
    Unsupported { what: String },
    /// A texture or mesh of the session could not be built (file missing, bad image...).
    #[error("{message}")]
    Asset { message: String },
    /// wgpu rejected a shader module or pipeline.
    #[error("{what}: {message}")]
    Gpu { what: String, message: String },
    #[error(
        "the reference has {reference} (frames, width, height) but the session needs {session}"
    )]
    ReferenceMismatch { reference: String, session: String },
    #[error("variant: {message}")]
    Variant { message: String },
    #[error(transparent)]
    Write(#[from] reproj_io::WriteError),
    #[error(transparent)]
    Read(#[from] reproj_io::ReadError),
    #[error("cannot encode {path}: {message}")]
    Image { path: PathBuf, message: String },
    /// The object covers no pixel in any frame: every error would read 0 (PSNR 100) and mean
    /// nothing.
    #[error(
        "{session}: the object covers no pixel in any of its {frames} frames (a camera looking away or whose `up` is parallel to its view, a zero scale, or the object behind the far plane); there is nothing to measure"
    )]
    NothingCovered { session: String, frames: u32 },
    /// The render would not fit the adapter or the machine's memory: refused before allocating.
    #[error("{session}: too large to render: {what}")]
    TooLarge { session: String, what: String },
}

impl ReplayError {
    /// True when the error comes from the user's input (exit code 2); false for a missing driver
    /// or a GPU failure, which are not.
    pub fn is_user_error(&self) -> bool {
        !matches!(self, ReplayError::Gpu { .. } | ReplayError::Device { .. })
    }
}
