//! One object of the scene on the GPU: its mesh's buffers, its cull mode and its per-frame
//! transforms ([`TransformUniform`], one bind group of one uniform at binding 0), and how it is
//! drawn. The frame's own passes and the depth passes draw the same objects, each pass with its
//! own transforms.

use std::num::NonZeroU64;

use reproj_scene::session::Cull;
use reproj_scene::vertex::TransformUniform;

use crate::upload::MeshBuffers;

/// The layout of a per-object transforms group: [`TransformUniform`] at binding 0, read by the
/// vertex stage.
pub fn transform_layout(device: &wgpu::Device, label: &str) -> wgpu::BindGroupLayout {
    device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
        label: Some(label),
        entries: &[wgpu::BindGroupLayoutEntry {
            binding: 0,
            visibility: wgpu::ShaderStages::VERTEX,
            ty: wgpu::BindingType::Buffer {
                ty: wgpu::BufferBindingType::Uniform,
                has_dynamic_offset: false,
                min_binding_size: NonZeroU64::new(size_of::<TransformUniform>() as u64),
            },
            count: None,
        }],
    })
}

/// One object's transforms for one pass: the uniform buffer and its bind group.
#[derive(Debug)]
pub struct Transforms {
    pub buffer: wgpu::Buffer,
    pub group: wgpu::BindGroup,
}

impl Transforms {
    /// A transform buffer and its group of `layout` ([`transform_layout`]).
    pub fn new(device: &wgpu::Device, layout: &wgpu::BindGroupLayout, label: &str) -> Transforms {
        let buffer = buffer(
            device,
            label,
            size_of::<TransformUniform>() as u64,
            wgpu::BufferUsages::UNIFORM,
        );
        let group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some(label),
            layout,
            entries: &[wgpu::BindGroupEntry {
                binding: 0,
                resource: buffer.as_entire_binding(),
            }],
        });
        Transforms { buffer, group }
    }

    /// Write this frame's transforms.
    pub fn write(&self, queue: &wgpu::Queue, u: &TransformUniform) {
        queue.write_buffer(&self.buffer, 0, bytemuck::bytes_of(u));
    }
}

/// A buffer of `usage` the CPU writes (`COPY_DST` added), of `size` bytes but at least 16 (a
/// uniform's smallest binding).
pub fn buffer(
    device: &wgpu::Device,
    label: &str,
    size: u64,
    usage: wgpu::BufferUsages,
) -> wgpu::Buffer {
    device.create_buffer(&wgpu::BufferDescriptor {
        label: Some(label),
        size: size.max(16),
        usage: usage | wgpu::BufferUsages::COPY_DST,
        mapped_at_creation: false,
    })
}

/// An object of the session: its mesh, its cull mode and its transforms in the frame's passes.
#[derive(Debug)]
pub struct SceneObject {
    pub mesh: MeshBuffers,
    pub cull: Cull,
    pub transforms: Transforms,
}

impl SceneObject {
    /// Draw the object in `pass` (its pipeline set) with its own transforms at `group`.
    pub fn draw(&self, pass: &mut wgpu::RenderPass<'_>, group: u32) {
        self.draw_with(pass, group, &self.transforms);
    }

    /// Draw the object with `transforms` (another pass's) at `group`.
    pub fn draw_with(&self, pass: &mut wgpu::RenderPass<'_>, group: u32, transforms: &Transforms) {
        pass.set_bind_group(group, &transforms.group, &[]);
        pass.set_vertex_buffer(0, self.mesh.vertices.slice(..));
        pass.set_index_buffer(self.mesh.indices.slice(..), wgpu::IndexFormat::Uint32);
        pass.draw_indexed(0..self.mesh.count, 0, 0..1);
    }
}
