//! Meshes and textures built by `reproj-scene`, uploaded.

use reproj_scene::mesh::MeshData;
use reproj_scene::reflect::TexDim;
use reproj_scene::session::TexFormat;
use reproj_scene::textures::TextureData;

/// A mesh's vertex and index buffers (`u32` indices) and its index count.
#[derive(Debug, Clone)]
pub struct MeshBuffers {
    pub vertices: wgpu::Buffer,
    pub indices: wgpu::Buffer,
    pub count: u32,
}

/// Upload `data`'s vertices ([`reproj_scene::mesh::Vertex`]) and indices.
pub fn mesh_buffers(device: &wgpu::Device, data: &MeshData) -> MeshBuffers {
    let init = |label, contents: &[u8], usage| {
        wgpu::util::DeviceExt::create_buffer_init(
            device,
            &wgpu::util::BufferInitDescriptor {
                label: Some(label),
                contents,
                usage,
            },
        )
    };
    MeshBuffers {
        vertices: init(
            "vertices",
            bytemuck::cast_slice(&data.vertices),
            wgpu::BufferUsages::VERTEX,
        ),
        indices: init(
            "indices",
            bytemuck::cast_slice(&data.indices),
            wgpu::BufferUsages::INDEX,
        ),
        count: data.indices.len() as u32,
    }
}

/// The texture format of a session texture's texels.
pub fn texture_format(format: TexFormat) -> wgpu::TextureFormat {
    match format {
        TexFormat::Rgba8unorm => wgpu::TextureFormat::Rgba8Unorm,
        TexFormat::Rgba8unormSrgb => wgpu::TextureFormat::Rgba8UnormSrgb,
        TexFormat::Rgba16float => wgpu::TextureFormat::Rgba16Float,
    }
}

/// The view dimension of a shader's texture variable.
pub fn view_dimension(dim: TexDim) -> wgpu::TextureViewDimension {
    match dim {
        TexDim::D2 => wgpu::TextureViewDimension::D2,
        TexDim::D2Array => wgpu::TextureViewDimension::D2Array,
        TexDim::D3 => wgpu::TextureViewDimension::D3,
        TexDim::Cube => wgpu::TextureViewDimension::Cube,
    }
}

/// Upload texture `name`'s texels with their mip levels, viewed as a shader variable of
/// dimensionality `dim` takes it (layers of an array or a cube's faces; a 3D texture's slices).
pub fn texture(
    device: &wgpu::Device,
    queue: &wgpu::Queue,
    name: &str,
    data: &TextureData,
    dim: TexDim,
) -> wgpu::TextureView {
    let tex = device.create_texture(&wgpu::TextureDescriptor {
        label: Some(name),
        size: wgpu::Extent3d {
            width: data.width,
            height: data.height,
            depth_or_array_layers: data.layers,
        },
        mip_level_count: data.levels.len() as u32,
        sample_count: 1,
        dimension: if dim == TexDim::D3 {
            wgpu::TextureDimension::D3
        } else {
            wgpu::TextureDimension::D2
        },
        format: texture_format(data.format),
        usage: wgpu::TextureUsages::TEXTURE_BINDING | wgpu::TextureUsages::COPY_DST,
        view_formats: &[],
    });
    for level in 0..data.levels.len() {
        let (w, h, l) = data.level_size(level);
        queue.write_texture(
            wgpu::TexelCopyTextureInfo {
                texture: &tex,
                mip_level: level as u32,
                origin: wgpu::Origin3d::ZERO,
                aspect: wgpu::TextureAspect::All,
            },
            &data.encode_level(level),
            wgpu::TexelCopyBufferLayout {
                offset: 0,
                bytes_per_row: Some(w * data.bytes_per_texel()),
                rows_per_image: Some(h),
            },
            wgpu::Extent3d {
                width: w,
                height: h,
                depth_or_array_layers: l,
            },
        );
    }
    tex.create_view(&wgpu::TextureViewDescriptor {
        dimension: Some(view_dimension(dim)),
        ..Default::default()
    })
}
