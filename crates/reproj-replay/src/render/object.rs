//! One object of the session on the GPU: its mesh's buffers, its cull mode and its per-frame
//! transforms. What the frame's own pass ([`super::scene`]) and the depth passes
//! ([`super::depth`]) both draw; it knows neither.

use reproj_scene::session::Cull;

/// An object's vertex and index buffers and its transform uniform, with its bind group.
pub(super) struct ObjectGpu {
    pub(super) vbuf: wgpu::Buffer,
    pub(super) ibuf: wgpu::Buffer,
    pub(super) count: u32,
    pub(super) cull: Cull,
    pub(super) xf_buf: wgpu::Buffer,
    pub(super) xf_bg: wgpu::BindGroup,
}
