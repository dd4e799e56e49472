//! The GPU device: opening the adapter, error scopes, host waits and small resource helpers.

use std::borrow::Cow;
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::{Arc, Mutex};

use crate::ReplayError;
use crate::assets::Assets;
use crate::metrics::{AdapterReport, TimingMethod};
use crate::reduce::{self};

use super::*;

/// Source of [`Renderer::id`].
pub(super) static NEXT_RENDERER_ID: AtomicU64 = AtomicU64::new(1);

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
        // Half-float shaders (`enable f16;`) where the adapter has them; `shader_module` says
        // clearly when it does not.
        features |= adapter.features() & wgpu::Features::SHADER_F16;
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

    pub(super) fn check_errors(&self, what: &str) -> Result<(), ReplayError> {
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

    pub(super) fn wait(&self) -> Result<(), ReplayError> {
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

    pub(super) fn buffer(&self, label: &str, size: u64, usage: wgpu::BufferUsages) -> wgpu::Buffer {
        self.device.create_buffer(&wgpu::BufferDescriptor {
            label: Some(label),
            size,
            usage,
            mapped_at_creation: false,
        })
    }

    pub(super) fn shader_module(
        &self,
        label: &str,
        source: &str,
    ) -> Result<wgpu::ShaderModule, ReplayError> {
        let enables_f16 = source.lines().any(|l| {
            let l = l.trim_start();
            l.starts_with("enable") && l.contains("f16")
        });
        if enables_f16 && !self.device.features().contains(wgpu::Features::SHADER_F16) {
            return Err(ReplayError::Unsupported {
                what: format!(
                    "{label} computes in half floats (`enable f16;`), which {} does not support (wgpu feature SHADER_F16); rewrite it in f32 or run on an adapter that has it",
                    self.adapter_info.name
                ),
            });
        }
        self.scoped(&format!("shader module {label}"), || {
            self.device
                .create_shader_module(wgpu::ShaderModuleDescriptor {
                    label: Some(label),
                    source: wgpu::ShaderSource::Wgsl(Cow::Borrowed(source)),
                })
        })
    }
}
