//! The manifest's WebGPU names as wgpu values. Every function fails with a message naming the
//! value it does not know (the caller adds the file and field), so a manifest from a newer reproj
//! is refused clearly.

use std::num::NonZeroU64;
use std::str::FromStr;

use crate::manifest::LayoutEntry;

/// A WebGPU texture format name (uncompressed formats).
pub(crate) fn texture_format(name: &str) -> Result<wgpu::TextureFormat, String> {
    use wgpu::TextureFormat as F;
    Ok(match name {
        "r8unorm" => F::R8Unorm,
        "r8snorm" => F::R8Snorm,
        "r8uint" => F::R8Uint,
        "r8sint" => F::R8Sint,
        "r16uint" => F::R16Uint,
        "r16sint" => F::R16Sint,
        "r16float" => F::R16Float,
        "rg8unorm" => F::Rg8Unorm,
        "rg8snorm" => F::Rg8Snorm,
        "rg8uint" => F::Rg8Uint,
        "rg8sint" => F::Rg8Sint,
        "r32uint" => F::R32Uint,
        "r32sint" => F::R32Sint,
        "r32float" => F::R32Float,
        "rg16uint" => F::Rg16Uint,
        "rg16sint" => F::Rg16Sint,
        "rg16float" => F::Rg16Float,
        "rgba8unorm" => F::Rgba8Unorm,
        "rgba8unorm-srgb" => F::Rgba8UnormSrgb,
        "rgba8snorm" => F::Rgba8Snorm,
        "rgba8uint" => F::Rgba8Uint,
        "rgba8sint" => F::Rgba8Sint,
        "bgra8unorm" => F::Bgra8Unorm,
        "bgra8unorm-srgb" => F::Bgra8UnormSrgb,
        "rgb10a2uint" => F::Rgb10a2Uint,
        "rgb10a2unorm" => F::Rgb10a2Unorm,
        "rg11b10ufloat" => F::Rg11b10Ufloat,
        "rg32uint" => F::Rg32Uint,
        "rg32sint" => F::Rg32Sint,
        "rg32float" => F::Rg32Float,
        "rgba16uint" => F::Rgba16Uint,
        "rgba16sint" => F::Rgba16Sint,
        "rgba16float" => F::Rgba16Float,
        "rgba32uint" => F::Rgba32Uint,
        "rgba32sint" => F::Rgba32Sint,
        "rgba32float" => F::Rgba32Float,
        "depth16unorm" => F::Depth16Unorm,
        "depth24plus" => F::Depth24Plus,
        "depth24plus-stencil8" => F::Depth24PlusStencil8,
        "depth32float" => F::Depth32Float,
        "depth32float-stencil8" => F::Depth32FloatStencil8,
        other => return Err(format!("unknown texture format `{other}`")),
    })
}

/// Texture usages (the schema writes them in snake case).
pub(crate) fn texture_usages(names: &[String]) -> Result<wgpu::TextureUsages, String> {
    let mut u = wgpu::TextureUsages::empty();
    for n in names {
        u |= match n.as_str() {
            "render_attachment" => wgpu::TextureUsages::RENDER_ATTACHMENT,
            "texture_binding" => wgpu::TextureUsages::TEXTURE_BINDING,
            "storage_binding" => wgpu::TextureUsages::STORAGE_BINDING,
            "copy_src" => wgpu::TextureUsages::COPY_SRC,
            "copy_dst" => wgpu::TextureUsages::COPY_DST,
            other => return Err(format!("unknown texture usage `{other}`")),
        };
    }
    Ok(u)
}

/// WebGPU feature names (`float32-filterable`, ...).
pub(crate) fn features(names: &[String]) -> Result<wgpu::Features, String> {
    let mut f = wgpu::Features::empty();
    for n in names {
        f |= wgpu::Features::from_str(n).map_err(|()| format!("unknown device feature `{n}`"))?;
    }
    Ok(f)
}

pub(crate) fn compare(name: &str) -> Result<wgpu::CompareFunction, String> {
    use wgpu::CompareFunction as C;
    Ok(match name {
        "never" => C::Never,
        "less" => C::Less,
        "equal" => C::Equal,
        "less-equal" => C::LessEqual,
        "greater" => C::Greater,
        "not-equal" => C::NotEqual,
        "greater-equal" => C::GreaterEqual,
        "always" => C::Always,
        other => return Err(format!("unknown compare function `{other}`")),
    })
}

pub(crate) fn filter(name: &str) -> Result<wgpu::FilterMode, String> {
    Ok(match name {
        "nearest" => wgpu::FilterMode::Nearest,
        "linear" => wgpu::FilterMode::Linear,
        other => return Err(format!("unknown filter `{other}`")),
    })
}

pub(crate) fn mipmap_filter(name: &str) -> Result<wgpu::MipmapFilterMode, String> {
    Ok(match name {
        "nearest" => wgpu::MipmapFilterMode::Nearest,
        "linear" => wgpu::MipmapFilterMode::Linear,
        other => return Err(format!("unknown mipmap filter `{other}`")),
    })
}

pub(crate) fn address_mode(name: &str) -> Result<wgpu::AddressMode, String> {
    Ok(match name {
        "clamp-to-edge" => wgpu::AddressMode::ClampToEdge,
        "repeat" => wgpu::AddressMode::Repeat,
        "mirror-repeat" => wgpu::AddressMode::MirrorRepeat,
        other => return Err(format!("unknown address mode `{other}`")),
    })
}

pub(crate) fn view_dimension(name: &str) -> Result<wgpu::TextureViewDimension, String> {
    use wgpu::TextureViewDimension as D;
    Ok(match name {
        "1d" => D::D1,
        "2d" => D::D2,
        "2d-array" => D::D2Array,
        "cube" => D::Cube,
        "cube-array" => D::CubeArray,
        "3d" => D::D3,
        other => return Err(format!("unknown view dimension `{other}`")),
    })
}

/// A bind group layout entry's binding type.
pub(crate) fn binding_type(entry: &LayoutEntry) -> Result<wgpu::BindingType, String> {
    Ok(match entry {
        LayoutEntry::Buffer {
            buffer_type,
            min_binding_size,
        } => wgpu::BindingType::Buffer {
            ty: match buffer_type.as_str() {
                "uniform" => wgpu::BufferBindingType::Uniform,
                "storage" => wgpu::BufferBindingType::Storage { read_only: false },
                "read-only-storage" => wgpu::BufferBindingType::Storage { read_only: true },
                other => return Err(format!("unknown buffer binding type `{other}`")),
            },
            has_dynamic_offset: false,
            min_binding_size: NonZeroU64::new(*min_binding_size),
        },
        LayoutEntry::Texture {
            sample_type,
            view_dimension: dim,
            multisampled,
        } => wgpu::BindingType::Texture {
            sample_type: match sample_type.as_str() {
                "float" => wgpu::TextureSampleType::Float { filterable: true },
                "unfilterable-float" => wgpu::TextureSampleType::Float { filterable: false },
                "depth" => wgpu::TextureSampleType::Depth,
                "sint" => wgpu::TextureSampleType::Sint,
                "uint" => wgpu::TextureSampleType::Uint,
                other => return Err(format!("unknown texture sample type `{other}`")),
            },
            view_dimension: view_dimension(dim)?,
            multisampled: *multisampled,
        },
        LayoutEntry::Sampler { sampler_type } => {
            wgpu::BindingType::Sampler(match sampler_type.as_str() {
                "filtering" => wgpu::SamplerBindingType::Filtering,
                "non-filtering" => wgpu::SamplerBindingType::NonFiltering,
                "comparison" => wgpu::SamplerBindingType::Comparison,
                other => return Err(format!("unknown sampler binding type `{other}`")),
            })
        }
        LayoutEntry::StorageTexture {
            format,
            access,
            view_dimension: dim,
        } => wgpu::BindingType::StorageTexture {
            access: match access.as_str() {
                "read-only" => wgpu::StorageTextureAccess::ReadOnly,
                "write-only" => wgpu::StorageTextureAccess::WriteOnly,
                "read-write" => wgpu::StorageTextureAccess::ReadWrite,
                other => return Err(format!("unknown storage texture access `{other}`")),
            },
            format: texture_format(format).map_err(|e| format!("storage texture: {e}"))?,
            view_dimension: view_dimension(dim)?,
        },
    })
}
