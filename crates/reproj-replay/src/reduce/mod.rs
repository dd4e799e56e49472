//! Per-frame error against the reference, reduced on the GPU.
//!
//! A variant replay used to read every frame back (16 bytes per pixel) only to compute a few sums
//! on the CPU. Here the reference frames stay on the GPU ([`GpuReference`], made by
//! `render_original` with [`Keeper`]) and a compute pass ([`Reducer`]) compares each frame of the
//! variant with its reference where it was rendered: each 8×8 block of the frame becomes one
//! [`Partial`] record (28 bytes; 1,024 for a 256×256 frame, 32,640 at 1920×1080), and only those
//! come back, into one slot per frame of a readback batch. The host sums the blocks in f64 into a
//! [`FrameError`], the same sums [`reproj_metrics::l2::compare`] makes on the CPU (which stays for
//! replays that read the pixels back anyway, to write PNGs).
//!
//! The kernel has no workgroup memory and no barrier: a thread writes its block's record. The first
//! form (16×16 threads of 4×4 pixels, then a tree over the workgroup) cost 1.05–1.2 ms per 256×256
//! frame on lavapipe, which runs barriers as coroutine switches (a third of a marble variant's own
//! passes at Δn 50); this one 0.37–0.38 ms (`docs/notebook/analysis-time.md`, "Analysis time:
//! the error reduction").
//!
//! Precision: a thread sums each row of its block in f32 (8 terms), then the rows (8), and the
//! host sums the blocks in f64; the relative error of a frame's sums is about 16 f32 roundings,
//! ~1e-6 (the per-pixel terms are all non-negative, so nothing cancels).

use std::borrow::Cow;
use std::num::NonZeroU64;
use std::sync::Mutex;

use crate::error::ReplayError;
use crate::gpu::{Gpu, gpu_err};
use crate::readback::Staging;
use reproj_metrics::l2::{self, FrameError};

mod perceptual;
mod reference;

pub(crate) use perceptual::GpuPerceptual;
use reference::GpuFrame;
pub use reference::Reference;
pub(crate) use reference::{GpuReference, Keeper};
use reproj_metrics::perceptual::PerceptualError;

/// Pixels per side of the tile one workgroup covers (8×8 threads, 8×8 pixels each: `SIDE` and
/// `BLOCK` in `reduce.wgsl`).
const TILE: u32 = 64;
/// Threads per workgroup, each writing one [`Partial`].
const THREADS: u64 = 64;

/// The reduction kernel (`reduce.wgsl`).
const SHADER: &str = include_str!("reduce.wgsl");

/// One block's sums, as the shader writes them (`struct Partial` in `reduce.wgsl`).
#[derive(Debug, Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
#[repr(C)]
struct Partial {
    l2: f32,
    sq: f32,
    covered: u32,
    max_bits: u32,
    flags: u32,
    bad: u32,
    bad_ref: u32,
}

const NAN_ANY: u32 = 1;
const NAN_COVERED: u32 = 2;

/// The compute pipeline and its bind group layout, built once per renderer ([`KernelCache`]).
#[derive(Debug, Clone)]
pub(crate) struct Kernel {
    pipeline: wgpu::ComputePipeline,
    layout: wgpu::BindGroupLayout,
}

impl Kernel {
    pub(crate) fn new(r: &Gpu) -> Result<Kernel, ReplayError> {
        let tex = |binding| wgpu::BindGroupLayoutEntry {
            binding,
            visibility: wgpu::ShaderStages::COMPUTE,
            ty: wgpu::BindingType::Texture {
                sample_type: wgpu::TextureSampleType::Float { filterable: false },
                view_dimension: wgpu::TextureViewDimension::D2,
                multisampled: false,
            },
            count: None,
        };
        r.scoped("the error reduction pipeline", || {
            let module = r.device.create_shader_module(wgpu::ShaderModuleDescriptor {
                label: Some("error reduction"),
                source: wgpu::ShaderSource::Wgsl(Cow::Borrowed(SHADER)),
            });
            let layout = r
                .device
                .create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
                    label: Some("error reduction"),
                    entries: &[
                        tex(0),
                        tex(1),
                        tex(2),
                        wgpu::BindGroupLayoutEntry {
                            binding: 3,
                            visibility: wgpu::ShaderStages::COMPUTE,
                            ty: wgpu::BindingType::Buffer {
                                ty: wgpu::BufferBindingType::Storage { read_only: false },
                                has_dynamic_offset: false,
                                min_binding_size: NonZeroU64::new(
                                    std::mem::size_of::<Partial>() as u64
                                ),
                            },
                            count: None,
                        },
                    ],
                });
            let pl = r
                .device
                .create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
                    label: Some("error reduction"),
                    bind_group_layouts: &[Some(&layout)],
                    immediate_size: 0,
                });
            let pipeline = r
                .device
                .create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
                    label: Some("error reduction"),
                    layout: Some(&pl),
                    module: &module,
                    entry_point: Some("reduce"),
                    compilation_options: Default::default(),
                    cache: None,
                });
            Kernel { pipeline, layout }
        })
    }
}

/// A compute kernel built once per device ([`Built`]).
pub(crate) trait Builds: Clone {
    fn build(r: &Gpu) -> Result<Self, ReplayError>;
}

impl Builds for Kernel {
    fn build(r: &Gpu) -> Result<Kernel, ReplayError> {
        Kernel::new(r)
    }
}

/// A kernel of one device, built on first use and kept (the renderer holds one of each).
pub(crate) struct Built<K>(Mutex<Option<K>>);

impl<K> Default for Built<K> {
    fn default() -> Self {
        Built(Mutex::new(None))
    }
}

impl<K: Builds> Built<K> {
    /// The kernel on `r`, built on first use.
    pub(crate) fn get(&self, r: &Gpu) -> Result<K, ReplayError> {
        let mut k = self.0.lock().unwrap_or_else(|e| e.into_inner());
        if let Some(k) = &*k {
            return Ok(k.clone());
        }
        let built = K::build(r)?;
        *k = Some(built.clone());
        Ok(built)
    }
}

/// The error reduction's kernel of one device.
pub(crate) type KernelCache = Built<Kernel>;
/// The perceptual metrics' kernels of one device.
pub(crate) type PerceptualCache = Built<perceptual::PerceptualKernel>;

/// Reduces each frame of a variant replay against the reference: [`Reducer::encode`] after the
/// frame's passes, [`Reducer::read`] once the batch's [`Reducer::read_buffer`] is mapped.
pub(crate) struct Reducer<'a> {
    kernel: Kernel,
    reference: Cow<'a, GpuReference>,
    /// Per slot: one [`Partial`] per block ([`THREADS`] per tile), at `slot * stride`.
    out: wgpu::Buffer,
    read: wgpu::Buffer,
    stride: u64,
    groups: [u32; 2],
    pixels: u64,
}

impl<'a> Reducer<'a> {
    /// A reducer against `reference` (`w`×`h` frames on `r`'s device), read back in batches of
    /// `slots` frames.
    pub(crate) fn new(
        r: &Gpu,
        kernel: Kernel,
        reference: Cow<'a, GpuReference>,
        w: u32,
        h: u32,
        slots: u32,
    ) -> Result<Reducer<'a>, ReplayError> {
        let groups = [w.div_ceil(TILE), h.div_ceil(TILE)];
        let bytes = slot_bytes(groups);
        let align = u64::from(r.device.limits().min_storage_buffer_offset_alignment)
            .max(wgpu::COPY_BUFFER_ALIGNMENT);
        let stride = bytes.div_ceil(align) * align;
        let buffer = |label, usage| {
            r.device.create_buffer(&wgpu::BufferDescriptor {
                label: Some(label),
                size: stride * slots.max(1) as u64,
                usage,
                mapped_at_creation: false,
            })
        };
        Ok(Reducer {
            kernel,
            reference,
            out: buffer(
                "error partials",
                wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC,
            ),
            read: buffer(
                "error partials read",
                wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
            ),
            stride,
            groups,
            pixels: w as u64 * h as u64,
        })
    }

    /// Record the reduction of `color` (the variant's frame `frame`, rgba32float, bindable)
    /// against the reference frame, into `slot`, and its copy into the read buffer.
    pub(crate) fn encode(
        &self,
        r: &Gpu,
        enc: &mut wgpu::CommandEncoder,
        color: &wgpu::TextureView,
        frame: u32,
        slot: u32,
    ) -> Result<(), ReplayError> {
        let refr = self.frame(frame)?;
        let at = slot as u64 * self.stride;
        let size = slot_bytes(self.groups);
        let group = r.device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("error reduction"),
            layout: &self.kernel.layout,
            entries: &[
                wgpu::BindGroupEntry {
                    binding: 0,
                    resource: wgpu::BindingResource::TextureView(color),
                },
                wgpu::BindGroupEntry {
                    binding: 1,
                    resource: wgpu::BindingResource::TextureView(&refr.color),
                },
                wgpu::BindGroupEntry {
                    binding: 2,
                    resource: wgpu::BindingResource::TextureView(&refr.depth),
                },
                wgpu::BindGroupEntry {
                    binding: 3,
                    resource: wgpu::BindingResource::Buffer(wgpu::BufferBinding {
                        buffer: &self.out,
                        offset: at,
                        size: NonZeroU64::new(size),
                    }),
                },
            ],
        });
        {
            let mut pass = enc.begin_compute_pass(&wgpu::ComputePassDescriptor {
                label: Some("error reduction"),
                timestamp_writes: None,
            });
            pass.set_pipeline(&self.kernel.pipeline);
            pass.set_bind_group(0, &group, &[]);
            pass.dispatch_workgroups(self.groups[0], self.groups[1], 1);
        }
        enc.copy_buffer_to_buffer(&self.out, at, &self.read, at, Some(size));
        Ok(())
    }

    /// The buffer to map with the batch's other readbacks.
    pub(crate) fn read_buffer(&self) -> &wgpu::Buffer {
        &self.read
    }

    /// Reference frame `frame` on the GPU.
    fn frame(&self, frame: u32) -> Result<&GpuFrame, ReplayError> {
        self.reference
            .frames
            .get(frame as usize)
            .ok_or_else(|| gpu_err("the error reduction", format!("no reference frame {frame}")))
    }

    /// The error sums of the frame in `slot` (the read buffer must be mapped).
    pub(crate) fn read(&self, slot: u32) -> Result<FrameError, ReplayError> {
        let at = slot as u64 * self.stride;
        let size = slot_bytes(self.groups);
        let view = self
            .read
            .get_mapped_range(at..at + size)
            .map_err(|e| gpu_err("reading the error reduction", e))?;
        let partials: Vec<Partial> = bytemuck::pod_collect_to_vec(&view);
        Ok(sum(&partials, self.pixels))
    }
}

/// Which frames of a replay come back as pixels.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum PixelsBack {
    /// None: only the GPU's sums come back (the error's, and the perceptual metrics' of the
    /// frames scored on the device).
    None,
    /// Frames `f` with `f % k == 0`, for the perceptual metrics on the CPU; the reduction still
    /// gives every frame's sums.
    Every(u32),
    /// Every frame (they are written as PNGs); the error is computed on the CPU
    /// ([`reproj_metrics::l2::compare`]) and there is no reduction.
    All,
}

impl PixelsBack {
    /// Whether frame `frame`'s pixels come back.
    fn includes(self, frame: u32) -> bool {
        match self {
            PixelsBack::None => false,
            PixelsBack::Every(k) => frame.is_multiple_of(k.max(1)),
            PixelsBack::All => true,
        }
    }
}

/// What comes back of one frame ([`FrameErrors::read`]).
pub(crate) struct FrameBack {
    /// Its error against the reference.
    pub(crate) error: FrameError,
    /// Its pixels, where it comes back whole: written as a PNG, or sampled and scored on the CPU.
    pub(crate) pixels: Option<Vec<f32>>,
    /// Its ꟻLIP and SSIM, where it is sampled and scored on the device.
    pub(crate) perceptual: Option<PerceptualError>,
}

/// How a replay gets each frame's error against the reference, the perceptual metrics of the
/// sampled frames on the device, and the pixels of the frames that come back whole.
pub(crate) struct FrameErrors<'a> {
    /// Reduced on the GPU: only the per-block sums come back. `None` with [`PixelsBack::All`].
    reducer: Option<Reducer<'a>>,
    /// ꟻLIP and SSIM of every `k`-th frame on the device.
    perceptual: Option<(u32, GpuPerceptual)>,
    /// One slot per frame of a batch for the frames whose pixels come back.
    pixels: Option<Staging>,
    back: PixelsBack,
}

/// The kernels a replay's scoring uses, each built once per renderer; no perceptual kernel
/// where the sampled frames are scored on the CPU.
pub(crate) struct Kernels<'k> {
    pub(crate) reduce: &'k KernelCache,
    pub(crate) perceptual: Option<&'k PerceptualCache>,
}

impl<'a> FrameErrors<'a> {
    /// For `frames` frames of `reference` read back in batches of `slots`: every frame back
    /// whole where `pngs` (scored on the CPU), else reduced on the GPU, with frames `f` where
    /// `f % k == 0` (`perceptual_stride` `Some(k)`) scored for ꟻLIP and SSIM on the device where
    /// `kernels` has its kernel, else brought back for the CPU.
    pub(crate) fn new(
        r: &Gpu,
        kernels: Kernels<'_>,
        reference: &'a Reference,
        frames: u32,
        slots: u32,
        (pngs, perceptual_stride): (bool, Option<u32>),
    ) -> Result<FrameErrors<'a>, ReplayError> {
        let (w, h) = (reference.width, reference.height);
        let (back, perceptual) = match (pngs, perceptual_stride, kernels.perceptual) {
            (true, _, _) => (PixelsBack::All, None),
            (false, Some(k), Some(cache)) => (
                PixelsBack::None,
                Some((k.max(1), GpuPerceptual::new(r, cache.get(r)?, w, h, slots)?)),
            ),
            (false, Some(k), None) => (PixelsBack::Every(k.max(1)), None),
            (false, None, _) => (PixelsBack::None, None),
        };
        let pixels =
            (back != PixelsBack::None).then(|| Staging::new(r, "frame readback", w, h, 16, slots));
        let reducer = if back == PixelsBack::All {
            None
        } else {
            let gpu = reference.gpu.on(r, reference, frames)?;
            Some(Reducer::new(r, kernels.reduce.get(r)?, gpu, w, h, slots)?)
        };
        Ok(FrameErrors {
            reducer,
            perceptual,
            pixels,
            back,
        })
    }

    /// The buffers to map with the batch's other readbacks.
    pub(crate) fn read_buffers(&self) -> Vec<&wgpu::Buffer> {
        let reducer = self.reducer.as_ref().map(|red| red.read_buffer());
        let perceptual = self.perceptual.as_ref().map(|(_, p)| p.read_buffer());
        let pixels = self.pixels.as_ref().map(|p| &p.buf);
        reducer
            .into_iter()
            .chain(perceptual)
            .chain(pixels)
            .collect()
    }

    /// The device's scorer, where it scores frame `frame`.
    fn scores(&self, frame: u32) -> Option<&GpuPerceptual> {
        self.perceptual
            .as_ref()
            .filter(|(k, _)| frame.is_multiple_of(*k))
            .map(|(_, p)| p)
    }

    /// Record what frame `frame` (its color target `color`, viewed as `view`) needs, into `slot`:
    /// the reduction, the perceptual metrics, the copy of its pixels, as asked.
    pub(crate) fn encode(
        &self,
        r: &Gpu,
        enc: &mut wgpu::CommandEncoder,
        color: &wgpu::Texture,
        view: &wgpu::TextureView,
        frame: u32,
        slot: u32,
    ) -> Result<(), ReplayError> {
        if let Some(red) = &self.reducer {
            red.encode(r, enc, view, frame, slot)?;
            if let Some(p) = self.scores(frame) {
                p.encode(r, enc, view, red.frame(frame)?, slot);
            }
        }
        if let Some(staging) = &self.pixels
            && self.back.includes(frame)
        {
            staging.copy(enc, color, slot);
        }
        Ok(())
    }

    /// What came back of frame `frame` in `slot` (the read buffers must be mapped).
    pub(crate) fn read(
        &self,
        slot: u32,
        reference: &Reference,
        frame: u32,
    ) -> Result<FrameBack, ReplayError> {
        let pixels: Option<Vec<f32>> = match &self.pixels {
            Some(staging) if self.back.includes(frame) => {
                Some(bytemuck::pod_collect_to_vec(&staging.image(slot)?))
            }
            _ => None,
        };
        let perceptual = self.scores(frame).map(|p| p.read(slot)).transpose()?;
        if let Some(red) = &self.reducer {
            return Ok(FrameBack {
                error: red.read(slot)?,
                pixels,
                perceptual,
            });
        }
        let f = frame as usize;
        let (Some(pixels), Some(color), Some(depth)) =
            (pixels, reference.frames.get(f), reference.depth.get(f))
        else {
            return Err(ReplayError::ReferenceMismatch {
                reference: format!("{} frames", reference.frames.len()),
                session: format!("frame {frame}"),
            });
        };
        Ok(FrameBack {
            error: l2::compare(&pixels, color, depth),
            pixels: Some(pixels),
            perceptual,
        })
    }
}

/// The bytes of one frame's [`Partial`]s: [`THREADS`] per workgroup of `groups`.
fn slot_bytes(groups: [u32; 2]) -> u64 {
    u64::from(groups[0]) * u64::from(groups[1]) * THREADS * std::mem::size_of::<Partial>() as u64
}

/// A frame's error sums from its blocks' partial sums, in f64.
fn sum(partials: &[Partial], pixels: u64) -> FrameError {
    let mut e = FrameError {
        pixels,
        ..FrameError::default()
    };
    let mut flags = 0;
    let mut max_bits = 0;
    for p in partials {
        e.sum_l2 += f64::from(p.l2);
        e.sum_sq += f64::from(p.sq);
        e.covered += u64::from(p.covered);
        max_bits = max_bits.max(p.max_bits);
        flags |= p.flags;
        e.nonfinite += u64::from(p.bad);
        e.nonfinite_reference += u64::from(p.bad_ref);
    }
    e.max_abs_diff = f64::from(f32::from_bits(max_bits));
    // As on the CPU, a non-finite color makes the sums it enters NaN.
    if flags & NAN_ANY != 0 {
        e.sum_l2 = f64::NAN;
    }
    if flags & NAN_COVERED != 0 {
        e.sum_sq = f64::NAN;
    }
    e
}

#[cfg(test)]
mod tests;

/// Noise for the kernels' tests: a small deterministic generator and frames made with it.
#[cfg(test)]
pub(crate) mod noise {
    /// xorshift, values in [0, 1).
    pub(crate) struct Rng(pub(crate) u32);

    impl Rng {
        pub(crate) fn next(&mut self) -> f32 {
            self.0 ^= self.0 << 13;
            self.0 ^= self.0 >> 17;
            self.0 ^= self.0 << 5;
            (self.0 >> 8) as f32 / (1u32 << 24) as f32
        }

        /// A reference of `px` RGBA pixels with channels in `[lo, lo + span)`, a frame off it by
        /// up to ±`jitter` / 2, and a depth leaving a third of the pixels uncovered.
        pub(crate) fn frames(
            &mut self,
            px: usize,
            lo: f32,
            span: f32,
            jitter: f32,
        ) -> (Vec<f32>, Vec<f32>, Vec<f32>) {
            let reference: Vec<f32> = (0..4 * px).map(|_| span * self.next() + lo).collect();
            let frame = reference
                .iter()
                .map(|&v| v + jitter * (self.next() - 0.5))
                .collect();
            let depth = (0..px)
                .map(|_| if self.next() < 0.33 { 1.0 } else { self.next() })
                .collect();
            (frame, reference, depth)
        }
    }
}
