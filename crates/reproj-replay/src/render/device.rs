//! The renderer's own state beside its [`Gpu`]: what is kept across replays (assets, the
//! reduction kernel, pipelines) and what it reports (adapter, timing method).

use std::sync::Mutex;
use std::sync::atomic::{AtomicU64, Ordering};

use crate::assets::Assets;
use crate::error::ReplayError;
use crate::gpu::Gpu;
use crate::reduce::{KernelCache, Kernels, PerceptualCache};
use reproj_metrics::{AdapterReport, TimingMethod};

use super::*;

impl Renderer {
    /// Open the default adapter of the chosen backends (Vulkan unless `opts.backend` or
    /// `WGPU_BACKEND` says otherwise) and create a device with timestamp queries when available.
    pub fn new(opts: &RendererOptions) -> Result<Renderer, ReplayError> {
        let gpu = Gpu::open(opts.backend.as_deref(), opts.cpu_timing)?;
        let cpu_rasterizer = gpu.adapter_info.is_cpu_rasterizer();
        Ok(Renderer {
            gpu,
            assets: Assets::default(),
            reduce_kernel: KernelCache::default(),
            perceptual_kernel: PerceptualCache::default(),
            perceptual_on_device: match opts.perceptual_on {
                PerceptualOn::Auto => !cpu_rasterizer,
                PerceptualOn::Device => true,
                PerceptualOn::Cpu => false,
            },
            pipelines: Mutex::default(),
            variants: Mutex::default(),
            pipeline_hits: AtomicU64::new(0),
        })
    }

    /// The scoring kernels, built on first use and kept.
    pub(crate) fn kernels(&self) -> Kernels<'_> {
        Kernels {
            reduce: &self.reduce_kernel,
            perceptual: self.perceptual_on_device.then_some(&self.perceptual_kernel),
        }
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
}

impl std::ops::Deref for Renderer {
    type Target = Gpu;

    fn deref(&self) -> &Gpu {
        &self.gpu
    }
}
