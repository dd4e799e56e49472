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
//! host maps and waits once per `K` frames ([`Renderer::batch_len`]) and then computes the records
//! of those frames in order. Results are unchanged: frame times still come from each frame's own
//! GPU timestamps, and queue order keeps each frame's uniform writes, render and copies in sequence.
//! Only `cpu_ms` is amortized: the wall time of a batch's submit + wait divided by its frames.
//! Without timestamp queries (frame time = CPU submit + wait) nothing is batched: `K` = 1 and each
//! frame's render submission is waited for and timed alone, as before.

use std::borrow::Cow;
use std::collections::{BTreeMap, BTreeSet, HashMap};
use std::num::NonZeroU64;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::{Arc, Mutex};
use std::time::Instant;

use reproj_front::Shader;
use reproj_instance::{CacheFormat, MANIFEST_KIND, Manifest, PassKind};

use crate::ReplayError;
use crate::assets::Assets;
use crate::mesh::Vertex;
use crate::metrics::{self, AdapterReport, FrameRecord, RenderReport, TimingMethod};
use crate::output;
use crate::perceptual;
use crate::reduce::{self, FrameErrors, GpuReference, Keeper, PixelsBack};
use crate::reflect::{self, Interface, ResourceKind, TexDim};
use crate::session::{Address, Cull, Filter, Session};
use crate::vertex::{self, TransformUniform, VERTEX_ENTRY};

/// Maximum bind groups the replay uses (WebGPU's default limit).
pub const MAX_BIND_GROUPS: u32 = 4;

const FRAME_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba32Float;
const DEPTH_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Depth32Float;
const CLASSIFY_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba8Unorm;
/// The depth copy a variant's color passes write and the next frame's lookup reads.
const DEPTH_COPY_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::R32Float;
/// The depth copy is cleared to the far plane, like a depth buffer.
const DEPTH_COPY_CLEAR: wgpu::Color = wgpu::Color {
    r: 1.0,
    g: 0.0,
    b: 0.0,
    a: 0.0,
};
/// Most frames whose readbacks share one host wait (see the module docs).
const MAX_BATCH: u32 = 16;
/// Host-visible staging memory one batch may use for frame images.
const BATCH_BYTES: u64 = 64 << 20;
/// Fragment entry point of the pass-1 module that writes the hit / miss / refresh map.
pub const CLASSIFY_ENTRY: &str = "reproj_classify";

/// How to open the GPU.
#[derive(Debug, Clone, Default)]
pub struct RendererOptions {
    /// Backend list as for `WGPU_BACKEND` (`"vulkan"`, `"vk"`, ...), of backends this build has
    /// ([`crate::compiled_backends`]). None: the `WGPU_BACKEND` environment variable, else Vulkan.
    pub backend: Option<String>,
    /// Time with CPU submit + wait even if the adapter has timestamp queries.
    pub cpu_timing: bool,
}

/// Per-render options.
#[derive(Debug, Clone)]
pub struct RenderOptions {
    /// Write PNGs here (frames; for variants also hit maps and error maps).
    pub png_dir: Option<PathBuf>,
    /// Render only the first N frames of the session.
    pub max_frames: Option<u32>,
    /// Variants: render the `reproj_classify` entry point each frame (hit map and exact
    /// hit / miss / refresh pixel counts). Ignored when the pass-1 module has no such entry point.
    pub classify: bool,
    /// With `png_dir`: also write each frame's exact RGBA f32 values as `frame_NNN.f32`
    /// ([`output::write_frame_raw`]).
    pub raw_frames: bool,
    /// Variants: compute the perceptual metrics ([`crate::perceptual`]: ꟻLIP and SSIM over the
    /// covered pixels) on frames `f` with `f % k == 0`, reading those frames back (with
    /// `png_dir`, also their ꟻLIP maps). `None`: not computed.
    pub perceptual_stride: Option<u32>,
}

impl Default for RenderOptions {
    fn default() -> Self {
        RenderOptions {
            png_dir: None,
            max_frames: None,
            classify: true,
            raw_frames: false,
            perceptual_stride: None,
        }
    }
}

/// Reference frames of the original shader: RGBA f32, row-major, top row first, one per frame,
/// with their depth; the same frames stay on the GPU for the error reduction of variants.
#[derive(Debug, Clone)]
pub struct Reference {
    pub width: u32,
    pub height: u32,
    pub frames: Vec<Vec<f32>>,
    /// Depth per pixel of each frame, row-major, top row first: 1 where nothing was drawn. The
    /// pixels with depth < 1 are the *covered* ones, over which the MSE and PSNR are taken.
    pub depth: Vec<Vec<f32>>,
    pub report: RenderReport,
    /// The frames and depths on the renderer's device.
    pub(crate) gpu: GpuReference,
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
    /// Refresh block size k (≥ 1).
    pub block: u32,
    /// Depth tolerance ε.
    pub depth_epsilon: f32,
    /// Label used in messages (directory or node name).
    pub label: String,
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
            label,
        }
    }

    /// From naga modules (written back to WGSL with naga's writer).
    pub fn from_modules(
        modules: &[naga::Module],
        manifest: Manifest,
        delta_n: u32,
    ) -> Result<Self, ReplayError> {
        let mut sources = Vec::new();
        for (i, m) in modules.iter().enumerate() {
            let info = reproj_front::validator()
                .validate(m)
                .map_err(|e| ReplayError::Variant {
                    message: format!("pass module {i} does not validate: {e}"),
                })?;
            let text =
                naga::back::wgsl::write_string(m, &info, naga::back::wgsl::WriterFlags::empty())
                    .map_err(|e| ReplayError::Variant {
                        message: format!("pass module {i}: cannot write WGSL: {e}"),
                    })?;
            sources.push(text);
        }
        Ok(Self::new(sources, manifest, delta_n))
    }

    /// From a directory holding `manifest.json` and the pass files it names.
    pub fn from_dir(dir: &Path, delta_n: u32) -> Result<Self, ReplayError> {
        let mpath = dir.join("manifest.json");
        let manifest: Manifest = reproj_io::read_json(&mpath, &MANIFEST_KIND)?;
        let mut sources = Vec::new();
        for p in &manifest.passes {
            let f = dir.join(&p.file);
            sources.push(
                std::fs::read_to_string(&f).map_err(|e| ReplayError::Variant {
                    message: format!("cannot read {}: {e}", f.display()),
                })?,
            );
        }
        let mut v = Self::new(sources, manifest, delta_n);
        v.label = dir.display().to_string();
        Ok(v)
    }
}

/// The GPU: instance, adapter, device and queue, plus what the adapter supports, and what is kept
/// across replays: the session's meshes and textures, the error reduction pipeline.
pub struct Renderer {
    _instance: wgpu::Instance,
    adapter_info: AdapterReport,
    pub(crate) device: wgpu::Device,
    pub(crate) queue: wgpu::Queue,
    timestamps: bool,
    timestamp_period: f32,
    errors: Arc<Mutex<Vec<String>>>,
    /// Unique per renderer in the process: tells whose device a [`Reference`]'s textures are on.
    pub(crate) id: u64,
    assets: Assets,
    reduce_kernel: Mutex<Option<reduce::Kernel>>,
    /// Render pipelines kept across replays (see [`Renderer::pipeline`]).
    pipelines: Mutex<HashMap<String, Pipe>>,
    pipeline_hits: AtomicU64,
}

/// Pipelines kept at most; the cache starts over beyond (an `analyze` keeps one node's few).
const PIPELINE_CACHE_LEN: usize = 64;

/// Source of [`Renderer::id`].
static NEXT_RENDERER_ID: AtomicU64 = AtomicU64::new(1);

impl std::fmt::Debug for Renderer {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Renderer")
            .field("adapter", &self.adapter_info)
            .field("timestamps", &self.timestamps)
            .finish()
    }
}

pub(crate) fn gpu_err(what: impl Into<String>, e: impl std::fmt::Display) -> ReplayError {
    ReplayError::Gpu {
        what: what.into(),
        message: e.to_string(),
    }
}

/// A shader module plus its reflected fragment interface.
struct Stage {
    shader: Shader,
    iface: Interface,
}

/// GPU resources of a session (shared by every pipeline of one render).
struct Scene {
    objects: Vec<ObjectGpu>,
    textures: HashMap<String, wgpu::TextureView>,
    samplers: HashMap<String, wgpu::Sampler>,
    /// Uniform buffers by variable name, with their reflected fields.
    uniforms: BTreeMap<String, (wgpu::Buffer, u32, Vec<reflect::UniformField>)>,
    vertex_bgl: wgpu::BindGroupLayout,
}

struct ObjectGpu {
    vbuf: wgpu::Buffer,
    ibuf: wgpu::Buffer,
    count: u32,
    cull: Cull,
    xf_buf: wgpu::Buffer,
    xf_bg: wgpu::BindGroup,
}

/// Host-owned resources of the variant's added bind group, by binding name.
struct AddedResources<'a> {
    params: &'a wgpu::Buffer,
    point_sampler: &'a wgpu::Sampler,
    linear_sampler: &'a wgpu::Sampler,
    /// The payload is rgba16float (always filterable).
    payload_half: bool,
    prev_payload: &'a wgpu::TextureView,
    /// The previous frame's depth copy (r32float), read as a float texture.
    prev_depth_copy: &'a wgpu::TextureView,
    /// The previous frame's depth buffer, for variants written before the depth copy, whose lookup
    /// declares `reproj_prev_depth` as a depth texture (they list no depth copy target).
    prev_depth_buffer: Option<&'a wgpu::TextureView>,
    cur_payload: &'a wgpu::TextureView,
}

/// Bind group layouts and bind groups of one fragment entry point.
struct Bindings {
    layouts: BTreeMap<u32, wgpu::BindGroupLayout>,
    groups: BTreeMap<u32, wgpu::BindGroup>,
    /// Each layout's entries, written out: part of the pipeline cache key.
    layout_keys: BTreeMap<u32, String>,
}

/// A color attachment of a variant pass.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Attachment {
    Frame,
    Cache,
    /// The fragment's depth, read by the next frame's lookup.
    DepthCopy,
}

/// One variant pass as the manifest describes it.
#[derive(Debug)]
struct PassSpec {
    label: String,
    /// By `@location`: the attachment and whether it is loaded (else cleared).
    colors: Vec<Option<(Attachment, bool)>>,
    compare: wgpu::CompareFunction,
    depth_write: bool,
    /// Depth loaded (else cleared to 1).
    depth_load: bool,
}

/// The passes of a variant, from its manifest.
fn pass_specs(m: &Manifest) -> Result<Vec<PassSpec>, ReplayError> {
    use reproj_instance::Strategy;
    let expected: &[PassKind] = match m.strategy {
        Strategy::ThreePass => &[PassKind::Reproject, PassKind::Recompute, PassKind::Shade],
        Strategy::TwoPass => &[PassKind::ShadeHits, PassKind::ShadeMisses],
        Strategy::Fused => &[PassKind::Fused],
    };
    let kinds: Vec<PassKind> = m.passes.iter().map(|p| p.kind).collect();
    let bad = |message: String| ReplayError::Variant { message };
    if kinds != expected {
        return Err(bad(format!(
            "a {} variant has the passes {expected:?}, the manifest lists {kinds:?}",
            m.strategy
        )));
    }
    m.passes
        .iter()
        .enumerate()
        .map(|(i, p)| {
            let mut colors = Vec::new();
            for c in &p.colors {
                let t = match c.attachment.as_str() {
                    reproj_instance::ATTACHMENT_FRAME => Attachment::Frame,
                    reproj_instance::ROLE_CUR_PAYLOAD => Attachment::Cache,
                    reproj_instance::ROLE_CUR_DEPTH_COPY => Attachment::DepthCopy,
                    other => return Err(bad(format!("unknown color attachment `{other}`"))),
                };
                let load = c.load.is_load();
                let at = c.location as usize;
                if at >= 8 {
                    return Err(bad(format!("color location {at} is out of range")));
                }
                if colors.len() <= at {
                    colors.resize(at + 1, None);
                }
                colors[at] = Some((t, load));
            }
            let compare = match p.depth.compare.as_str() {
                "less" => wgpu::CompareFunction::Less,
                "less-equal" => wgpu::CompareFunction::LessEqual,
                "equal" => wgpu::CompareFunction::Equal,
                "always" => wgpu::CompareFunction::Always,
                other => return Err(bad(format!("unknown depth compare `{other}`"))),
            };
            Ok(PassSpec {
                label: format!("pass {} {}", i + 1, p.file.trim_end_matches(".wgsl")),
                colors,
                compare,
                depth_write: p.depth.write,
                depth_load: p.depth.load.is_load(),
            })
        })
        .collect()
}

/// Hits, misses (recomputes, refreshes included) and shaded pixels of one frame.
struct Counts {
    hits: u64,
    misses: u64,
    shaded: u64,
}

/// The frame's counts from its occlusion queries (one per pass, in pass order) and, for the
/// fused strategy whose one pass cannot count hits apart, the classification map.
fn counts_of(strategy: reproj_instance::Strategy, occ: &[u64], hit_px: Option<u64>) -> Counts {
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

/// Occlusion counts, per-pass ms, frame span ms of one frame's queries.
type QueryResults = (Vec<u64>, Vec<f64>, Option<f64>);

/// One pipeline per cull mode used by the scene.
#[derive(Clone)]
struct Pipe {
    by_cull: HashMap<Cull, wgpu::RenderPipeline>,
}

pub(crate) fn tex_dim(d: TexDim) -> wgpu::TextureViewDimension {
    match d {
        TexDim::D2 => wgpu::TextureViewDimension::D2,
        TexDim::D3 => wgpu::TextureViewDimension::D3,
        TexDim::Cube => wgpu::TextureViewDimension::Cube,
    }
}

pub(crate) fn readback_row_bytes(width: u32, bpp: u32) -> u32 {
    let a = wgpu::COPY_BYTES_PER_ROW_ALIGNMENT;
    (width * bpp).div_ceil(a) * a
}

/// Lowest group index not in `used`.
fn free_group(used: &BTreeSet<u32>) -> Result<u32, ReplayError> {
    let g = (0..MAX_BIND_GROUPS).find(|g| !used.contains(g)).ok_or_else(|| ReplayError::Unsupported {
        what: format!(
            "the fragment modules use every bind group 0..{MAX_BIND_GROUPS}; the replay needs a free one for the vertex transforms"
        ),
    })?;
    Ok(g)
}

impl Renderer {
    /// Open the default adapter of the chosen backends (Vulkan unless `opts.backend` or
    /// `WGPU_BACKEND` says otherwise) and create a device with timestamp queries when available.
    pub fn new(opts: &RendererOptions) -> Result<Renderer, ReplayError> {
        let backends = match &opts.backend {
            Some(b) => crate::backend::parse_backends(b, "--backend")?,
            None => match std::env::var("WGPU_BACKEND") {
                Ok(b) if !b.trim().is_empty() => {
                    crate::backend::parse_backends(&b, "WGPU_BACKEND")?
                }
                _ => wgpu::Backends::VULKAN,
            },
        };
        let mut desc = wgpu::InstanceDescriptor::new_without_display_handle().with_env();
        desc.backends = backends;
        let instance = wgpu::Instance::new(desc);
        let adapter = pollster::block_on(instance.request_adapter(&wgpu::RequestAdapterOptions {
            power_preference: wgpu::PowerPreference::from_env().unwrap_or_default(),
            ..Default::default()
        }))
        .map_err(|_| ReplayError::NoAdapter {
            backends: format!("{backends:?}"),
        })?;
        let info = adapter.get_info();
        let adapter_info = AdapterReport {
            name: info.name.clone(),
            backend: format!("{:?}", info.backend),
            device_type: format!("{:?}", info.device_type),
            driver: info.driver.clone(),
            driver_info: info.driver_info.clone(),
        };
        let want_ts =
            !opts.cpu_timing && adapter.features().contains(wgpu::Features::TIMESTAMP_QUERY);
        let mut features = if want_ts {
            wgpu::Features::TIMESTAMP_QUERY
        } else {
            wgpu::Features::empty()
        };
        // Pass 1 reconstructs an rgba32float cache with one filtered fetch when it can.
        features |= adapter.features() & wgpu::Features::FLOAT32_FILTERABLE;
        let (device, queue) = pollster::block_on(adapter.request_device(&wgpu::DeviceDescriptor {
            label: Some("reproj-replay"),
            required_features: features,
            required_limits: adapter.limits(),
            ..Default::default()
        }))
        .map_err(|e| ReplayError::Device {
            adapter: info.name.clone(),
            message: e.to_string(),
        })?;
        let errors: Arc<Mutex<Vec<String>>> = Arc::default();
        let sink = errors.clone();
        device.on_uncaptured_error(Arc::new(move |e: wgpu::Error| {
            if let Ok(mut v) = sink.lock() {
                v.push(e.to_string());
            }
        }));
        let timestamp_period = queue.get_timestamp_period();
        Ok(Renderer {
            _instance: instance,
            adapter_info,
            device,
            queue,
            timestamps: want_ts,
            timestamp_period,
            errors,
            id: NEXT_RENDERER_ID.fetch_add(1, Ordering::Relaxed),
            assets: Assets::default(),
            reduce_kernel: Mutex::new(None),
            pipelines: Mutex::default(),
            pipeline_hits: AtomicU64::new(0),
        })
    }

    /// The error reduction pipeline, built on first use.
    pub(crate) fn reduce_kernel(&self) -> Result<reduce::Kernel, ReplayError> {
        let mut k = self.reduce_kernel.lock().unwrap_or_else(|e| e.into_inner());
        if let Some(k) = &*k {
            return Ok(k.clone());
        }
        let built = reduce::Kernel::new(self)?;
        *k = Some(built.clone());
        Ok(built)
    }

    /// How many times a replay found its render pipelines already built (compiled) by an earlier one.
    pub fn reused_pipelines(&self) -> u64 {
        self.pipeline_hits.load(Ordering::Relaxed)
    }

    /// How many times a replay found a mesh or texture of its session already on the GPU.
    pub fn reused_assets(&self) -> u64 {
        self.assets.hits()
    }

    /// The adapter results are measured on.
    pub fn adapter(&self) -> &AdapterReport {
        &self.adapter_info
    }

    /// How frame times are measured.
    pub fn timing_method(&self) -> TimingMethod {
        if self.timestamps {
            TimingMethod::GpuTimestamps
        } else {
            TimingMethod::CpuSubmitWait
        }
    }

    fn check_errors(&self, what: &str) -> Result<(), ReplayError> {
        let mut v = self
            .errors
            .lock()
            .map_err(|_| gpu_err(what, "error sink poisoned"))?;
        if v.is_empty() {
            Ok(())
        } else {
            let msg = v.join("; ");
            v.clear();
            Err(gpu_err(what, msg))
        }
    }

    /// Run `f` inside a validation error scope; wgpu's complaint becomes an error.
    pub(crate) fn scoped<T>(&self, what: &str, f: impl FnOnce() -> T) -> Result<T, ReplayError> {
        let guard = self.device.push_error_scope(wgpu::ErrorFilter::Validation);
        let out = f();
        if let Some(e) = pollster::block_on(guard.pop()) {
            return Err(gpu_err(what, e));
        }
        self.check_errors(what)?;
        Ok(out)
    }

    fn wait(&self) -> Result<(), ReplayError> {
        self.device
            .poll(wgpu::PollType::wait_indefinitely())
            .map_err(|e| gpu_err("waiting for the GPU", e))?;
        Ok(())
    }

    /// Map every buffer in `bufs` for reading with a single host wait. The caller reads them with
    /// `get_mapped_range` and unmaps them with [`Renderer::unmap_all`].
    pub(crate) fn map_read(&self, bufs: &[&wgpu::Buffer]) -> Result<(), ReplayError> {
        type Statuses = Arc<Mutex<Vec<Result<(), wgpu::BufferAsyncError>>>>;
        let status: Statuses = Arc::default();
        for b in bufs {
            let s2 = status.clone();
            b.slice(..).map_async(wgpu::MapMode::Read, move |r| {
                if let Ok(mut g) = s2.lock() {
                    g.push(r);
                }
            });
        }
        self.wait()?;
        let done = status
            .lock()
            .map(|mut g| std::mem::take(&mut *g))
            .unwrap_or_default();
        if let Some(Err(e)) = done.iter().find(|r| r.is_err()) {
            return Err(gpu_err("mapping a readback buffer", e));
        }
        if done.len() != bufs.len() {
            return Err(gpu_err(
                "mapping a readback buffer",
                "the map did not complete",
            ));
        }
        Ok(())
    }

    pub(crate) fn unmap_all(bufs: &[&wgpu::Buffer]) {
        for b in bufs {
            b.unmap();
        }
    }

    /// Frames per readback batch: up to [`MAX_BATCH`] and [`BATCH_BYTES`] of staging for images
    /// of `slot_bytes`; 1 without timestamp queries, where the frame time is the CPU wait.
    fn batch_len(&self, frames: u32, slot_bytes: u64) -> u32 {
        if !self.timestamps {
            return 1;
        }
        let budget = BATCH_BYTES.min(self.device.limits().max_buffer_size);
        let by_mem = (budget / slot_bytes.max(1)).max(1);
        by_mem.min(MAX_BATCH as u64).min(frames.max(1) as u64) as u32
    }

    fn make_stage(&self, path: &Path, source: String, entry: &str) -> Result<Stage, ReplayError> {
        let shader =
            reproj_front::parse_shader(path, source).map_err(|e| ReplayError::Variant {
                message: e.to_string(),
            })?;
        let idx = reflect::fragment_entry_index(&shader.module, entry).ok_or_else(|| {
            ReplayError::Variant {
                message: format!("{}: no @fragment entry point `{entry}`", path.display()),
            }
        })?;
        let iface = reflect::reflect(&shader.module, &shader.info, idx)?;
        Ok(Stage { shader, iface })
    }

    fn shader_module(&self, label: &str, source: &str) -> Result<wgpu::ShaderModule, ReplayError> {
        self.scoped(&format!("shader module {label}"), || {
            self.device
                .create_shader_module(wgpu::ShaderModuleDescriptor {
                    label: Some(label),
                    source: wgpu::ShaderSource::Wgsl(Cow::Borrowed(source)),
                })
        })
    }

    /// Build every session resource the interfaces use (except `skip_group`, the variant's own
    /// group). Missing ones are reported together, by name.
    fn build_scene(
        &self,
        session: &Session,
        ifaces: &[&Interface],
        skip_group: Option<u32>,
    ) -> Result<Scene, ReplayError> {
        let mut missing_fields = Vec::new();
        let mut missing_textures = Vec::new();
        let mut unsupported = Vec::new();
        let mut tex_needed: BTreeMap<String, TexDim> = BTreeMap::new();
        let mut samp_needed: BTreeSet<String> = BTreeSet::new();
        let mut uni_needed: BTreeMap<String, (u32, Vec<reflect::UniformField>)> = BTreeMap::new();
        for iface in ifaces {
            for r in &iface.resources {
                if Some(r.group) == skip_group {
                    continue;
                }
                match &r.kind {
                    ResourceKind::Uniform { size, fields } => {
                        for f in fields {
                            if !crate::scene::session_must_provide(&f.name) {
                                continue;
                            }
                            match session.uniforms.get(&f.name) {
                                None => missing_fields.push(format!("`{}` (field of uniform `{}`)", f.name, r.name)),
                                Some(v) if v.len() != f.len() => unsupported.push(format!(
                                    "uniform field `{}` is {} ({} values) but the session gives {} values",
                                    f.name,
                                    f.ty,
                                    f.len(),
                                    v.len()
                                )),
                                Some(_) => {}
                            }
                        }
                        uni_needed.insert(r.name.clone(), (*size, fields.clone()));
                    }
                    ResourceKind::Texture { dim } => {
                        if !session.textures.contains_key(&r.name) {
                            missing_textures.push(format!("`{}`", r.name));
                        } else {
                            tex_needed.insert(r.name.clone(), *dim);
                        }
                    }
                    ResourceKind::Sampler { comparison } => {
                        if *comparison {
                            unsupported.push(format!("comparison sampler `{}`", r.name));
                        }
                        samp_needed.insert(r.name.clone());
                    }
                    ResourceKind::DepthTexture => {
                        unsupported.push(format!("depth texture `{}`", r.name));
                    }
                    ResourceKind::Unsupported(what) => unsupported.push(what.clone()),
                }
            }
        }
        missing_textures.sort();
        missing_textures.dedup();
        missing_fields.sort();
        missing_fields.dedup();
        if !missing_textures.is_empty() || !missing_fields.is_empty() {
            let mut names = missing_textures
                .iter()
                .map(|t| format!("texture {t}"))
                .collect::<Vec<_>>();
            names.extend(missing_fields.iter().map(|f| format!("uniform {f}")));
            return Err(ReplayError::MissingResources {
                what: "resources the shader declares".into(),
                names,
            });
        }
        if !unsupported.is_empty() {
            unsupported.sort();
            unsupported.dedup();
            return Err(ReplayError::Unsupported {
                what: unsupported.join("; "),
            });
        }
        self.scoped(
            "creating the session's resources",
            || -> Result<Scene, ReplayError> {
                let dev = &self.device;
                // Meshes and per-object transforms.
                let vertex_bgl = dev.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
                    label: Some("replay vertex transforms"),
                    entries: &[wgpu::BindGroupLayoutEntry {
                        binding: 0,
                        visibility: wgpu::ShaderStages::VERTEX,
                        ty: wgpu::BindingType::Buffer {
                            ty: wgpu::BufferBindingType::Uniform,
                            has_dynamic_offset: false,
                            min_binding_size: NonZeroU64::new(
                                std::mem::size_of::<TransformUniform>() as u64,
                            ),
                        },
                        count: None,
                    }],
                });
                let mut objects = Vec::new();
                for (i, o) in session.geometry.objects.iter().enumerate() {
                    let m = self.assets.mesh(self, session, &o.mesh)?;
                    let xf_buf = dev.create_buffer(&wgpu::BufferDescriptor {
                        label: Some(&format!("object {i} transforms")),
                        size: std::mem::size_of::<TransformUniform>() as u64,
                        usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
                        mapped_at_creation: false,
                    });
                    let xf_bg = dev.create_bind_group(&wgpu::BindGroupDescriptor {
                        label: Some("object transforms"),
                        layout: &vertex_bgl,
                        entries: &[wgpu::BindGroupEntry {
                            binding: 0,
                            resource: xf_buf.as_entire_binding(),
                        }],
                    });
                    objects.push(ObjectGpu {
                        vbuf: m.vbuf,
                        ibuf: m.ibuf,
                        count: m.count,
                        cull: o.cull,
                        xf_buf,
                        xf_bg,
                    });
                }
                // Textures.
                let mut textures = HashMap::new();
                for (name, dim) in &tex_needed {
                    let view =
                        self.assets
                            .texture(self, session, name, &session.textures[name], *dim)?;
                    textures.insert(name.clone(), view);
                }
                // Samplers.
                let mut samplers = HashMap::new();
                for name in &samp_needed {
                    let spec = session.samplers.get(name).cloned().unwrap_or_default();
                    let f = |x: Filter| match x {
                        Filter::Linear => wgpu::FilterMode::Linear,
                        Filter::Nearest => wgpu::FilterMode::Nearest,
                    };
                    let mf = match spec.mipmap_filter {
                        Filter::Linear => wgpu::MipmapFilterMode::Linear,
                        Filter::Nearest => wgpu::MipmapFilterMode::Nearest,
                    };
                    let a = match spec.address {
                        Address::Repeat => wgpu::AddressMode::Repeat,
                        Address::Clamp => wgpu::AddressMode::ClampToEdge,
                        Address::Mirror => wgpu::AddressMode::MirrorRepeat,
                    };
                    let all_linear =
                        spec.filter == Filter::Linear && spec.mipmap_filter == Filter::Linear;
                    let s = dev.create_sampler(&wgpu::SamplerDescriptor {
                        label: Some(name),
                        address_mode_u: a,
                        address_mode_v: a,
                        address_mode_w: a,
                        mag_filter: f(spec.filter),
                        min_filter: f(spec.filter),
                        mipmap_filter: mf,
                        anisotropy_clamp: if all_linear { spec.anisotropy } else { 1 },
                        ..Default::default()
                    });
                    samplers.insert(name.clone(), s);
                }
                // Uniform buffers.
                let mut uniforms = BTreeMap::new();
                for (name, (size, fields)) in uni_needed {
                    let buf = dev.create_buffer(&wgpu::BufferDescriptor {
                        label: Some(&name),
                        size: size.max(16) as u64,
                        usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
                        mapped_at_creation: false,
                    });
                    uniforms.insert(name, (buf, size, fields));
                }
                Ok(Scene {
                    objects,
                    textures,
                    samplers,
                    uniforms,
                    vertex_bgl,
                })
            },
        )?
    }

    /// Write the frame's uniform values and transforms.
    fn write_frame_uniforms(&self, session: &Session, scene: &Scene, frame: u32) {
        let st = session.frame_state(frame);
        let prev = session.frame_state(frame.saturating_sub(1));
        for (i, o) in scene.objects.iter().enumerate() {
            let u = TransformUniform::new(
                st.camera.view_proj,
                prev.camera.view_proj,
                st.models[i],
                prev.models[i],
            );
            self.queue
                .write_buffer(&o.xf_buf, 0, bytemuck::bytes_of(&u));
        }
        for (buf, size, fields) in scene.uniforms.values() {
            let bytes = crate::scene::uniform_bytes(session, &st, *size, fields);
            self.queue.write_buffer(buf, 0, &bytes);
        }
    }

    /// Layouts and bind groups of one fragment interface (every group but the vertex group).
    fn bindings(
        &self,
        label: &str,
        iface: &Interface,
        scene: &Scene,
        added_group: Option<u32>,
        added: Option<&AddedResources<'_>>,
    ) -> Result<Bindings, ReplayError> {
        let added_format_16 = added.is_some_and(|a| a.payload_half);
        let mut by_group: BTreeMap<u32, Vec<&reflect::Resource>> = BTreeMap::new();
        for r in &iface.resources {
            by_group.entry(r.group).or_default().push(r);
        }
        let mut layouts = BTreeMap::new();
        let mut groups = BTreeMap::new();
        let mut layout_keys = BTreeMap::new();
        for (g, rs) in by_group {
            let in_added = Some(g) == added_group;
            let mut entries = Vec::new();
            let mut bind: Vec<wgpu::BindingResource<'_>> = Vec::new();
            for r in &rs {
                let missing = |what: &str| ReplayError::Variant {
                    message: format!(
                        "{label}: {what} `{}` at @group({g}) @binding({}) is not one the replay knows",
                        r.name, r.binding
                    ),
                };
                let (ty, res) = match &r.kind {
                    ResourceKind::Uniform { size, .. } => {
                        let buf = if in_added {
                            match (r.name.as_str(), added) {
                                ("reproj_params", Some(a)) => a.params,
                                _ => return Err(missing("uniform")),
                            }
                        } else {
                            &scene
                                .uniforms
                                .get(&r.name)
                                .ok_or_else(|| missing("uniform"))?
                                .0
                        };
                        (
                            wgpu::BindingType::Buffer {
                                ty: wgpu::BufferBindingType::Uniform,
                                has_dynamic_offset: false,
                                min_binding_size: NonZeroU64::new(*size as u64),
                            },
                            buf.as_entire_binding(),
                        )
                    }
                    ResourceKind::Texture { dim } => {
                        let view = if in_added {
                            match (r.name.as_str(), added) {
                                ("reproj_prev_payload", Some(a)) => a.prev_payload,
                                ("reproj_prev_depth", Some(a)) => a.prev_depth_copy,
                                ("reproj_cur_payload", Some(a)) => a.cur_payload,
                                _ => return Err(missing("texture")),
                            }
                        } else {
                            scene
                                .textures
                                .get(&r.name)
                                .ok_or_else(|| missing("texture"))?
                        };
                        let filterable = !in_added
                            || (r.name == "reproj_prev_payload"
                                && (self
                                    .device
                                    .features()
                                    .contains(wgpu::Features::FLOAT32_FILTERABLE)
                                    || added_format_16));
                        (
                            wgpu::BindingType::Texture {
                                sample_type: wgpu::TextureSampleType::Float { filterable },
                                view_dimension: tex_dim(*dim),
                                multisampled: false,
                            },
                            wgpu::BindingResource::TextureView(view),
                        )
                    }
                    ResourceKind::DepthTexture => {
                        let view = match (r.name.as_str(), added) {
                            ("reproj_prev_depth", Some(a)) if in_added => a
                                .prev_depth_buffer
                                .ok_or_else(|| missing("depth texture"))?,
                            _ => return Err(missing("depth texture")),
                        };
                        (
                            wgpu::BindingType::Texture {
                                sample_type: wgpu::TextureSampleType::Depth,
                                view_dimension: wgpu::TextureViewDimension::D2,
                                multisampled: false,
                            },
                            wgpu::BindingResource::TextureView(view),
                        )
                    }
                    ResourceKind::Sampler { .. } if in_added => {
                        let (s, ty) = match (r.name.as_str(), added) {
                            ("reproj_point_sampler", Some(a)) => {
                                (a.point_sampler, wgpu::SamplerBindingType::NonFiltering)
                            }
                            ("reproj_linear_sampler", Some(a)) => {
                                (a.linear_sampler, wgpu::SamplerBindingType::Filtering)
                            }
                            _ => return Err(missing("sampler")),
                        };
                        (
                            wgpu::BindingType::Sampler(ty),
                            wgpu::BindingResource::Sampler(s),
                        )
                    }
                    ResourceKind::Sampler { .. } => {
                        let s = scene
                            .samplers
                            .get(&r.name)
                            .ok_or_else(|| missing("sampler"))?;
                        (
                            wgpu::BindingType::Sampler(wgpu::SamplerBindingType::Filtering),
                            wgpu::BindingResource::Sampler(s),
                        )
                    }
                    ResourceKind::Unsupported(w) => {
                        return Err(ReplayError::Unsupported { what: w.clone() });
                    }
                };
                entries.push(wgpu::BindGroupLayoutEntry {
                    binding: r.binding,
                    visibility: wgpu::ShaderStages::FRAGMENT,
                    ty,
                    count: None,
                });
                bind.push(res);
            }
            let (layout, group) = self.scoped(&format!("{label}: bind group {g}"), || {
                let layout =
                    self.device
                        .create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
                            label: Some(label),
                            entries: &entries,
                        });
                let group_entries: Vec<wgpu::BindGroupEntry<'_>> = rs
                    .iter()
                    .zip(bind)
                    .map(|(r, resource)| wgpu::BindGroupEntry {
                        binding: r.binding,
                        resource,
                    })
                    .collect();
                let group = self.device.create_bind_group(&wgpu::BindGroupDescriptor {
                    label: Some(label),
                    layout: &layout,
                    entries: &group_entries,
                });
                (layout, group)
            })?;
            layouts.insert(g, layout);
            groups.insert(g, group);
            layout_keys.insert(g, format!("{entries:?}"));
        }
        Ok(Bindings {
            layouts,
            groups,
            layout_keys,
        })
    }

    #[allow(clippy::too_many_arguments)]
    /// The render pipelines of one pass, one per cull mode. Kept across replays (keyed by the
    /// stages' whole WGSL sources and every piece of state), so replaying a variant again at another Δn
    /// does not compile its shaders again: on a CPU rasterizer compilation is most of a replay's
    /// set-up time.
    fn pipeline(
        &self,
        label: &str,
        sources: [&str; 2],
        vs: &wgpu::ShaderModule,
        fs: &wgpu::ShaderModule,
        entry: &str,
        bindings: &Bindings,
        scene: &Scene,
        vertex_group: u32,
        formats: &[Option<wgpu::TextureFormat>],
        compare: wgpu::CompareFunction,
        depth_write: bool,
    ) -> Result<Pipe, ReplayError> {
        let targets: Vec<Option<wgpu::ColorTargetState>> = formats
            .iter()
            .map(|f| {
                f.map(|format| wgpu::ColorTargetState {
                    format,
                    blend: None,
                    write_mask: wgpu::ColorWrites::ALL,
                })
            })
            .collect();
        let max_group = bindings
            .layouts
            .keys()
            .copied()
            .chain([vertex_group])
            .max()
            .unwrap_or(0);
        let bgls: Vec<Option<&wgpu::BindGroupLayout>> = (0..=max_group)
            .map(|g| {
                if g == vertex_group {
                    Some(&scene.vertex_bgl)
                } else {
                    bindings.layouts.get(&g)
                }
            })
            .collect();
        let culls: BTreeSet<u8> = scene.objects.iter().map(|o| o.cull as u8).collect();
        let key = format!(
            "{label}|{entry}|{:?}|{vertex_group}|{formats:?}|{compare:?}|{depth_write}|{culls:?}|{}|{}",
            bindings.layout_keys, sources[0], sources[1],
        );
        if let Some(p) = self
            .pipelines
            .lock()
            .unwrap_or_else(|e| e.into_inner())
            .get(&key)
        {
            self.pipeline_hits.fetch_add(1, Ordering::Relaxed);
            return Ok(p.clone());
        }
        let mut by_cull = HashMap::new();
        self.scoped(&format!("render pipeline {label}"), || {
            let layout = self.device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
                label: Some(label),
                bind_group_layouts: &bgls,
                immediate_size: 0,
            });
            let attrs = wgpu::vertex_attr_array![0 => Float32x3, 1 => Float32x3, 2 => Float32x2, 3 => Float32x4];
            for c in culls {
                let cull = if c == Cull::Back as u8 { Cull::Back } else { Cull::None };
                let p = self.device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
                    label: Some(label),
                    layout: Some(&layout),
                    vertex: wgpu::VertexState {
                        module: vs,
                        entry_point: Some(VERTEX_ENTRY),
                        compilation_options: Default::default(),
                        buffers: &[Some(wgpu::VertexBufferLayout {
                            array_stride: std::mem::size_of::<Vertex>() as u64,
                            step_mode: wgpu::VertexStepMode::Vertex,
                            attributes: &attrs,
                        })],
                    },
                    primitive: wgpu::PrimitiveState {
                        topology: wgpu::PrimitiveTopology::TriangleList,
                        front_face: wgpu::FrontFace::Ccw,
                        cull_mode: if cull == Cull::Back { Some(wgpu::Face::Back) } else { None },
                        ..Default::default()
                    },
                    depth_stencil: Some(wgpu::DepthStencilState {
                        format: DEPTH_FORMAT,
                        depth_write_enabled: Some(depth_write),
                        depth_compare: Some(compare),
                        stencil: Default::default(),
                        bias: Default::default(),
                    }),
                    multisample: Default::default(),
                    fragment: Some(wgpu::FragmentState {
                        module: fs,
                        entry_point: Some(entry),
                        compilation_options: Default::default(),
                        targets: &targets,
                    }),
                    multiview_mask: None,
                    cache: None,
                });
                by_cull.insert(cull, p);
            }
        })?;
        let pipe = Pipe { by_cull };
        let mut cache = self.pipelines.lock().unwrap_or_else(|e| e.into_inner());
        if cache.len() >= PIPELINE_CACHE_LEN {
            cache.clear();
        }
        cache.insert(key, pipe.clone());
        Ok(pipe)
    }

    fn draw(
        &self,
        pass: &mut wgpu::RenderPass<'_>,
        pipe: &Pipe,
        bindings: &Bindings,
        scene: &Scene,
        vertex_group: u32,
    ) {
        for (g, bg) in &bindings.groups {
            pass.set_bind_group(*g, bg, &[]);
        }
        for o in &scene.objects {
            if let Some(p) = pipe.by_cull.get(&o.cull) {
                pass.set_pipeline(p);
            }
            pass.set_bind_group(vertex_group, &o.xf_bg, &[]);
            pass.set_vertex_buffer(0, o.vbuf.slice(..));
            pass.set_index_buffer(o.ibuf.slice(..), wgpu::IndexFormat::Uint32);
            pass.draw_indexed(0..o.count, 0, 0..1);
        }
    }

    fn target(
        &self,
        label: &str,
        w: u32,
        h: u32,
        format: wgpu::TextureFormat,
        binding: bool,
    ) -> wgpu::Texture {
        let mut usage = wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::COPY_SRC;
        if binding {
            usage |= wgpu::TextureUsages::TEXTURE_BINDING;
        }
        self.device.create_texture(&wgpu::TextureDescriptor {
            label: Some(label),
            size: wgpu::Extent3d {
                width: w,
                height: h,
                depth_or_array_layers: 1,
            },
            mip_level_count: 1,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format,
            usage,
            view_formats: &[],
        })
    }

    fn buffer(&self, label: &str, size: u64, usage: wgpu::BufferUsages) -> wgpu::Buffer {
        self.device.create_buffer(&wgpu::BufferDescriptor {
            label: Some(label),
            size,
            usage,
            mapped_at_creation: false,
        })
    }

    /// Submit a frame's render and readback commands. With timestamp queries both go in one
    /// submission and nothing waits (None: the batch's wall time is amortized later). Without, the
    /// render submission is waited for and timed alone (that is the frame time) before the readback
    /// is submitted.
    fn submit_frame(
        &self,
        render: wgpu::CommandEncoder,
        readback: wgpu::CommandEncoder,
        what: &str,
    ) -> Result<Option<f64>, ReplayError> {
        if self.timestamps {
            self.queue.submit([render.finish(), readback.finish()]);
            return Ok(None);
        }
        let t0 = Instant::now();
        self.queue.submit([render.finish()]);
        self.wait()?;
        let cpu_ms = t0.elapsed().as_secs_f64() * 1e3;
        self.check_errors(what)?;
        self.queue.submit([readback.finish()]);
        Ok(Some(cpu_ms))
    }

    fn unpad(data: &[u8], w: u32, h: u32, bpp: u32) -> Vec<u8> {
        let row = readback_row_bytes(w, bpp) as usize;
        let tight = (w * bpp) as usize;
        let mut out = Vec::with_capacity(tight * h as usize);
        for y in 0..h as usize {
            out.extend_from_slice(&data[y * row..y * row + tight]);
        }
        out
    }

    fn frame_count(session: &Session, opts: &RenderOptions) -> u32 {
        opts.max_frames
            .map_or(session.frames, |m| m.min(session.frames))
            .max(1)
    }

    /// Render the original shader's fragment entry `entry_index` over the session: the reference
    /// frames (kept in memory) and a report with frame times and shaded-pixel counts.
    pub fn render_original(
        &self,
        shader: &Shader,
        entry_index: usize,
        session: &Session,
        opts: &RenderOptions,
    ) -> Result<Reference, ReplayError> {
        session.clone().validate()?;
        let iface = reflect::reflect(&shader.module, &shader.info, entry_index)?;
        let [w, h] = session.resolution;
        let frames = Self::frame_count(session, opts);
        let used: BTreeSet<u32> = iface.groups().into_iter().collect();
        let vgroup = free_group(&used)?;
        let scene = self.build_scene(session, &[&iface], None)?;
        let vs_src = vertex::vertex_wgsl(vgroup, &iface.inputs, &session.inputs, None)?;
        let vs = self.shader_module("replay vertex stage", &vs_src)?;
        let fs = self.shader_module(&shader.path.display().to_string(), &shader.source)?;
        let bindings = self.bindings("original", &iface, &scene, None, None)?;
        let pipe = self.pipeline(
            "original",
            [&vs_src, &shader.source],
            &vs,
            &fs,
            &iface.entry,
            &bindings,
            &scene,
            vgroup,
            &[Some(FRAME_FORMAT)],
            wgpu::CompareFunction::Less,
            true,
        )?;

        let color = self.target("frame color", w, h, FRAME_FORMAT, false);
        let color_view = color.create_view(&Default::default());
        let depth = self.target("depth", w, h, DEPTH_FORMAT, false);
        let depth_view = depth.create_view(&Default::default());
        let slots = self.batch_len(frames, Staging::slot_bytes(w, h, 16));
        let q = QueryKit::new(self, 1, slots);
        let frame_rb = Staging::new(self, "frame readback", w, h, 16, slots);
        let depth_rb = Staging::new(self, "depth readback", w, h, 4, slots);
        let keeper = Keeper::new(self, w, h);
        let mut gpu = GpuReference::new(self);
        let mut rb_bufs = q.read_buffers();
        rb_bufs.push(&frame_rb.buf);
        rb_bufs.push(&depth_rb.buf);
        let bg = session.background;
        let clear = wgpu::Color {
            r: bg[0] as f64,
            g: bg[1] as f64,
            b: bg[2] as f64,
            a: bg[3] as f64,
        };

        let mut report = self.new_report("original", shader, &iface.entry, session);
        let mut out_frames = Vec::with_capacity(frames as usize);
        let mut out_depth = Vec::with_capacity(frames as usize);
        // Frames submitted but not read back yet: (frame, CPU time when measured alone).
        let mut pending: Vec<(u32, Option<f64>)> = Vec::new();
        let mut batch_t0 = Instant::now();
        for f in 0..frames {
            let slot = pending.len() as u32;
            self.write_frame_uniforms(session, &scene, f);
            let mut enc = self.device.create_command_encoder(&Default::default());
            {
                let mut pass = enc.begin_render_pass(&wgpu::RenderPassDescriptor {
                    label: Some("original"),
                    color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                        view: &color_view,
                        depth_slice: None,
                        resolve_target: None,
                        ops: wgpu::Operations {
                            load: wgpu::LoadOp::Clear(clear),
                            store: wgpu::StoreOp::Store,
                        },
                    })],
                    depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                        view: &depth_view,
                        depth_ops: Some(wgpu::Operations {
                            load: wgpu::LoadOp::Clear(1.0),
                            store: wgpu::StoreOp::Store,
                        }),
                        stencil_ops: None,
                    }),
                    timestamp_writes: q.writes(0),
                    occlusion_query_set: Some(&q.occlusion),
                    multiview_mask: None,
                });
                pass.begin_occlusion_query(0);
                self.draw(&mut pass, &pipe, &bindings, &scene, vgroup);
                pass.end_occlusion_query();
            }
            q.resolve(&mut enc, slot);
            let mut rb = self.device.create_command_encoder(&Default::default());
            frame_rb.copy(&mut rb, &color, slot);
            let at = slot as u64 * depth_rb.slot_bytes;
            keeper.keep(self, &mut rb, &color, &depth, &depth_rb.buf, at, &mut gpu);
            if slot == 0 {
                batch_t0 = Instant::now();
            }
            let cpu = self.submit_frame(enc, rb, &format!("rendering frame {f}"))?;
            pending.push((f, cpu));
            if pending.len() < slots as usize && f + 1 < frames {
                continue;
            }

            // Read the batch back with one wait.
            self.map_read(&rb_bufs)?;
            let batch_ms = batch_t0.elapsed().as_secs_f64() * 1e3 / pending.len() as f64;
            self.check_errors(&format!("rendering frames {}..={f}", pending[0].0))?;
            for (slot, &(f, cpu)) in pending.iter().enumerate() {
                let slot = slot as u32;
                let cpu_ms = cpu.unwrap_or(batch_ms);
                let pixels: Vec<f32> = bytemuck::pod_collect_to_vec(&frame_rb.image(slot)?);
                let depth: Vec<f32> = bytemuck::pod_collect_to_vec(&depth_rb.image(slot)?);
                let covered = depth.iter().filter(|&&d| d < 1.0).count() as u64;
                let (occ, pass_ms, span) = q.read(slot)?;
                let frame_ms = span.unwrap_or(cpu_ms);
                if let Some(dir) = &opts.png_dir {
                    output::write_frame(dir, f, w, h, &pixels)?;
                    if opts.raw_frames {
                        output::write_frame_raw(dir, f, &pixels)?;
                    }
                }
                report.frames.push(FrameRecord {
                    frame: f,
                    frame_ms,
                    cpu_ms,
                    pass_ms,
                    shaded: occ[0],
                    hits: 0,
                    recomputes: occ[0],
                    hit_px: None,
                    miss_px: None,
                    refresh_px: None,
                    hit_rate: 0.0,
                    error: 0.0,
                    mse: 0.0,
                    covered,
                    psnr: metrics::PSNR_CAP,
                    max_abs_diff: 0.0,
                    flip: None,
                    ssim: None,
                });
                out_frames.push(pixels);
                out_depth.push(depth);
            }
            Self::unmap_all(&rb_bufs);
            self.check_errors(&format!("reading frames {}..={f}", pending[0].0))?;
            pending.clear();
        }
        report.summarize();
        Ok(Reference {
            width: w,
            height: h,
            frames: out_frames,
            depth: out_depth,
            report,
            gpu,
        })
    }

    fn new_report(
        &self,
        kind: &str,
        shader: &Shader,
        entry: &str,
        session: &Session,
    ) -> RenderReport {
        RenderReport {
            schema: metrics::RENDER_REPORT_SCHEMA.into(),
            version: metrics::RENDER_REPORT_VERSION,
            kind: kind.into(),
            shader: shader.path.display().to_string(),
            entry: entry.into(),
            session: session.display_name(),
            resolution: session.resolution,
            adapter: self.adapter_info.clone(),
            timing: self.timing_method(),
            node: None,
            delta_n: None,
            block: None,
            depth_epsilon: None,
            error: 0.0,
            error_worst: None,
            flip: None,
            ssim: None,
            mse: 0.0,
            psnr: metrics::PSNR_CAP,
            hit_rate: 0.0,
            frame_ms: 0.0,
            cpu_ms: 0.0,
            frames: Vec::new(),
        }
    }

    /// Render a cached variant of any strategy over the session (see `docs/PASSES.md`) and compare
    /// each frame with `reference` (from [`Renderer::render_original`] on the same session).
    ///
    /// Per frame, the manifest's passes in order, each with its color targets (frame color, current
    /// payload, current depth copy: cleared or loaded as listed) and depth state; then the current
    /// payload and depth copy become the previous ones. (A variant written before the depth copy
    /// reads the previous frame's depth buffer instead, which then alternates too.) Frame 0 runs with
    /// Δn = 1; `clock` is the frame index.
    pub fn render_variant(
        &self,
        shader: &Shader,
        session: &Session,
        variant: &VariantInput,
        reference: &Reference,
        opts: &RenderOptions,
    ) -> Result<RenderReport, ReplayError> {
        session.clone().validate()?;
        let m = &variant.manifest;
        let [w, h] = session.resolution;
        let frames = Self::frame_count(session, opts);
        if reference.width != w || reference.height != h || (reference.frames.len() as u32) < frames
        {
            return Err(ReplayError::ReferenceMismatch {
                reference: format!(
                    "{} frames, {}×{}",
                    reference.frames.len(),
                    reference.width,
                    reference.height
                ),
                session: format!("{frames} frames, {w}×{h}"),
            });
        }
        if variant.delta_n == 0 || variant.block == 0 {
            return Err(ReplayError::Variant {
                message: "Δn and k must be at least 1".into(),
            });
        }
        let specs = pass_specs(m)?;
        if variant.sources.len() != m.passes.len() {
            return Err(ReplayError::Variant {
                message: format!(
                    "the manifest lists {} passes and {} modules were given",
                    m.passes.len(),
                    variant.sources.len()
                ),
            });
        }
        let mut stages = Vec::new();
        for (p, src) in m.passes.iter().zip(&variant.sources) {
            stages.push(self.make_stage(Path::new(&p.file), src.clone(), &p.entry)?);
        }
        // naga's WGSL writer renames identifiers that end in a digit (`sh0` becomes `sh0_`): take
        // the shader's own names back from the original module, by group/binding and field order.
        let original = reflect::reflect(
            &shader.module,
            &shader.info,
            shader
                .fragment_entry(Some(&m.entry))
                .map_err(|e| ReplayError::Variant {
                    message: e.to_string(),
                })?,
        )?;
        for st in &mut stages {
            restore_names(&mut st.iface, &original);
        }
        // The fused pass cannot count its hits with an occlusion query: classify every frame.
        let classify_stage = if opts.classify || m.strategy == reproj_instance::Strategy::Fused {
            let s1 = &stages[0].shader;
            match reflect::fragment_entry_index(&s1.module, CLASSIFY_ENTRY) {
                Some(ci) => Some(reflect::reflect(&s1.module, &s1.info, ci)?),
                None => None,
            }
        } else {
            None
        };
        let mut used: BTreeSet<u32> = [m.group].into_iter().collect();
        for s in &stages {
            used.extend(s.iface.groups());
        }
        if let Some(c) = &classify_stage {
            used.extend(c.groups());
        }
        let vgroup = free_group(&used)?;
        let mut input_sets: Vec<&[reflect::FragInput]> =
            stages.iter().map(|s| s.iface.inputs.as_slice()).collect();
        if let Some(c) = &classify_stage {
            input_sets.push(&c.inputs);
        }
        let inputs = vertex::merge_inputs(&input_sets)?;
        let mut ifaces: Vec<&Interface> = stages.iter().map(|s| &s.iface).collect();
        if let Some(c) = &classify_stage {
            ifaces.push(c);
        }
        let scene = self.build_scene(session, &ifaces, Some(m.group))?;
        let vs_src = vertex::vertex_wgsl(
            vgroup,
            &inputs,
            &session.inputs,
            Some(m.vertex.prev_clip_location),
        )?;
        let vs = self.shader_module("replay vertex stage (variant)", &vs_src)?;
        let fsm: Vec<wgpu::ShaderModule> = stages
            .iter()
            .map(|s| self.shader_module(&s.shader.path.display().to_string(), &s.shader.source))
            .collect::<Result<_, _>>()?;

        let cache_format = match m.cache_format {
            CacheFormat::Rgba32float => wgpu::TextureFormat::Rgba32Float,
            CacheFormat::Rg32float => wgpu::TextureFormat::Rg32Float,
            CacheFormat::R32float => wgpu::TextureFormat::R32Float,
            CacheFormat::Rgba16float => wgpu::TextureFormat::Rgba16Float,
            CacheFormat::Rg16float => wgpu::TextureFormat::Rg16Float,
            CacheFormat::R16float => wgpu::TextureFormat::R16Float,
        };
        let payload = [
            self.target("payload A", w, h, cache_format, true),
            self.target("payload B", w, h, cache_format, true),
        ];
        let depth_copy = [
            self.target("depth copy A", w, h, DEPTH_COPY_FORMAT, true),
            self.target("depth copy B", w, h, DEPTH_COPY_FORMAT, true),
        ];
        // The lookup reads the depth copy; only a variant written before it (no depth copy target)
        // reads the previous depth buffer, which must then alternate like the payload.
        let legacy_depth = !specs.iter().any(|s| {
            s.colors
                .iter()
                .flatten()
                .any(|c| c.0 == Attachment::DepthCopy)
        });
        let depth: Vec<wgpu::Texture> = if legacy_depth {
            vec![
                self.target("depth A", w, h, DEPTH_FORMAT, true),
                self.target("depth B", w, h, DEPTH_FORMAT, true),
            ]
        } else {
            vec![self.target("depth", w, h, DEPTH_FORMAT, false)]
        };
        let views = |ts: &[wgpu::Texture]| -> Vec<wgpu::TextureView> {
            ts.iter()
                .map(|t| t.create_view(&Default::default()))
                .collect()
        };
        let payload_v = views(&payload);
        let depth_copy_v = views(&depth_copy);
        let depth_v = views(&depth);
        // The depth buffer of the frame of parity `p`.
        let depth_at = |p: usize| &depth_v[p % depth_v.len()];
        let color = self.target("frame color", w, h, FRAME_FORMAT, true);
        let color_view = color.create_view(&Default::default());
        let cls = self.target("classify", w, h, CLASSIFY_FORMAT, false);
        let cls_view = cls.create_view(&Default::default());
        let cls_depth = self.target("classify depth", w, h, DEPTH_FORMAT, false);
        let cls_depth_view = cls_depth.create_view(&Default::default());
        let params = self.buffer(
            "reproj_params",
            16,
            wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
        );

        let clamp = |filter: wgpu::FilterMode, label: &str| {
            self.device.create_sampler(&wgpu::SamplerDescriptor {
                label: Some(label),
                address_mode_u: wgpu::AddressMode::ClampToEdge,
                address_mode_v: wgpu::AddressMode::ClampToEdge,
                address_mode_w: wgpu::AddressMode::ClampToEdge,
                mag_filter: filter,
                min_filter: filter,
                ..Default::default()
            })
        };
        let point_sampler = clamp(wgpu::FilterMode::Nearest, "reproj_point_sampler");
        let linear_sampler = clamp(wgpu::FilterMode::Linear, "reproj_linear_sampler");
        if !m.cache_format.is_half()
            && m.reconstruct == reproj_instance::Reconstruct::Bilinear
            && !self
                .device
                .features()
                .contains(wgpu::Features::FLOAT32_FILTERABLE)
        {
            return Err(ReplayError::Unsupported {
                what: format!(
                    "{} has no float32-filterable feature, needed to filter a {} cache; use a 16-bit cache format or nearest reconstruction",
                    self.adapter_info.name,
                    m.cache_format.name()
                ),
            });
        }
        // Bindings for each parity (cur = parity, prev = 1 − parity).
        let mut binds: Vec<(Vec<Bindings>, Bindings)> = Vec::new();
        for parity in 0..2usize {
            let added = AddedResources {
                params: &params,
                point_sampler: &point_sampler,
                linear_sampler: &linear_sampler,
                payload_half: m.cache_format.is_half(),
                prev_payload: &payload_v[1 - parity],
                prev_depth_copy: &depth_copy_v[1 - parity],
                prev_depth_buffer: legacy_depth.then(|| depth_at(1 - parity)),
                cur_payload: &payload_v[parity],
            };
            let mut per_pass = Vec::new();
            for (st, spec) in stages.iter().zip(&specs) {
                per_pass.push(self.bindings(
                    &spec.label,
                    &st.iface,
                    &scene,
                    Some(m.group),
                    Some(&added),
                )?);
            }
            let bc = match &classify_stage {
                Some(c) => {
                    self.bindings("reproj_classify", c, &scene, Some(m.group), Some(&added))?
                }
                None => Bindings {
                    layouts: BTreeMap::new(),
                    groups: BTreeMap::new(),
                    layout_keys: BTreeMap::new(),
                },
            };
            binds.push((per_pass, bc));
        }
        use wgpu::CompareFunction as Cf;
        let mut pipes = Vec::new();
        for (i, spec) in specs.iter().enumerate() {
            let formats: Vec<Option<wgpu::TextureFormat>> = spec
                .colors
                .iter()
                .map(|c| {
                    c.map(|(t, _)| match t {
                        Attachment::Frame => FRAME_FORMAT,
                        Attachment::Cache => cache_format,
                        Attachment::DepthCopy => DEPTH_COPY_FORMAT,
                    })
                })
                .collect();
            pipes.push(self.pipeline(
                &spec.label,
                [&vs_src, &stages[i].shader.source],
                &vs,
                &fsm[i],
                &stages[i].iface.entry,
                &binds[0].0[i],
                &scene,
                vgroup,
                &formats,
                spec.compare,
                spec.depth_write,
            )?);
        }
        let pc = match &classify_stage {
            Some(_) => Some(self.pipeline(
                "reproj_classify",
                [&vs_src, &stages[0].shader.source],
                &vs,
                &fsm[0],
                CLASSIFY_ENTRY,
                &binds[0].1,
                &scene,
                vgroup,
                &[Some(CLASSIFY_FORMAT)],
                Cf::Less,
                true,
            )?),
            None => None,
        };

        let slots = self.batch_len(frames, Staging::slot_bytes(w, h, 16));
        let q = QueryKit::new(self, specs.len() as u32, slots);
        let back = match (&opts.png_dir, opts.perceptual_stride) {
            (Some(_), _) => PixelsBack::All,
            (None, Some(k)) => PixelsBack::Every(k.max(1)),
            (None, None) => PixelsBack::None,
        };
        let perceptual = |f: u32| {
            opts.perceptual_stride
                .is_some_and(|k| f.is_multiple_of(k.max(1)))
        };
        let errors = FrameErrors::new(self, reference, frames, slots, back)?;
        let cls_rb = pc
            .as_ref()
            .map(|_| Staging::new(self, "classify readback", w, h, 4, slots));
        let mut rb_bufs = q.read_buffers();
        rb_bufs.extend(errors.read_buffers());
        if let Some(c) = &cls_rb {
            rb_bufs.push(&c.buf);
        }
        let bg = session.background;
        let clear = wgpu::Color {
            r: bg[0] as f64,
            g: bg[1] as f64,
            b: bg[2] as f64,
            a: bg[3] as f64,
        };

        // The "previous" cache before frame 0: payload 0, depth 1.
        {
            let mut enc = self.device.create_command_encoder(&Default::default());
            for i in 0..2 {
                let clear_to = |view, color| {
                    Some(wgpu::RenderPassColorAttachment {
                        view,
                        depth_slice: None,
                        resolve_target: None,
                        ops: wgpu::Operations {
                            load: wgpu::LoadOp::Clear(color),
                            store: wgpu::StoreOp::Store,
                        },
                    })
                };
                let _ = enc.begin_render_pass(&wgpu::RenderPassDescriptor {
                    label: Some("clear cache"),
                    color_attachments: &[
                        clear_to(&payload_v[i], wgpu::Color::TRANSPARENT),
                        clear_to(&depth_copy_v[i], DEPTH_COPY_CLEAR),
                    ],
                    depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                        view: depth_at(i),
                        depth_ops: Some(wgpu::Operations {
                            load: wgpu::LoadOp::Clear(1.0),
                            store: wgpu::StoreOp::Store,
                        }),
                        stencil_ops: None,
                    }),
                    ..Default::default()
                });
            }
            self.queue.submit([enc.finish()]);
            self.wait()?;
            self.check_errors("clearing the cache")?;
        }

        let mut report = self.new_report("variant", shader, &m.entry, session);
        report.node = Some(m.node.id.clone());
        report.delta_n = Some(variant.delta_n);
        report.block = Some(variant.block);
        report.depth_epsilon = Some(variant.depth_epsilon);
        let clear_payload = wgpu::Color::TRANSPARENT;
        let host_clears_frame = !specs.iter().any(|s| {
            s.colors
                .iter()
                .flatten()
                .any(|(t, load)| *t == Attachment::Frame && !load)
        });
        // Frames submitted but not read back yet: (frame, CPU time when measured alone).
        let mut pending: Vec<(u32, Option<f64>)> = Vec::new();
        let mut batch_t0 = Instant::now();
        for f in 0..frames {
            let slot = pending.len() as u32;
            let cur = (f % 2) as usize;
            let b = &binds[cur];
            self.write_frame_uniforms(session, &scene, f);
            let dn = if f == 0 { 1 } else { variant.delta_n };
            let mut pbytes = [0u8; 16];
            pbytes[0..4].copy_from_slice(&dn.to_le_bytes());
            pbytes[4..8].copy_from_slice(&f.to_le_bytes());
            pbytes[8..12].copy_from_slice(&variant.block.to_le_bytes());
            pbytes[12..16].copy_from_slice(&variant.depth_epsilon.to_le_bytes());
            self.queue.write_buffer(&params, 0, &pbytes);

            let mut enc = self.device.create_command_encoder(&Default::default());
            if host_clears_frame {
                // `--frame-load load`: the passes keep what the engine drew; here that is the
                // background, as the original shader's frame starts.
                let _ = enc.begin_render_pass(&wgpu::RenderPassDescriptor {
                    label: Some("host clears the frame"),
                    color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                        view: &color_view,
                        depth_slice: None,
                        resolve_target: None,
                        ops: wgpu::Operations {
                            load: wgpu::LoadOp::Clear(clear),
                            store: wgpu::StoreOp::Store,
                        },
                    })],
                    ..Default::default()
                });
            }
            for (i, spec) in specs.iter().enumerate() {
                let colors: Vec<Option<wgpu::RenderPassColorAttachment<'_>>> = spec
                    .colors
                    .iter()
                    .map(|c| {
                        c.map(|(t, load)| {
                            let (view, clear_to) = match t {
                                Attachment::Frame => (&color_view, clear),
                                Attachment::Cache => (&payload_v[cur], clear_payload),
                                Attachment::DepthCopy => (&depth_copy_v[cur], DEPTH_COPY_CLEAR),
                            };
                            wgpu::RenderPassColorAttachment {
                                view,
                                depth_slice: None,
                                resolve_target: None,
                                ops: wgpu::Operations {
                                    load: if load {
                                        wgpu::LoadOp::Load
                                    } else {
                                        wgpu::LoadOp::Clear(clear_to)
                                    },
                                    store: wgpu::StoreOp::Store,
                                },
                            }
                        })
                    })
                    .collect();
                let mut pass = enc.begin_render_pass(&wgpu::RenderPassDescriptor {
                    label: Some(&spec.label),
                    color_attachments: &colors,
                    depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                        view: depth_at(cur),
                        depth_ops: Some(wgpu::Operations {
                            load: if spec.depth_load {
                                wgpu::LoadOp::Load
                            } else {
                                wgpu::LoadOp::Clear(1.0)
                            },
                            store: wgpu::StoreOp::Store,
                        }),
                        stencil_ops: None,
                    }),
                    timestamp_writes: q.writes(i as u32),
                    occlusion_query_set: Some(&q.occlusion),
                    multiview_mask: None,
                });
                pass.begin_occlusion_query(i as u32);
                self.draw(&mut pass, &pipes[i], &b.0[i], &scene, vgroup);
                pass.end_occlusion_query();
            }
            q.resolve(&mut enc, slot);

            // Readback (and the untimed classification pass).
            let render = enc;
            let mut enc = self.device.create_command_encoder(&Default::default());
            errors.encode(self, &mut enc, &color, &color_view, f, slot)?;
            if let (Some(pc), Some(cls_rb)) = (&pc, &cls_rb) {
                {
                    let mut pass = enc.begin_render_pass(&wgpu::RenderPassDescriptor {
                        label: Some("reproj_classify"),
                        color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                            view: &cls_view,
                            depth_slice: None,
                            resolve_target: None,
                            ops: wgpu::Operations {
                                load: wgpu::LoadOp::Clear(wgpu::Color::TRANSPARENT),
                                store: wgpu::StoreOp::Store,
                            },
                        })],
                        depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                            view: &cls_depth_view,
                            depth_ops: Some(wgpu::Operations {
                                load: wgpu::LoadOp::Clear(1.0),
                                store: wgpu::StoreOp::Store,
                            }),
                            stencil_ops: None,
                        }),
                        ..Default::default()
                    });
                    self.draw(&mut pass, pc, &b.1, &scene, vgroup);
                }
                cls_rb.copy(&mut enc, &cls, slot);
            }
            if slot == 0 {
                batch_t0 = Instant::now();
            }
            let cpu = self.submit_frame(render, enc, &format!("rendering variant frame {f}"))?;
            pending.push((f, cpu));
            if pending.len() < slots as usize && f + 1 < frames {
                continue;
            }

            // Read the batch back with one wait.
            self.map_read(&rb_bufs)?;
            let batch_ms = batch_t0.elapsed().as_secs_f64() * 1e3 / pending.len() as f64;
            let first = pending[0].0;
            self.check_errors(&format!("rendering variant frames {first}..={f}"))?;
            for (slot, &(f, cpu)) in pending.iter().enumerate() {
                let slot = slot as u32;
                let cpu_ms = cpu.unwrap_or(batch_ms);
                let (errs, pixels) = errors.read(slot, reference, f)?;
                let cls_px = match &cls_rb {
                    Some(c) => Some(c.image(slot)?),
                    None => None,
                };
                let (occ, pass_ms, span) = q.read(slot)?;

                let (mut hit_px, mut miss_px, mut refresh_px) = (None, None, None);
                if let Some(c) = &cls_px {
                    let (mut hi, mut mi, mut re) = (0u64, 0u64, 0u64);
                    for p in c.chunks_exact(4) {
                        if p[1] > 127 {
                            hi += 1;
                        } else if p[0] > 127 {
                            mi += 1;
                        } else if p[2] > 127 {
                            re += 1;
                        }
                    }
                    hit_px = Some(hi);
                    miss_px = Some(mi);
                    refresh_px = Some(re);
                }
                let counts = counts_of(m.strategy, &occ, hit_px);
                let hit_rate = match (hit_px, miss_px, refresh_px) {
                    (Some(hi), Some(mi), Some(re)) if hi + mi + re > 0 => {
                        hi as f64 / (hi + mi + re) as f64
                    }
                    _ if counts.shaded > 0 => (counts.hits as f64 / counts.shaded as f64).min(1.0),
                    _ => 0.0,
                };
                let frame_ms = span.unwrap_or(cpu_ms);
                let (mut flip, mut ssim) = (None, None);
                if let Some(pixels) = pixels.as_ref().filter(|_| perceptual(f)) {
                    let fi = f as usize;
                    let (e, map) = perceptual::compare_perceptual(
                        pixels,
                        &reference.frames[fi],
                        &reference.depth[fi],
                        w,
                        h,
                    );
                    (flip, ssim) = (Some(e.flip), Some(e.ssim));
                    if let Some(dir) = &opts.png_dir {
                        output::write_flipmap(dir, f, w, h, &map)?;
                    }
                }
                if let (Some(dir), Some(pixels)) = (&opts.png_dir, &pixels) {
                    let refr = &reference.frames[f as usize];
                    output::write_frame(dir, f, w, h, pixels)?;
                    if opts.raw_frames {
                        output::write_frame_raw(dir, f, pixels)?;
                    }
                    output::write_errmap(dir, f, w, h, &metrics::pixel_errors(pixels, refr))?;
                    if let Some(c) = &cls_px {
                        output::write_hitmap(dir, f, w, h, c)?;
                    }
                }
                report.frames.push(FrameRecord {
                    frame: f,
                    frame_ms,
                    cpu_ms,
                    pass_ms,
                    shaded: counts.shaded,
                    hits: counts.hits,
                    recomputes: counts.misses,
                    hit_px,
                    miss_px,
                    refresh_px,
                    hit_rate,
                    error: errs.error(),
                    mse: errs.mse(),
                    covered: errs.covered,
                    psnr: errs.psnr(),
                    max_abs_diff: errs.max_abs_diff,
                    flip,
                    ssim,
                });
            }
            Self::unmap_all(&rb_bufs);
            self.check_errors(&format!("reading variant frames {first}..={f}"))?;
            pending.clear();
            // Swap happens through the parity of the next frame.
        }
        report.summarize();
        Ok(report)
    }
}

/// A host-readable buffer of `slots` padded w×h images of `bpp` bytes per texel: each frame of a
/// readback batch copies its image into its own slot.
pub(crate) struct Staging {
    pub(crate) buf: wgpu::Buffer,
    pub(crate) slot_bytes: u64,
    w: u32,
    h: u32,
    bpp: u32,
}

impl Staging {
    pub(crate) fn new(r: &Renderer, label: &str, w: u32, h: u32, bpp: u32, slots: u32) -> Staging {
        let slot_bytes = Self::slot_bytes(w, h, bpp);
        let buf = r.buffer(
            label,
            slot_bytes * slots as u64,
            wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::MAP_READ,
        );
        Staging {
            buf,
            slot_bytes,
            w,
            h,
            bpp,
        }
    }

    /// Bytes of one padded image (a multiple of the row alignment, so slots stay aligned).
    fn slot_bytes(w: u32, h: u32, bpp: u32) -> u64 {
        readback_row_bytes(w, bpp) as u64 * h as u64
    }

    /// Record a copy of `tex` into `slot`.
    pub(crate) fn copy(&self, enc: &mut wgpu::CommandEncoder, tex: &wgpu::Texture, slot: u32) {
        enc.copy_texture_to_buffer(
            wgpu::TexelCopyTextureInfo {
                texture: tex,
                mip_level: 0,
                origin: wgpu::Origin3d::ZERO,
                aspect: wgpu::TextureAspect::All,
            },
            wgpu::TexelCopyBufferInfo {
                buffer: &self.buf,
                layout: wgpu::TexelCopyBufferLayout {
                    offset: slot as u64 * self.slot_bytes,
                    bytes_per_row: Some(readback_row_bytes(self.w, self.bpp)),
                    rows_per_image: Some(self.h),
                },
            },
            wgpu::Extent3d {
                width: self.w,
                height: self.h,
                depth_or_array_layers: 1,
            },
        );
    }

    /// The tightly packed image in `slot` (the buffer must be mapped).
    pub(crate) fn image(&self, slot: u32) -> Result<Vec<u8>, ReplayError> {
        let at = slot as u64 * self.slot_bytes;
        let view = self
            .buf
            .get_mapped_range(at..at + self.slot_bytes)
            .map_err(|e| gpu_err("reading a readback buffer", e))?;
        Ok(Renderer::unpad(&view, self.w, self.h, self.bpp))
    }
}

/// Occlusion and timestamp query sets for `passes` passes, with resolve and readback buffers of
/// `slots` frames: the query sets are reused every frame, and each frame of a readback batch
/// resolves its results into its own slot.
struct QueryKit {
    passes: u32,
    occlusion: wgpu::QuerySet,
    occ_resolve: wgpu::Buffer,
    occ_read: wgpu::Buffer,
    /// Bytes between the slots of the occlusion buffers (resolve offsets are 256-aligned).
    occ_stride: u64,
    ts: Option<(wgpu::QuerySet, wgpu::Buffer, wgpu::Buffer)>,
    /// Bytes between the slots of the timestamp buffers.
    ts_stride: u64,
    period_ns: f32,
}

impl QueryKit {
    fn new(r: &Renderer, passes: u32, slots: u32) -> QueryKit {
        let align = |n: u64| {
            n.div_ceil(wgpu::QUERY_RESOLVE_BUFFER_ALIGNMENT) * wgpu::QUERY_RESOLVE_BUFFER_ALIGNMENT
        };
        let occ_stride = align(8 * passes as u64);
        let ts_stride = align(16 * passes as u64);
        let occlusion = r.device.create_query_set(&wgpu::QuerySetDescriptor {
            label: Some("occlusion"),
            ty: wgpu::QueryType::Occlusion,
            count: passes,
        });
        let occ_resolve = r.buffer(
            "occlusion resolve",
            occ_stride * slots as u64,
            wgpu::BufferUsages::QUERY_RESOLVE | wgpu::BufferUsages::COPY_SRC,
        );
        let occ_read = r.buffer(
            "occlusion read",
            occ_stride * slots as u64,
            wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::MAP_READ,
        );
        let ts = r.timestamps.then(|| {
            let qs = r.device.create_query_set(&wgpu::QuerySetDescriptor {
                label: Some("timestamps"),
                ty: wgpu::QueryType::Timestamp,
                count: 2 * passes,
            });
            let res = r.buffer(
                "timestamp resolve",
                ts_stride * slots as u64,
                wgpu::BufferUsages::QUERY_RESOLVE | wgpu::BufferUsages::COPY_SRC,
            );
            let read = r.buffer(
                "timestamp read",
                ts_stride * slots as u64,
                wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::MAP_READ,
            );
            (qs, res, read)
        });
        QueryKit {
            passes,
            occlusion,
            occ_resolve,
            occ_read,
            occ_stride,
            ts,
            ts_stride,
            period_ns: r.timestamp_period,
        }
    }

    fn writes(&self, pass: u32) -> Option<wgpu::RenderPassTimestampWrites<'_>> {
        self.ts
            .as_ref()
            .map(|(qs, _, _)| wgpu::RenderPassTimestampWrites {
                query_set: qs,
                beginning_of_pass_write_index: Some(2 * pass),
                end_of_pass_write_index: Some(2 * pass + 1),
            })
    }

    /// Record resolving this frame's queries into `slot` of the readback buffers.
    fn resolve(&self, enc: &mut wgpu::CommandEncoder, slot: u32) {
        let at = self.occ_stride * slot as u64;
        enc.resolve_query_set(&self.occlusion, 0..self.passes, &self.occ_resolve, at);
        enc.copy_buffer_to_buffer(
            &self.occ_resolve,
            at,
            &self.occ_read,
            at,
            Some(8 * self.passes as u64),
        );
        if let Some((qs, res, read)) = &self.ts {
            let at = self.ts_stride * slot as u64;
            enc.resolve_query_set(qs, 0..2 * self.passes, res, at);
            enc.copy_buffer_to_buffer(res, at, read, at, Some(16 * self.passes as u64));
        }
    }

    /// The readback buffers, to map once per batch.
    fn read_buffers(&self) -> Vec<&wgpu::Buffer> {
        let mut v = vec![&self.occ_read];
        if let Some((_, _, read)) = &self.ts {
            v.push(read);
        }
        v
    }

    /// (occlusion counts per pass, per-pass ms, first-begin-to-last-end ms) of the frame in
    /// `slot` (the read buffers must be mapped); times empty / None without timestamps.
    fn read(&self, slot: u32) -> Result<QueryResults, ReplayError> {
        let mapped = |buf: &wgpu::Buffer, at: u64, len: u64| -> Result<Vec<u64>, ReplayError> {
            let view = buf
                .get_mapped_range(at..at + len)
                .map_err(|e| gpu_err("reading a query readback buffer", e))?;
            Ok(bytemuck::pod_collect_to_vec(&view))
        };
        let occ = mapped(
            &self.occ_read,
            self.occ_stride * slot as u64,
            8 * self.passes as u64,
        )?;
        let mut ms = Vec::new();
        let mut span = None;
        if let Some((_, _, read)) = &self.ts {
            let t = mapped(read, self.ts_stride * slot as u64, 16 * self.passes as u64)?;
            for p in 0..self.passes as usize {
                ms.push(t[2 * p + 1].saturating_sub(t[2 * p]) as f64 * self.period_ns as f64 / 1e6);
            }
            span = Some(
                t[2 * self.passes as usize - 1].saturating_sub(t[0]) as f64 * self.period_ns as f64
                    / 1e6,
            );
        }
        Ok((occ, ms, span))
    }
}

/// Give the resources (and uniform fields) of a pass module the names they have in the original
/// shader, matched by group and binding (fields by position: the struct is the same).
fn restore_names(iface: &mut Interface, original: &Interface) {
    for r in &mut iface.resources {
        let Some(o) = original
            .resources
            .iter()
            .find(|o| o.group == r.group && o.binding == r.binding)
        else {
            continue;
        };
        r.name = o.name.clone();
        if let (
            ResourceKind::Uniform { fields, .. },
            ResourceKind::Uniform {
                fields: ofields, ..
            },
        ) = (&mut r.kind, &o.kind)
            && fields.len() == ofields.len()
        {
            for (f, of) in fields.iter_mut().zip(ofields) {
                f.name = of.name.clone();
            }
        }
    }
}
