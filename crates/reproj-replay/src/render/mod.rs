//! The headless wgpu renderer: the original shader (reference frames) and cached variants.
//!
//! # Batched readback
//!
//! Every frame must come back to the host (reference frames, error metrics, PNGs) together with its
//! occlusion and timestamp queries. Reading each frame back synchronously (map, wait, copy) costs
//! several host/device round trips per frame, which on a software device (Mesa lavapipe) took about
//! as much wall time as rendering itself. So the frame loops batch the readback: each frame's
//! submission copies its color image (and classification map) into its own slot of a `K`-slot
//! [`Staging`] buffer and resolves its queries into its own slot of the [`QueryKit`] buffers; the
//! host maps and waits once per `K` frames (`Gpu::batch_len`) and then computes the records
//! of those frames in order. Results are unchanged: frame times still come from each frame's own
//! GPU timestamps, and queue order keeps each frame's uniform writes, render and copies in sequence.
//! Only `cpu_ms` is amortized: the wall time of a batch's submit + wait divided by its frames.
//! Without timestamp queries (frame time = CPU submit + wait) nothing is batched: `K` = 1 and each
//! frame's render submission is waited for and timed alone, as before.

use std::collections::HashMap;
use std::path::{Path, PathBuf};
use std::sync::Mutex;
use std::sync::atomic::AtomicU64;

use reproj_instance::contract::AddedPlace;
use reproj_instance::{MANIFEST_KIND, Manifest};

use crate::assets::Assets;
use crate::error::ReplayError;
use crate::gpu::Gpu;
use crate::readback::*;
use crate::reduce::{KernelCache, PerceptualCache, Reference};

mod bind;
mod device;
mod original;
mod pipeline;
mod scene;
mod score;
mod upsample;
mod variant;

use bind::*;
use pipeline::*;
use reproj_scene_gpu::{DEPTH_FORMAT, SceneObject};
use scene::*;
use score::{Scorer, scoring_pool};

pub use original::available_memory;
pub use reproj_instance::contract::CLASSIFY_ENTRY;
pub use upsample::{UpsampleSpec, Upsampled};

const FRAME_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba32Float;
const CLASSIFY_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba8Unorm;

/// How to open the GPU.
#[derive(Debug, Clone, Default)]
pub struct RendererOptions {
    /// Backend list as for `WGPU_BACKEND` (`"vulkan"`, `"vk"`, ...), of backends this build has
    /// ([`crate::compiled_backends`]). None: the `WGPU_BACKEND` environment variable, else Vulkan.
    pub backend: Option<String>,
    /// Time with CPU submit + wait even if the adapter has timestamp queries.
    pub cpu_timing: bool,
    /// Where the sampled frames' ꟻLIP and SSIM are computed.
    pub perceptual_on: PerceptualOn,
}

/// Where a replay computes the perceptual metrics (ꟻLIP, SSIM) of its sampled frames.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub enum PerceptualOn {
    /// On the device, unless it is a CPU rasterizer: there the frames are in host memory already,
    /// and NVIDIA's code on the scoring threads (which take only the cycles the rasterizer leaves
    /// idle) costs a quarter of what the kernels cost run by the rasterizer (lavapipe, 256×256:
    /// about 40 against 160 ms a frame).
    #[default]
    Auto,
    /// On the device: a compute pass per frame, only numbers come back (`reduce/perceptual.rs`).
    Device,
    /// On the CPU: the frames come back and are scored by NVIDIA's code beside the frame loop.
    Cpu,
}

/// Told after each frame of a replay comes back (frames come back in batches, so the calls
/// arrive a batch at a time): `done` frames of `total`. `reproj render` draws its progress from
/// it; the other callers pass `&()`, which ignores it.
pub trait FrameProgress {
    fn frame(&self, done: u32, total: u32);
}

impl FrameProgress for () {
    fn frame(&self, _done: u32, _total: u32) {}
}

/// Per-render options.
#[derive(Debug, Clone)]
pub struct RenderOptions {
    /// Write PNGs here (frames; for variants also hit maps and error maps).
    pub png_dir: Option<PathBuf>,
    /// Render only N frames of the session (from `first_frame`).
    pub max_frames: Option<u32>,
    /// Start at this frame of the session (a window for interleaved timing, `reproj-bench`):
    /// frames `first_frame..first_frame + N` are rendered, a variant's cache starts empty there
    /// (that frame runs with Δn = 1) and its refresh clock is the session's frame index. Report
    /// records keep the session's frame numbers. A variant's reference must cover the window.
    pub first_frame: u32,
    /// Time only (the bench's blocks, `reproj-bench`): no frame, depth or error comes back — the
    /// original's [`Reference`] holds no frames and a variant's records no error — so a short
    /// block costs little besides its own frames. Timestamps and occlusion counts are unchanged.
    pub timing_only: bool,
    /// Variants: render the `reproj_classify` entry point each frame (hit map and exact
    /// hit / miss / refresh pixel counts). Ignored when the pass-1 module has no such entry point.
    pub classify: bool,
    /// With `png_dir`: also write each frame's exact RGBA f32 values as `frame_NNN.f32`
    /// ([`reproj_metrics::output::write_frame_raw`]).
    pub raw_frames: bool,
    /// Variants: compute the perceptual metrics ([`reproj_metrics::perceptual`]: ꟻLIP and SSIM over the
    /// covered pixels) on frames `f` with `f % k == 0`, reading those frames back (with
    /// `png_dir`, also their ꟻLIP maps). `None`: not computed.
    pub perceptual_stride: Option<u32>,
}

impl Default for RenderOptions {
    fn default() -> Self {
        RenderOptions {
            png_dir: None,
            max_frames: None,
            first_frame: 0,
            timing_only: false,
            classify: true,
            raw_frames: false,
            perceptual_stride: None,
        }
    }
}

/// A cached variant to render: the three pass modules in `manifest.passes` order, the manifest,
/// and the runtime parameters.
#[derive(Debug, Clone)]
pub struct VariantInput {
    /// WGSL text of each pass, in `manifest.passes` order.
    pub sources: Vec<String>,
    pub manifest: Manifest,
    /// Refresh period Δn (≥ 1).
    pub delta_n: u32,
    /// Run-time adaptation: Δn per frame of the session (index = frame), overriding `delta_n`
    /// where given (a frame past its end keeps `delta_n`). Built from the manifest's
    /// `params.schedule` and each frame's motion (`reproj render --adaptive`).
    pub delta_n_per_frame: Option<Vec<u32>>,
    /// Refresh block size k (≥ 1).
    pub block: u32,
    /// Depth tolerance ε.
    pub depth_epsilon: f32,
    /// Label used in messages (directory or node name).
    pub label: String,
    /// Draw every pass in its own render pass and time each (the records' `pass_ms`). By default
    /// (`false`) consecutive passes that write the same targets share one render pass, as a host
    /// draws them, and only the frame is timed (`pass_ms` empty where passes share one).
    pub pass_times: bool,
}

impl VariantInput {
    /// From WGSL texts and a manifest; k and ε from the manifest's defaults.
    pub fn new(sources: Vec<String>, manifest: Manifest, delta_n: u32) -> Self {
        let label = format!("{} node {}", manifest.shader, manifest.node.id);
        VariantInput {
            sources,
            block: manifest.params.block,
            depth_epsilon: manifest.params.depth_epsilon,
            manifest,
            delta_n,
            delta_n_per_frame: None,
            label,
            pass_times: false,
        }
    }

    /// Δn at frame `frame` ([`VariantInput::delta_n_per_frame`], else `delta_n`).
    pub fn delta_n_at(&self, frame: u32) -> u32 {
        self.delta_n_per_frame
            .as_ref()
            .and_then(|v| v.get(frame as usize).copied())
            .unwrap_or(self.delta_n)
    }

    /// From a directory holding `manifest.json` and the pass files it names: each pass inside the
    /// directory, a regular file within the shader size limit ([`reproj_io::read_input`]), valid
    /// WGSL, and within the GPU memory budget ([`reproj_front::memory`]).
    pub fn from_dir(dir: &Path, delta_n: u32) -> Result<Self, ReplayError> {
        let mpath = dir.join("manifest.json");
        let manifest: Manifest = reproj_io::read_json(&mpath, &MANIFEST_KIND)?;
        let mut sources = Vec::new();
        for (i, p) in manifest.passes.iter().enumerate() {
            // A manifest names its passes beside it: never another file of the machine, whose
            // text a parse error would then show.
            let f = reproj_scene::session::resolve_inside(dir, Path::new(&p.file), "manifest")
                .map_err(|why| ReplayError::Variant {
                    message: format!("{}: field `passes[{i}].file`: {why}", mpath.display()),
                })?;
            let source = reproj_io::read_input_string(&f, reproj_io::InputKind::Shader)
                .map_err(reproj_io::ReadError::from)?;
            // A pass is a shader read from a file: held to the same GPU memory budget as any
            // other before anything renders it.
            let shader = reproj_front::parse_shader(&f, source.clone()).map_err(|e| {
                ReplayError::Variant {
                    message: e.to_string(),
                }
            })?;
            reproj_front::memory::check_shader(&f, &shader)?;
            sources.push(source);
        }
        let mut v = Self::new(sources, manifest, delta_n);
        v.label = dir.display().to_string();
        Ok(v)
    }
}

/// The renderer: its [`Gpu`] (which it derefs to), and what is kept across replays: the session's
/// meshes and textures, the scoring pipelines (the error reduction, the perceptual metrics), the
/// render pipelines.
pub struct Renderer {
    gpu: Gpu,
    assets: Assets,
    reduce_kernel: KernelCache,
    perceptual_kernel: PerceptualCache,
    /// The sampled frames' perceptual metrics are computed on the device.
    perceptual_on_device: bool,
    /// Render pipelines kept across replays (see [`Renderer::pipeline`]).
    pipelines: Mutex<HashMap<String, Pipe>>,
    /// Variants kept built across replays, by key, the most recently used last
    /// (`variant/gpu.rs`).
    variants: Mutex<Vec<(String, variant::BuiltVariant)>>,
    pipeline_hits: AtomicU64,
}

impl std::fmt::Debug for Renderer {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Renderer")
            .field("adapter", &self.adapter_info)
            .field("timestamps", &self.timestamps)
            .finish()
    }
}

/// The session's background as a clear color.
pub(super) fn background_color(session: &reproj_scene::Session) -> wgpu::Color {
    let [r, g, b, a] = session.background.map(f64::from);
    wgpu::Color { r, g, b, a }
}
