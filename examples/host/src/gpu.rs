//! The device, frame readback and frame timing: plain wgpu, nothing reproj-specific.

use std::sync::{Arc, Mutex};

use anyhow::{Context, anyhow, bail};

/// Instance, adapter facts, device and queue.
pub struct Gpu {
    _instance: wgpu::Instance,
    pub device: wgpu::Device,
    pub queue: wgpu::Queue,
    /// Adapter name and backend, for the summary.
    pub adapter: String,
    pub backend: String,
    /// Frame times come from GPU timestamp queries (else CPU submit + wait).
    pub timestamps: bool,
    period_ns: f32,
    /// wgpu validation errors reported outside an error scope.
    errors: Arc<Mutex<Vec<String>>>,
}

impl std::fmt::Debug for Gpu {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Gpu")
            .field("adapter", &self.adapter)
            .field("timestamps", &self.timestamps)
            .finish()
    }
}

impl Gpu {
    /// Open the first Vulkan adapter (`WGPU_BACKEND` may pick another backend) with the device
    /// features in `required` (the manifest's `required_features`), plus timestamp queries when
    /// the adapter has them and `cpu_timing` is off. A required feature the adapter lacks is an
    /// error naming it.
    pub fn new(required: wgpu::Features, cpu_timing: bool) -> anyhow::Result<Gpu> {
        let mut desc = wgpu::InstanceDescriptor::new_without_display_handle().with_env();
        desc.backends = wgpu::Backends::VULKAN.with_env();
        let instance = wgpu::Instance::new(desc);
        let adapter = pollster::block_on(
            instance.request_adapter(&wgpu::RequestAdapterOptions::default()),
        )
        .map_err(|e| {
            anyhow!(
                "no GPU adapter ({e}); without a GPU install Mesa's lavapipe (mesa-vulkan-drivers)"
            )
        })?;
        let info = adapter.get_info();
        let missing = required - adapter.features();
        if !missing.is_empty() {
            let names: Vec<&str> = missing.iter().filter_map(|f| f.as_str()).collect();
            bail!(
                "the variant needs the device feature(s) {} which {} does not have (a 16-bit cache format or nearest reconstruction needs none: reproj instance --cache-format f16 / --reconstruct nearest)",
                names.join(", "),
                info.name
            );
        }
        let timestamps =
            !cpu_timing && adapter.features().contains(wgpu::Features::TIMESTAMP_QUERY);
        let mut features = required;
        if timestamps {
            features |= wgpu::Features::TIMESTAMP_QUERY;
        }
        let (device, queue) = pollster::block_on(adapter.request_device(&wgpu::DeviceDescriptor {
            label: Some("reproj-host"),
            required_features: features,
            required_limits: adapter.limits(),
            ..Default::default()
        }))
        .with_context(|| format!("opening the device on {}", info.name))?;
        let errors: Arc<Mutex<Vec<String>>> = Arc::default();
        let sink = errors.clone();
        device.on_uncaptured_error(Arc::new(move |e: wgpu::Error| {
            if let Ok(mut v) = sink.lock() {
                v.push(e.to_string());
            }
        }));
        let period_ns = queue.get_timestamp_period();
        Ok(Gpu {
            _instance: instance,
            device,
            queue,
            adapter: info.name.clone(),
            backend: format!("{:?}", info.backend),
            timestamps,
            period_ns,
            errors,
        })
    }

    /// Fail with wgpu's validation messages, if any arrived since the last check.
    pub fn check(&self, what: &str) -> anyhow::Result<()> {
        let mut v = self
            .errors
            .lock()
            .map_err(|_| anyhow!("error sink poisoned"))?;
        if v.is_empty() {
            return Ok(());
        }
        let msg = v.join("\n");
        v.clear();
        bail!("{what}: {msg}")
    }

    /// Block until the queue is idle.
    pub fn wait(&self) -> anyhow::Result<()> {
        self.device
            .poll(wgpu::PollType::wait_indefinitely())
            .context("waiting for the GPU")?;
        Ok(())
    }

    /// Map `buf` for reading and return a copy of its contents.
    pub fn read_buffer(&self, buf: &wgpu::Buffer) -> anyhow::Result<Vec<u8>> {
        let status: Arc<Mutex<Option<Result<(), wgpu::BufferAsyncError>>>> = Arc::default();
        let s2 = status.clone();
        buf.slice(..).map_async(wgpu::MapMode::Read, move |r| {
            if let Ok(mut g) = s2.lock() {
                *g = Some(r);
            }
        });
        self.wait()?;
        match status.lock().map(|mut g| g.take()) {
            Ok(Some(Ok(()))) => {}
            Ok(Some(Err(e))) => bail!("mapping a readback buffer: {e}"),
            _ => bail!("mapping a readback buffer did not complete"),
        }
        let bytes = buf
            .get_mapped_range(..)
            .map_err(|e| anyhow!("reading a readback buffer: {e}"))?
            .to_vec();
        buf.unmap();
        Ok(bytes)
    }

    /// The texels of an `rgba32float` texture, row-major, top row first.
    pub fn read_rgba32f(&self, tex: &wgpu::Texture) -> anyhow::Result<Vec<f32>> {
        let (w, h) = (tex.width(), tex.height());
        let align = wgpu::COPY_BYTES_PER_ROW_ALIGNMENT;
        let tight = w * 16;
        let row = tight.div_ceil(align) * align;
        let buf = self.device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("frame readback"),
            size: u64::from(row) * u64::from(h),
            usage: wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::MAP_READ,
            mapped_at_creation: false,
        });
        let mut enc = self.device.create_command_encoder(&Default::default());
        enc.copy_texture_to_buffer(
            tex.as_image_copy(),
            wgpu::TexelCopyBufferInfo {
                buffer: &buf,
                layout: wgpu::TexelCopyBufferLayout {
                    offset: 0,
                    bytes_per_row: Some(row),
                    rows_per_image: Some(h),
                },
            },
            tex.size(),
        );
        self.queue.submit([enc.finish()]);
        let bytes = self.read_buffer(&buf)?;
        let mut out = Vec::with_capacity((w * h * 4) as usize);
        for y in 0..h as usize {
            let r = &bytes[y * row as usize..y * row as usize + tight as usize];
            out.extend(bytemuck::pod_collect_to_vec::<u8, f32>(r));
        }
        Ok(out)
    }
}

/// Timestamp queries around each render pass of a frame: render pass `i` writes queries `2i`
/// (begin) and `2i + 1` (end). A variant's passes that share their targets share a render pass
/// (`reproj_runtime::Variant::render_passes`).
pub struct Timer {
    set: Option<(wgpu::QuerySet, wgpu::Buffer, wgpu::Buffer)>,
    passes: u32,
    period_ns: f32,
}

/// One frame's GPU times in milliseconds.
#[derive(Debug, Clone, Default)]
pub struct FrameTimes {
    /// Per render pass, begin to end.
    pub pass_ms: Vec<f64>,
    /// First pass's begin to last pass's end.
    pub span_ms: Option<f64>,
}

impl Timer {
    /// Queries for up to `passes` timed passes a frame (none without timestamp queries).
    pub fn new(gpu: &Gpu, passes: u32) -> Timer {
        let set = gpu.timestamps.then(|| {
            let qs = gpu.device.create_query_set(&wgpu::QuerySetDescriptor {
                label: Some("pass timestamps"),
                ty: wgpu::QueryType::Timestamp,
                count: 2 * passes,
            });
            let buf = |label, usage| {
                gpu.device.create_buffer(&wgpu::BufferDescriptor {
                    label: Some(label),
                    size: 16 * u64::from(passes),
                    usage,
                    mapped_at_creation: false,
                })
            };
            let resolve = buf(
                "timestamp resolve",
                wgpu::BufferUsages::QUERY_RESOLVE | wgpu::BufferUsages::COPY_SRC,
            );
            let read = buf(
                "timestamp read",
                wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::MAP_READ,
            );
            (qs, resolve, read)
        });
        Timer {
            set,
            passes,
            period_ns: gpu.period_ns,
        }
    }

    /// The timestamp writes of pass `i` of the frame.
    pub fn writes(&self, i: u32) -> Option<wgpu::RenderPassTimestampWrites<'_>> {
        self.set
            .as_ref()
            .filter(|_| i < self.passes)
            .map(|(qs, _, _)| wgpu::RenderPassTimestampWrites {
                query_set: qs,
                beginning_of_pass_write_index: Some(2 * i),
                end_of_pass_write_index: Some(2 * i + 1),
            })
    }

    /// The query set, for a frame recorded by reproj-runtime (which writes the same indices).
    pub fn query_set(&self) -> Option<&wgpu::QuerySet> {
        self.set.as_ref().map(|(qs, _, _)| qs)
    }

    /// Record resolving the frame's queries (after its last pass).
    pub fn resolve(&self, enc: &mut wgpu::CommandEncoder) {
        if let Some((qs, resolve, read)) = &self.set {
            enc.resolve_query_set(qs, 0..2 * self.passes, resolve, 0);
            enc.copy_buffer_to_buffer(resolve, 0, read, 0, None);
        }
    }

    /// The frame's times (after its submission completed).
    pub fn read(&self, gpu: &Gpu) -> anyhow::Result<FrameTimes> {
        let Some((_, _, read)) = &self.set else {
            return Ok(FrameTimes::default());
        };
        let t: Vec<u64> = bytemuck::pod_collect_to_vec(&gpu.read_buffer(read)?);
        let ms = |a: u64, b: u64| b.saturating_sub(a) as f64 * f64::from(self.period_ns) / 1e6;
        let n = self.passes as usize;
        Ok(FrameTimes {
            pass_ms: (0..n).map(|p| ms(t[2 * p], t[2 * p + 1])).collect(),
            span_ms: Some(ms(t[0], t[2 * n - 1])),
        })
    }
}
