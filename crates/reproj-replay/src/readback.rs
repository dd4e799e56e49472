//! Batched readback: the staging buffer of frame images, the query buffers, frame submission
//! (the renderer's module docs say why frames come back in batches). On a [`Gpu`]; used by the
//! reduction and the frame loops above it.

use std::time::Instant;

use crate::error::ReplayError;
use crate::gpu::{Gpu, gpu_err};

/// Most frames whose readbacks share one host wait (see the module docs).
pub(crate) const MAX_BATCH: u32 = 16;

/// Host-visible staging memory one batch may use for frame images.
pub(crate) const BATCH_BYTES: u64 = 64 << 20;

pub(crate) fn readback_row_bytes(width: u32, bpp: u32) -> u32 {
    let a = wgpu::COPY_BYTES_PER_ROW_ALIGNMENT;
    (width * bpp).div_ceil(a) * a
}

/// A host-readable buffer of `slots` padded w×h images of `bpp` bytes per texel: each frame of a
/// readback batch copies its image into its own slot.
pub(crate) struct Staging {
    pub(crate) buf: wgpu::Buffer,
    pub(crate) slot_bytes: u64,
    pub(crate) w: u32,
    pub(crate) h: u32,
    pub(crate) bpp: u32,
}

impl Staging {
    pub(crate) fn new(r: &Gpu, label: &str, w: u32, h: u32, bpp: u32, slots: u32) -> Staging {
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
    pub(crate) fn slot_bytes(w: u32, h: u32, bpp: u32) -> u64 {
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
        Ok(Gpu::unpad(&view, self.w, self.h, self.bpp))
    }
}

/// Occlusion and timestamp query sets for `passes` passes, with resolve and readback buffers of
/// `slots` frames: the query sets are reused every frame, and each frame of a readback batch
/// resolves its results into its own slot.
pub(crate) struct QueryKit {
    /// Occlusion queries: one per pass.
    pub(crate) passes: u32,
    /// Timestamp pairs: one per render pass (several passes may share one).
    pub(crate) render_passes: u32,
    pub(crate) occlusion: wgpu::QuerySet,
    pub(crate) occ_resolve: wgpu::Buffer,
    pub(crate) occ_read: wgpu::Buffer,
    /// Bytes between the slots of the occlusion buffers (resolve offsets are 256-aligned).
    pub(crate) occ_stride: u64,
    pub(crate) ts: Option<(wgpu::QuerySet, wgpu::Buffer, wgpu::Buffer)>,
    /// Bytes between the slots of the timestamp buffers.
    pub(crate) ts_stride: u64,
    pub(crate) period_ns: f32,
}

impl QueryKit {
    /// Queries for `passes` passes drawn in `render_passes` render passes, `slots` frames in
    /// flight.
    pub(crate) fn new(r: &Gpu, passes: u32, render_passes: u32, slots: u32) -> QueryKit {
        let align = |n: u64| {
            n.div_ceil(wgpu::QUERY_RESOLVE_BUFFER_ALIGNMENT) * wgpu::QUERY_RESOLVE_BUFFER_ALIGNMENT
        };
        let occ_stride = align(8 * passes as u64);
        let ts_stride = align(16 * render_passes as u64);
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
                count: 2 * render_passes,
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
            render_passes,
            occlusion,
            occ_resolve,
            occ_read,
            occ_stride,
            ts,
            ts_stride,
            period_ns: r.timestamp_period,
        }
    }

    /// The timestamps of render pass `render_pass`: its beginning and its end.
    pub(crate) fn writes(&self, render_pass: u32) -> Option<wgpu::RenderPassTimestampWrites<'_>> {
        self.ts
            .as_ref()
            .map(|(qs, _, _)| wgpu::RenderPassTimestampWrites {
                query_set: qs,
                beginning_of_pass_write_index: Some(2 * render_pass),
                end_of_pass_write_index: Some(2 * render_pass + 1),
            })
    }

    /// The timestamp query set (render pass `r` writes `2r` and `2r + 1`), where the adapter has
    /// timestamps.
    pub(crate) fn timestamps(&self) -> Option<&wgpu::QuerySet> {
        self.ts.as_ref().map(|(qs, _, _)| qs)
    }

    /// Record resolving this frame's queries into `slot` of the readback buffers.
    pub(crate) fn resolve(&self, enc: &mut wgpu::CommandEncoder, slot: u32) {
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
            enc.resolve_query_set(qs, 0..2 * self.render_passes, res, at);
            enc.copy_buffer_to_buffer(res, at, read, at, Some(16 * self.render_passes as u64));
        }
    }

    /// The readback buffers, to map once per batch.
    pub(crate) fn read_buffers(&self) -> Vec<&wgpu::Buffer> {
        let mut v = vec![&self.occ_read];
        if let Some((_, _, read)) = &self.ts {
            v.push(read);
        }
        v
    }

    /// (occlusion counts per pass, ms per render pass, first-begin-to-last-end ms) of the frame
    /// in `slot` (the read buffers must be mapped); times empty / None without timestamps.
    pub(crate) fn read(&self, slot: u32) -> Result<QueryResults, ReplayError> {
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
            let n = self.render_passes as usize;
            let t = mapped(read, self.ts_stride * slot as u64, 16 * n as u64)?;
            for p in 0..n {
                ms.push(t[2 * p + 1].saturating_sub(t[2 * p]) as f64 * self.period_ns as f64 / 1e6);
            }
            span = Some(t[2 * n - 1].saturating_sub(t[0]) as f64 * self.period_ns as f64 / 1e6);
        }
        Ok((occ, ms, span))
    }
}

/// Occlusion counts, per-pass ms, frame span ms of one frame's queries.
pub(crate) type QueryResults = (Vec<u64>, Vec<f64>, Option<f64>);

impl Gpu {
    /// Frames per readback batch: up to [`MAX_BATCH`] and [`BATCH_BYTES`] of staging for images
    /// of `slot_bytes`; 1 without timestamp queries, where the frame time is the CPU wait.
    pub(crate) fn batch_len(&self, frames: u32, slot_bytes: u64) -> u32 {
        if !self.timestamps {
            return 1;
        }
        let budget = BATCH_BYTES.min(self.device.limits().max_buffer_size);
        let by_mem = (budget / slot_bytes.max(1)).max(1);
        by_mem.min(MAX_BATCH as u64).min(frames.max(1) as u64) as u32
    }

    /// Submit a frame's render and readback commands. With timestamp queries both go in one
    /// submission and nothing waits (None: the batch's wall time is amortized later). Without, the
    /// render submission is waited for and timed alone (that is the frame time) before the readback
    /// is submitted.
    pub(crate) fn submit_frame(
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

    pub(crate) fn unpad(data: &[u8], w: u32, h: u32, bpp: u32) -> Vec<u8> {
        let row = readback_row_bytes(w, bpp) as usize;
        let tight = (w * bpp) as usize;
        let mut out = Vec::with_capacity(tight * h as usize);
        for y in 0..h as usize {
            out.extend_from_slice(&data[y * row..y * row + tight]);
        }
        out
    }
}

/// The frame loops' batching, shared by the reference and the variant loop: each frame is
/// submitted into the next slot, and the batch is read back with one host wait when its slots are
/// full or the last frame is in (see the module docs of `render`).
pub(crate) struct FrameBatch<'a> {
    /// `""` or `"variant "`: goes into messages.
    what: &'a str,
    slots: u32,
    frames: u32,
    /// Frames submitted but not read back yet: (frame, CPU time when measured alone).
    pending: Vec<(u32, Option<f64>)>,
    /// When the batch's first frame was submitted.
    t0: Instant,
}

impl<'a> FrameBatch<'a> {
    pub(crate) fn new(what: &'a str, slots: u32, frames: u32) -> FrameBatch<'a> {
        FrameBatch {
            what,
            slots,
            frames,
            pending: Vec::new(),
            t0: Instant::now(),
        }
    }

    /// The slot the next frame's images and queries go in.
    pub(crate) fn slot(&self) -> u32 {
        self.pending.len() as u32
    }

    /// Submit frame `f` ([`Gpu::submit_frame`]); true when the batch must now be read back.
    pub(crate) fn submit(
        &mut self,
        r: &Gpu,
        render: wgpu::CommandEncoder,
        readback: wgpu::CommandEncoder,
        f: u32,
    ) -> Result<bool, ReplayError> {
        if self.pending.is_empty() {
            self.t0 = Instant::now();
        }
        let cpu = r.submit_frame(
            render,
            readback,
            &format!("rendering {}frame {f}", self.what),
        )?;
        self.pending.push((f, cpu));
        Ok(self.pending.len() >= self.slots as usize || f + 1 >= self.frames)
    }

    /// Map `bufs` with one wait, call `each(slot, frame, cpu_ms)` for the batch's frames in order
    /// (`cpu_ms`: the frame's own CPU time, else the batch's wall time per frame), unmap, and start
    /// a new batch.
    pub(crate) fn read_back(
        &mut self,
        r: &Gpu,
        bufs: &[&wgpu::Buffer],
        mut each: impl FnMut(u32, u32, f64) -> Result<(), ReplayError>,
    ) -> Result<(), ReplayError> {
        r.map_read(bufs)?;
        let batch_ms = self.t0.elapsed().as_secs_f64() * 1e3 / self.pending.len() as f64;
        let first = self.pending[0].0;
        let last = self.pending[self.pending.len() - 1].0;
        let what = self.what;
        r.check_errors(&format!("rendering {what}frames {first}..={last}"))?;
        for (slot, &(f, cpu)) in self.pending.iter().enumerate() {
            each(slot as u32, f, cpu.unwrap_or(batch_ms))?;
        }
        Gpu::unmap_all(bufs);
        r.check_errors(&format!("reading {what}frames {first}..={last}"))?;
        self.pending.clear();
        Ok(())
    }
}
