//! The reference frames: on the CPU ([`Reference`], what `render_original` returns) and on the
//! GPU ([`GpuReference`], kept by [`Keeper`] as the frames are rendered, moved to another
//! renderer's device when a variant is scored there), as the error reduction reads them.

use std::borrow::Cow;

use crate::error::ReplayError;
use crate::gpu::Gpu;
use crate::readback::readback_row_bytes;
use reproj_metrics::RenderReport;

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

impl Reference {
    /// Check that these frames can be compared with a render of `frames` frames (from frame 0 of
    /// the session, the window's end) at `size`.
    pub(crate) fn covers(&self, [w, h]: [u32; 2], frames: u32) -> Result<(), ReplayError> {
        if self.width == w && self.height == h && self.frames.len() as u32 >= frames {
            return Ok(());
        }
        Err(ReplayError::ReferenceMismatch {
            reference: format!(
                "{} frames, {}×{}",
                self.frames.len(),
                self.width,
                self.height
            ),
            session: format!("{frames} frames, {w}×{h}"),
        })
    }
}

/// One reference frame on the GPU: its color (rgba32float) and its depth (r32float; 1 where
/// nothing was drawn).
#[derive(Debug, Clone)]
pub(crate) struct GpuFrame {
    pub(super) color: wgpu::TextureView,
    pub(super) depth: wgpu::TextureView,
}

/// The reference frames on the GPU of the renderer that rendered them.
#[derive(Debug, Clone, Default)]
pub(crate) struct GpuReference {
    /// [`Gpu::id`] of the owner: the textures belong to its device.
    owner: u64,
    pub(super) frames: Vec<GpuFrame>,
}

impl GpuReference {
    pub(crate) fn new(r: &Gpu) -> GpuReference {
        GpuReference {
            owner: r.id,
            frames: Vec::new(),
        }
    }

    /// The first `frames` reference frames on `r`'s device: these, or uploaded from the host
    /// copies in `reference` when another renderer (another device) rendered them.
    pub(crate) fn on<'a>(
        &'a self,
        r: &Gpu,
        reference: &Reference,
        frames: u32,
    ) -> Result<Cow<'a, GpuReference>, ReplayError> {
        if self.owner == r.id && self.frames.len() >= frames as usize {
            return Ok(Cow::Borrowed(self));
        }
        let n = frames as usize;
        if reference.frames.len() < n || reference.depth.len() < n {
            return Err(ReplayError::ReferenceMismatch {
                reference: format!(
                    "{} frames and {} depth images",
                    reference.frames.len(),
                    reference.depth.len()
                ),
                session: format!("{frames} frames"),
            });
        }
        GpuReference::upload(
            r,
            reference.width,
            reference.height,
            &reference.frames[..n],
            &reference.depth[..n],
        )
        .map(Cow::Owned)
    }

    /// Frames of `w`×`h` RGBA f32 `colors` and f32 `depths` (row-major, top row first) uploaded to
    /// `r`'s device.
    pub(crate) fn upload<C: AsRef<[f32]>, D: AsRef<[f32]>>(
        r: &Gpu,
        w: u32,
        h: u32,
        colors: &[C],
        depths: &[D],
    ) -> Result<GpuReference, ReplayError> {
        let px = w as usize * h as usize;
        let mut out = GpuReference::new(r);
        for (f, (color, depth)) in colors.iter().zip(depths).enumerate() {
            let (color, depth) = (color.as_ref(), depth.as_ref());
            if color.len() != 4 * px || depth.len() != px {
                return Err(ReplayError::ReferenceMismatch {
                    reference: format!(
                        "frame {f} with {} color and {} depth values",
                        color.len(),
                        depth.len()
                    ),
                    session: format!("{w}×{h} pixels"),
                });
            }
            let ct = frame_texture(r, "reference color", w, h, wgpu::TextureFormat::Rgba32Float);
            let dt = frame_texture(r, "reference depth", w, h, wgpu::TextureFormat::R32Float);
            for (tex, bytes, bpp) in [
                (&ct, bytemuck::cast_slice::<f32, u8>(color), 16),
                (&dt, bytemuck::cast_slice::<f32, u8>(depth), 4),
            ] {
                r.queue.write_texture(
                    tex.as_image_copy(),
                    bytes,
                    wgpu::TexelCopyBufferLayout {
                        offset: 0,
                        bytes_per_row: Some(w * bpp),
                        rows_per_image: Some(h),
                    },
                    extent(w, h),
                );
            }
            out.frames.push(GpuFrame {
                color: ct.create_view(&Default::default()),
                depth: dt.create_view(&Default::default()),
            });
        }
        Ok(out)
    }
}

fn extent(w: u32, h: u32) -> wgpu::Extent3d {
    wgpu::Extent3d {
        width: w,
        height: h,
        depth_or_array_layers: 1,
    }
}

fn frame_texture(
    r: &Gpu,
    label: &str,
    w: u32,
    h: u32,
    format: wgpu::TextureFormat,
) -> wgpu::Texture {
    r.device.create_texture(&wgpu::TextureDescriptor {
        label: Some(label),
        size: extent(w, h),
        mip_level_count: 1,
        sample_count: 1,
        dimension: wgpu::TextureDimension::D2,
        format,
        usage: wgpu::TextureUsages::TEXTURE_BINDING | wgpu::TextureUsages::COPY_DST,
        view_formats: &[],
    })
}

/// Keeps the reference frames on the GPU as `render_original` renders them.
pub(crate) struct Keeper {
    /// The frame's depth as rows of f32 padded for copies (depth cannot be copied to a color
    /// texture directly, only through a buffer).
    depth_rows: wgpu::Buffer,
    w: u32,
    h: u32,
}

impl Keeper {
    pub(crate) fn new(r: &Gpu, w: u32, h: u32) -> Keeper {
        let depth_rows = r.device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("reference depth rows"),
            size: readback_row_bytes(w, 4) as u64 * h as u64,
            usage: wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::COPY_SRC,
            mapped_at_creation: false,
        });
        Keeper { depth_rows, w, h }
    }

    /// Record copies of the frame's `color` (rgba32float) and `depth` (depth32float) into new
    /// textures appended to `keep`, and of the depth, as padded rows, into `readback` at `offset`
    /// (for the host copy).
    #[allow(clippy::too_many_arguments)]
    pub(crate) fn keep(
        &self,
        r: &Gpu,
        enc: &mut wgpu::CommandEncoder,
        color: &wgpu::Texture,
        depth: &wgpu::Texture,
        readback: &wgpu::Buffer,
        offset: u64,
        keep: &mut GpuReference,
    ) {
        let (w, h) = (self.w, self.h);
        let ct = frame_texture(r, "reference color", w, h, wgpu::TextureFormat::Rgba32Float);
        let dt = frame_texture(r, "reference depth", w, h, wgpu::TextureFormat::R32Float);
        enc.copy_texture_to_texture(color.as_image_copy(), ct.as_image_copy(), extent(w, h));
        let rows = wgpu::TexelCopyBufferLayout {
            offset: 0,
            bytes_per_row: Some(readback_row_bytes(w, 4)),
            rows_per_image: Some(h),
        };
        enc.copy_texture_to_buffer(
            wgpu::TexelCopyTextureInfo {
                texture: depth,
                mip_level: 0,
                origin: wgpu::Origin3d::ZERO,
                aspect: wgpu::TextureAspect::DepthOnly,
            },
            wgpu::TexelCopyBufferInfo {
                buffer: &self.depth_rows,
                layout: rows,
            },
            extent(w, h),
        );
        enc.copy_buffer_to_texture(
            wgpu::TexelCopyBufferInfo {
                buffer: &self.depth_rows,
                layout: rows,
            },
            dt.as_image_copy(),
            extent(w, h),
        );
        enc.copy_buffer_to_buffer(
            &self.depth_rows,
            0,
            readback,
            offset,
            Some(self.depth_rows.size()),
        );
        keep.frames.push(GpuFrame {
            color: ct.create_view(&Default::default()),
            depth: dt.create_view(&Default::default()),
        });
    }
}
