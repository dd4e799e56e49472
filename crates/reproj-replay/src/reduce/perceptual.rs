//! The perceptual metrics of a frame against its reference, computed on the GPU: ꟻLIP and SSIM
//! per pixel, summed over the covered pixels (`perceptual.wgsl`), so a scored frame sends back a
//! few numbers instead of its pixels (33 MB at 1920×1080, read back and scored on one core for
//! about a second by NVIDIA's reference code).
//!
//! The definitions are [`reproj_metrics::perceptual`]'s (LDR ꟻLIP at the default viewing
//! conditions, SSIM on the luma of the 8-bit sRGB image, both over the covered pixels), and the
//! results agree with it to f32 rounding (`perceptual_tests.rs` checks both on noise, edges and
//! flat images). The filters' weights and the 8-bit sRGB decoding are computed here in f32, as
//! the reference code computes them. The CPU path stays for the replays that read every frame
//! back anyway (`render --frames`: it also writes the ꟻLIP maps).
//!
//! Memory: seven scratch images of 16 bytes per pixel (about 230 MB at 1920×1080), shared by
//! the frames of a replay (each frame's three dispatches run in order on the queue).

use std::borrow::Cow;
use std::num::NonZeroU64;

use reproj_metrics::perceptual::{PIXELS_PER_DEGREE, PerceptualError, SSIM_SIGMA, SSIM_WINDOW};

use crate::error::ReplayError;
use crate::gpu::{Gpu, gpu_err};

use super::reference::{GpuFrame, GpuReference};

/// The kernels (`perceptual.wgsl`).
const SHADER: &str = include_str!("perceptual.wgsl");
/// Pixels per side of the tile one workgroup of `down` sums (8×8 threads of 8×8 pixels).
const TILE: u32 = 64;
/// Threads per workgroup of `down`, each writing one [`Partial`].
const THREADS: u64 = 64;
/// Scratch images (`seen_*`, `colour_*`, `feature_*`, `window`).
const SCRATCH: usize = 7;
/// Weights the params hold (`Params::weights`).
const WEIGHTS: usize = 64;

/// One thread's sums, as `down` writes them (`struct Partial` in `perceptual.wgsl`).
#[derive(Debug, Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
#[repr(C)]
struct Partial {
    flip: f32,
    covered: u32,
    ssim: f32,
    windows: u32,
}

/// `struct Params` in `perceptual.wgsl`.
#[derive(Debug, Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
#[repr(C)]
struct Params {
    dims: [u32; 4],
    remap: [f32; 4],
    weights: [[f32; 4]; WEIGHTS],
    decode: [[f32; 4]; 64],
}

/// What a binding of the kernels is.
#[derive(Clone, Copy)]
enum Slot {
    Uniform,
    Texture,
    Storage,
}

/// The three pipelines and their bind group layouts, built once per renderer
/// ([`PerceptualCache`]).
#[derive(Debug, Clone)]
pub(crate) struct PerceptualKernel {
    /// `prepare`, `across`, `down`, each with the layout of the bindings it uses.
    stages: [(wgpu::ComputePipeline, wgpu::BindGroupLayout); 3],
}

/// Each entry point's bindings (`perceptual.wgsl`'s numbers).
const BINDINGS: [(&str, &[(u32, Slot)]); 3] = [
    (
        "prepare",
        &[
            (0, Slot::Uniform),
            (1, Slot::Texture),
            (2, Slot::Texture),
            (4, Slot::Storage),
            (5, Slot::Storage),
        ],
    ),
    (
        "across",
        &[
            (0, Slot::Uniform),
            (4, Slot::Storage),
            (5, Slot::Storage),
            (6, Slot::Storage),
            (7, Slot::Storage),
            (8, Slot::Storage),
            (9, Slot::Storage),
            (10, Slot::Storage),
        ],
    ),
    (
        "down",
        &[
            (0, Slot::Uniform),
            (3, Slot::Texture),
            (6, Slot::Storage),
            (7, Slot::Storage),
            (8, Slot::Storage),
            (9, Slot::Storage),
            (10, Slot::Storage),
            (11, Slot::Storage),
        ],
    ),
];

impl PerceptualKernel {
    pub(crate) fn new(r: &Gpu) -> Result<PerceptualKernel, ReplayError> {
        r.scoped("the perceptual metrics' pipelines", || {
            let module = r.device.create_shader_module(wgpu::ShaderModuleDescriptor {
                label: Some("perceptual metrics"),
                source: wgpu::ShaderSource::Wgsl(Cow::Borrowed(SHADER)),
            });
            BINDINGS.map(|(entry, bindings)| {
                let entries: Vec<wgpu::BindGroupLayoutEntry> = bindings
                    .iter()
                    .map(|&(binding, slot)| wgpu::BindGroupLayoutEntry {
                        binding,
                        visibility: wgpu::ShaderStages::COMPUTE,
                        ty: match slot {
                            Slot::Uniform => wgpu::BindingType::Buffer {
                                ty: wgpu::BufferBindingType::Uniform,
                                has_dynamic_offset: false,
                                min_binding_size: NonZeroU64::new(
                                    std::mem::size_of::<Params>() as u64
                                ),
                            },
                            Slot::Texture => wgpu::BindingType::Texture {
                                sample_type: wgpu::TextureSampleType::Float { filterable: false },
                                view_dimension: wgpu::TextureViewDimension::D2,
                                multisampled: false,
                            },
                            Slot::Storage => wgpu::BindingType::Buffer {
                                ty: wgpu::BufferBindingType::Storage { read_only: false },
                                has_dynamic_offset: false,
                                min_binding_size: None,
                            },
                        },
                        count: None,
                    })
                    .collect();
                let layout = r
                    .device
                    .create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
                        label: Some(entry),
                        entries: &entries,
                    });
                let pl = r
                    .device
                    .create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
                        label: Some(entry),
                        bind_group_layouts: &[Some(&layout)],
                        immediate_size: 0,
                    });
                let pipeline = r
                    .device
                    .create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
                        label: Some(entry),
                        layout: Some(&pl),
                        module: &module,
                        entry_point: Some(entry),
                        compilation_options: Default::default(),
                        cache: None,
                    });
                (pipeline, layout)
            })
        })
        .map(|stages| PerceptualKernel { stages })
    }
}

impl super::Builds for PerceptualKernel {
    fn build(r: &Gpu) -> Result<PerceptualKernel, ReplayError> {
        PerceptualKernel::new(r)
    }
}

/// Scores frames of one size against their reference frames on the GPU: [`GpuPerceptual::encode`]
/// after a frame is drawn, [`GpuPerceptual::read`] once the batch's read buffer is mapped.
pub(crate) struct GpuPerceptual {
    kernel: PerceptualKernel,
    params: wgpu::Buffer,
    scratch: Vec<wgpu::Buffer>,
    /// Per slot: one [`Partial`] per thread of `down`, at `slot * stride`.
    out: wgpu::Buffer,
    read: wgpu::Buffer,
    stride: u64,
    size: [u32; 2],
}

impl GpuPerceptual {
    /// For `w`×`h` frames on `r`'s device, read back in batches of `slots` frames.
    pub(crate) fn new(
        r: &Gpu,
        kernel: PerceptualKernel,
        w: u32,
        h: u32,
        slots: u32,
    ) -> Result<GpuPerceptual, ReplayError> {
        let params = params(w, h)?;
        let image = u64::from(w) * u64::from(h) * 16;
        let limit = r.device.limits().max_storage_buffer_binding_size;
        if image > limit {
            return Err(ReplayError::Unsupported {
                what: format!(
                    "scoring {w}×{h} frames on {} needs storage buffers of {image} bytes (the device allows {limit})",
                    r.adapter_info.name
                ),
            });
        }
        let buffer = |label, size, usage| {
            r.device.create_buffer(&wgpu::BufferDescriptor {
                label: Some(label),
                size,
                usage,
                mapped_at_creation: false,
            })
        };
        let uniform = buffer(
            "perceptual params",
            std::mem::size_of::<Params>() as u64,
            wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
        );
        r.queue
            .write_buffer(&uniform, 0, bytemuck::bytes_of(&params));
        let scratch = (0..SCRATCH)
            .map(|_| buffer("perceptual scratch", image, wgpu::BufferUsages::STORAGE))
            .collect();
        let align = u64::from(r.device.limits().min_storage_buffer_offset_alignment)
            .max(wgpu::COPY_BUFFER_ALIGNMENT);
        let bytes = slot_bytes([w, h]);
        let stride = bytes.div_ceil(align) * align;
        let out = buffer(
            "perceptual partials",
            stride * u64::from(slots.max(1)),
            wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC,
        );
        let read = buffer(
            "perceptual partials read",
            stride * u64::from(slots.max(1)),
            wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
        );
        Ok(GpuPerceptual {
            kernel,
            params: uniform,
            scratch,
            out,
            read,
            stride,
            size: [w, h],
        })
    }

    /// Record the scoring of `color` (a frame, rgba32float, bindable) against `reference`, into
    /// `slot`, and its copy into the read buffer.
    pub(crate) fn encode(
        &self,
        r: &Gpu,
        enc: &mut wgpu::CommandEncoder,
        color: &wgpu::TextureView,
        reference: &GpuFrame,
        slot: u32,
    ) {
        let at = u64::from(slot) * self.stride;
        let size = slot_bytes(self.size);
        let resource = |binding: u32| -> wgpu::BindingResource<'_> {
            match binding {
                0 => self.params.as_entire_binding(),
                1 => wgpu::BindingResource::TextureView(color),
                2 => wgpu::BindingResource::TextureView(&reference.color),
                3 => wgpu::BindingResource::TextureView(&reference.depth),
                11 => wgpu::BindingResource::Buffer(wgpu::BufferBinding {
                    buffer: &self.out,
                    offset: at,
                    size: NonZeroU64::new(size),
                }),
                s => self.scratch[s as usize - 4].as_entire_binding(),
            }
        };
        let [w, h] = self.size;
        let per_pixel = [w.div_ceil(8), h.div_ceil(8)];
        let per_block = [w.div_ceil(TILE), h.div_ceil(TILE)];
        let mut pass = enc.begin_compute_pass(&wgpu::ComputePassDescriptor {
            label: Some("perceptual metrics"),
            timestamp_writes: None,
        });
        for ((pipeline, layout), ((entry, bindings), groups)) in self
            .kernel
            .stages
            .iter()
            .zip(BINDINGS.iter().zip([per_pixel, per_pixel, per_block]))
        {
            let entries: Vec<wgpu::BindGroupEntry<'_>> = bindings
                .iter()
                .map(|&(binding, _)| wgpu::BindGroupEntry {
                    binding,
                    resource: resource(binding),
                })
                .collect();
            let group = r.device.create_bind_group(&wgpu::BindGroupDescriptor {
                label: Some(entry),
                layout,
                entries: &entries,
            });
            pass.set_pipeline(pipeline);
            pass.set_bind_group(0, &group, &[]);
            pass.dispatch_workgroups(groups[0], groups[1], 1);
        }
        drop(pass);
        enc.copy_buffer_to_buffer(&self.out, at, &self.read, at, Some(size));
    }

    /// The metrics of `frame` against `reference` (linear RGBA f32 on the host) over the pixels
    /// where `depth` < 1: both uploaded, scored through slot 0, read back with one wait.
    pub(crate) fn score(
        &self,
        r: &Gpu,
        frame: &[f32],
        reference: &[f32],
        depth: &[f32],
    ) -> Result<PerceptualError, ReplayError> {
        let [w, h] = self.size;
        let refr = GpuReference::upload(r, w, h, &[reference], &[depth])?;
        let test = GpuReference::upload(r, w, h, &[frame], &[depth])?;
        let mut enc = r.device.create_command_encoder(&Default::default());
        self.encode(r, &mut enc, &test.frames[0].color, &refr.frames[0], 0);
        r.queue.submit([enc.finish()]);
        r.map_read(&[self.read_buffer()])?;
        let scored = self.read(0);
        Gpu::unmap_all(&[self.read_buffer()]);
        scored
    }

    /// The buffer to map with the batch's other readbacks.
    pub(crate) fn read_buffer(&self) -> &wgpu::Buffer {
        &self.read
    }

    /// The metrics of the frame scored into `slot` (the read buffer must be mapped): the means
    /// over the covered pixels, ꟻLIP 0 and SSIM 1 where there are none.
    pub(crate) fn read(&self, slot: u32) -> Result<PerceptualError, ReplayError> {
        let at = u64::from(slot) * self.stride;
        let view = self
            .read
            .get_mapped_range(at..at + slot_bytes(self.size))
            .map_err(|e| gpu_err("reading the perceptual metrics", e))?;
        let partials: Vec<Partial> = bytemuck::pod_collect_to_vec(&view);
        let (mut flip, mut ssim, mut covered, mut windows) = (0.0, 0.0, 0u64, 0u64);
        for p in &partials {
            flip += f64::from(p.flip);
            ssim += f64::from(p.ssim);
            covered += u64::from(p.covered);
            windows += u64::from(p.windows);
        }
        Ok(PerceptualError {
            flip: if covered > 0 {
                flip / covered as f64
            } else {
                0.0
            },
            ssim: if windows > 0 {
                ssim / windows as f64
            } else {
                1.0
            },
        })
    }
}

/// The bytes of one frame's [`Partial`]s.
fn slot_bytes([w, h]: [u32; 2]) -> u64 {
    u64::from(w.div_ceil(TILE))
        * u64::from(h.div_ceil(TILE))
        * THREADS
        * std::mem::size_of::<Partial>() as u64
}

/// The kernels' parameters for `w`×`h` frames: ꟻLIP's filters at the default viewing conditions
/// and SSIM's window, the colour remapping's constants and the 8-bit sRGB decoding table.
fn params(w: u32, h: u32) -> Result<Params, ReplayError> {
    let ppd = PIXELS_PER_DEGREE;
    let colour = colour_filter(ppd);
    let feature = feature_filter(ppd);
    let window = ssim_window();
    if colour.len() + feature.len() + window.len() > WEIGHTS {
        return Err(gpu_err(
            "the perceptual metrics",
            format!(
                "filters of {} + {} + {} taps do not fit {WEIGHTS}",
                colour.len(),
                feature.len(),
                window.len()
            ),
        ));
    }
    let mut weights = [[0.0f32; 4]; WEIGHTS];
    for (slot, w) in weights
        .iter_mut()
        .zip(colour.iter().chain(&feature).chain(&window))
    {
        *slot = *w;
    }
    let mut decode = [[0.0f32; 4]; 64];
    for i in 0..256 {
        decode[i / 4][i % 4] = srgb_to_linear(i as f32 / 255.0);
    }
    let cmax = max_colour_distance();
    Ok(Params {
        dims: [w, h, (colour.len() / 2) as u32, (feature.len() / 2) as u32],
        remap: [cmax, 0.4 * cmax, 0.0, 0.0],
        weights,
        decode,
    })
}

/// ꟻLIP's colour filters as one row of taps: (Y, Cx, Cz's first Gaussian, Cz's second), the
/// first two each normalized to 1, the Cz pair together (its two separable halves).
fn colour_filter(ppd: f32) -> Vec<[f32; 4]> {
    use std::f32::consts::PI;
    let (a1, b1) = ([1.0f32, 1.0, 34.1], [0.0047f32, 0.0053, 0.04]);
    let (a2, b2) = ([0.0f32, 0.0, 13.5], [1.0e-5f32, 1.0e-5, 0.025]);
    let b_max = b1.iter().chain(&b2).fold(0.0f32, |m, &b| m.max(b));
    let radius = (3.0 * (b_max / (2.0 * PI * PI)).sqrt() * ppd).ceil() as i32;
    let gauss = |x2: f32, a: f32, b: f32| a * (PI / b).sqrt() * (-PI * PI * x2 / b).exp();
    let gauss_sqrt =
        |x2: f32, a: f32, b: f32| (a * (PI / b).sqrt()).sqrt() * (-PI * PI * x2 / b).exp();
    let taps: Vec<[f32; 4]> = (-radius..=radius)
        .map(|i| {
            let x = i as f32 / ppd;
            let x2 = x * x;
            [
                gauss(x2, a1[0], b1[0]),
                gauss(x2, a1[1], b1[1]),
                gauss_sqrt(x2, a1[2], b1[2]),
                gauss_sqrt(x2, a2[2], b2[2]),
            ]
        })
        .collect();
    let sum = |c: usize| taps.iter().map(|t| t[c]).sum::<f32>();
    let (y, cx) = (sum(0), sum(1));
    let cz = (sum(2) * sum(2) + sum(3) * sum(3)).sqrt();
    taps.iter()
        .map(|t| [t[0] / y, t[1] / cx, t[2] / cz, t[3] / cz])
        .collect()
}

/// ꟻLIP's feature filters as one row of taps: (Gaussian, its first derivative, its second, 0),
/// the Gaussian normalized to 1, the derivatives' positive and negative weights each to ±1.
fn feature_filter(ppd: f32) -> Vec<[f32; 4]> {
    let sd = 0.5 * 0.082 * ppd;
    let radius = (3.0 * sd).ceil() as i32;
    let taps: Vec<[f32; 3]> = (-radius..=radius)
        .map(|i| {
            let x = i as f32;
            let g = (-(x * x) / (2.0 * sd * sd)).exp();
            [g, -x * g, (x * x / (sd * sd) - 1.0) * g]
        })
        .collect();
    let g_sum: f32 = taps.iter().map(|t| t[0]).sum();
    let signed = |c: usize, positive: bool| -> f32 {
        taps.iter()
            .map(|t| t[c])
            .filter(|&v| (v > 0.0) == positive)
            .map(f32::abs)
            .sum()
    };
    let (d_pos, d_neg) = (signed(1, true), signed(1, false));
    let (dd_pos, dd_neg) = (signed(2, true), signed(2, false));
    taps.iter()
        .map(|t| {
            [
                t[0] / g_sum,
                t[1] / if t[1] > 0.0 { d_pos } else { d_neg },
                t[2] / if t[2] > 0.0 { dd_pos } else { dd_neg },
                0.0,
            ]
        })
        .collect()
}

/// SSIM's window as one row of taps (in x; the 2-D window is its outer product).
fn ssim_window() -> Vec<[f32; 4]> {
    let r = (SSIM_WINDOW / 2) as f64;
    let g: Vec<f64> = (0..SSIM_WINDOW)
        .map(|i| {
            let x = i as f64 - r;
            (-x * x / (2.0 * SSIM_SIGMA * SSIM_SIGMA)).exp()
        })
        .collect();
    let sum: f64 = g.iter().sum();
    g.iter()
        .map(|v| [(v / sum) as f32, 0.0, 0.0, 0.0])
        .collect()
}

/// An 8-bit sRGB value (in [0, 1]) as linear light.
fn srgb_to_linear(c: f32) -> f32 {
    if c <= 0.04045 {
        c / 12.92
    } else {
        ((c + 0.055) / 1.055).powf(2.4)
    }
}

/// ꟻLIP's largest colour difference (between pure green and pure blue), raised to q_c = 0.7.
fn max_colour_distance() -> f32 {
    let lab = |rgb: [f32; 3]| -> [f32; 3] {
        let m = [
            [
                10135552.0 / 24577794.0,
                8788810.0 / 24577794.0,
                4435075.0 / 24577794.0,
            ],
            [
                2613072.0 / 12288897.0,
                8788810.0 / 12288897.0,
                887015.0 / 12288897.0,
            ],
            [
                1425312.0 / 73733382.0,
                8788810.0 / 73733382.0,
                70074185.0 / 73733382.0,
            ],
        ];
        let inv_white = [1.052_156_9f32, 1.0, 0.918_357_7];
        let delta = 6.0f32 / 29.0;
        let f: Vec<f32> = (0..3)
            .map(|i| {
                let t = (m[i][0] * rgb[0] + m[i][1] * rgb[1] + m[i][2] * rgb[2]) * inv_white[i];
                if t > delta * delta * delta {
                    t.powf(1.0 / 3.0)
                } else {
                    (1.0 / (3.0 * delta * delta)) * t + 4.0 / 29.0
                }
            })
            .collect();
        let l = 116.0 * f[1] - 16.0;
        let (a, b) = (500.0 * (f[0] - f[1]), 200.0 * (f[1] - f[2]));
        [l, 0.01 * l * a, 0.01 * l * b]
    };
    let (g, b) = (lab([0.0, 1.0, 0.0]), lab([0.0, 0.0, 1.0]));
    let hyab = (g[0] - b[0]).abs() + ((g[1] - b[1]).powi(2) + (g[2] - b[2]).powi(2)).sqrt();
    hyab.powf(0.7)
}

#[cfg(test)]
#[path = "perceptual_tests.rs"]
mod tests;
