//! The GPU every module of the replay works on ([`Gpu`]): opening the adapter and device, error
//! scopes, host waits and small resource helpers, and the conversions to wgpu values the asset
//! cache and the renderer share. Below the readback, the assets, the reduction and the renderer,
//! which all take a `&Gpu` (the [`crate::Renderer`] derefs to its own).

use std::borrow::Cow;
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::{Arc, Mutex};

use reproj_metrics::AdapterReport;

use crate::error::ReplayError;

/// Source of [`Gpu::id`].
static NEXT_GPU_ID: AtomicU64 = AtomicU64::new(1);

/// The instance, adapter, device and queue, and what the adapter supports.
pub struct Gpu {
    _instance: wgpu::Instance,
    pub(crate) adapter_info: AdapterReport,
    pub(crate) device: wgpu::Device,
    pub(crate) queue: wgpu::Queue,
    pub(crate) timestamps: bool,
    pub(crate) timestamp_period: f32,
    errors: Arc<Mutex<Vec<String>>>,
    /// Unique per device in the process: tells whose device a reference's textures are on.
    pub(crate) id: u64,
}

impl std::fmt::Debug for Gpu {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Gpu")
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

impl Gpu {
    /// Open the default adapter of the chosen backends (`backend`, as `--backend`; else
    /// `WGPU_BACKEND`; else Vulkan) and create a device with timestamp queries when available
    /// and not `cpu_timing`.
    pub(crate) fn open(backend: Option<&str>, cpu_timing: bool) -> Result<Gpu, ReplayError> {
        let backends = match backend {
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
        let want_ts = !cpu_timing && adapter.features().contains(wgpu::Features::TIMESTAMP_QUERY);
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
        Ok(Gpu {
            _instance: instance,
            adapter_info,
            device,
            queue,
            timestamps: want_ts,
            timestamp_period,
            errors,
            id: NEXT_GPU_ID.fetch_add(1, Ordering::Relaxed),
        })
    }

    pub(crate) fn check_errors(&self, what: &str) -> Result<(), ReplayError> {
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

    pub(crate) fn wait(&self) -> Result<(), ReplayError> {
        self.device
            .poll(wgpu::PollType::wait_indefinitely())
            .map_err(|e| gpu_err("waiting for the GPU", e))?;
        Ok(())
    }

    /// Map every buffer in `bufs` for reading with a single host wait. The caller reads them with
    /// `get_mapped_range` and unmaps them with [`Gpu::unmap_all`].
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

    pub(crate) fn buffer(&self, label: &str, size: u64, usage: wgpu::BufferUsages) -> wgpu::Buffer {
        self.device.create_buffer(&wgpu::BufferDescriptor {
            label: Some(label),
            size,
            usage,
            mapped_at_creation: false,
        })
    }

    pub(crate) fn shader_module(
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
