//! What the shader samples: textures (generated, files, cube maps, arrays, glTF materials),
//! samplers, and the depth passes that render depth textures.

use std::path::PathBuf;

use schemars::JsonSchema;
use serde::{Deserialize, Serialize};

use super::{GltfTexture, UniformValue};

/// A texture bound to a shader variable: generated (`kind`), read from an image file (`file`,
/// or `faces` for a cube map) or, for a `texture_2d_array`, a list of `layers`, each a texture of
/// its own (generated or a file, all of one size). Exactly one of `kind`, `file`, `faces`,
/// `layers`, `gltf`.
#[derive(Debug, Clone, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct TextureSpec {
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub kind: Option<TextureKind>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub file: Option<PathBuf>,
    /// Six images +X, −X, +Y, −Y, +Z, −Z for a `texture_cube`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub faces: Option<Vec<PathBuf>>,
    /// The layers of a `texture_2d_array`, in order; each is a 2D texture spec (no `layers` of
    /// its own) and all must come out the same size. Their `mipmaps` are ignored: this spec's
    /// apply to the array.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub layers: Option<Vec<TextureSpec>>,
    /// A texture of a glTF file's material (a 2D texture).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub gltf: Option<GltfTexture>,
    /// Edge length in texels of a generated texture (square; a cube face; a 3D texture's edge).
    /// Default 256.
    #[serde(default = "default_tex_size")]
    pub size: u32,
    #[serde(default)]
    pub params: TextureParams,
    /// Texel format: `rgba8unorm` (default for everything but environments),
    /// `rgba8unorm-srgb` (values are decoded from sRGB when sampled) or `rgba16float`
    /// (default for `environment`, which is HDR).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub format: Option<TexFormat>,
    /// Build a full mip chain (box filter). Default true.
    #[serde(default = "default_true")]
    pub mipmaps: bool,
}

fn default_tex_size() -> u32 {
    256
}
fn default_true() -> bool {
    true
}

/// Generated texture kinds.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, JsonSchema)]
#[serde(rename_all = "snake_case")]
pub enum TextureKind {
    /// Tileable fractal value noise v in [0, 1], as `mix(color_low, color_high, v)` (default grey
    /// r = g = b = v, alpha 1).
    Noise,
    /// Tangent-space normal map from a tileable noise height field, encoded `n * 0.5 + 0.5`.
    NormalMap,
    /// Sky / ground environment with a sun: a cube map for `texture_cube`, an equirectangular
    /// (longitude × latitude) map for `texture_2d`.
    Environment,
    /// Two-color checkerboard.
    Checker,
    /// One color.
    Solid,
}

/// Texel formats a session can ask for.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, JsonSchema)]
#[serde(rename_all = "kebab-case")]
pub enum TexFormat {
    Rgba8unorm,
    Rgba8unormSrgb,
    Rgba16float,
}

/// Parameters of generated textures; each kind reads the ones it needs.
#[derive(Debug, Clone, Serialize, Deserialize, JsonSchema)]
#[serde(default, deny_unknown_fields)]
pub struct TextureParams {
    /// Random seed (noise, normal_map, environment clouds). Default 1.
    pub seed: u32,
    /// Noise base frequency in cells per texture edge (noise, normal_map). Default 8.
    pub scale: f32,
    /// Octaves of fractal noise. Default 4.
    pub octaves: u32,
    /// Normal map bump strength (slope multiplier). Default 1.
    pub strength: f32,
    /// Solid color (linear RGBA). Default `[1, 1, 1, 1]`.
    pub color: [f32; 4],
    /// Noise: colors at noise value 0 and 1 (linear RGBA). Defaults black and white.
    pub color_low: [f32; 4],
    pub color_high: [f32; 4],
    /// Checker colors. Defaults white and grey 0.2.
    pub color_a: [f32; 4],
    pub color_b: [f32; 4],
    /// Checker squares per texture edge. Default 8.
    pub squares: u32,
    /// Environment: direction towards the sun (normalized internally). Default `[0.5, 0.6, 0.3]`.
    pub sun_direction: [f32; 3],
    /// Environment: sun radiance added over the sky (HDR). Default 20.
    pub sun_intensity: f32,
    /// Environment colors (linear RGB): zenith, horizon and ground.
    pub sky_color: [f32; 3],
    pub horizon_color: [f32; 3],
    pub ground_color: [f32; 3],
}

impl Default for TextureParams {
    fn default() -> Self {
        TextureParams {
            seed: 1,
            scale: 8.0,
            octaves: 4,
            strength: 1.0,
            color: [1.0; 4],
            color_low: [0.0, 0.0, 0.0, 1.0],
            color_high: [1.0; 4],
            color_a: [1.0; 4],
            color_b: [0.2, 0.2, 0.2, 1.0],
            squares: 8,
            sun_direction: [0.5, 0.6, 0.3],
            sun_intensity: 20.0,
            sky_color: [0.25, 0.45, 0.85],
            horizon_color: [0.8, 0.85, 0.9],
            ground_color: [0.25, 0.22, 0.2],
        }
    }
}

/// A sampler by shader variable name.
#[derive(Debug, Clone, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct SamplerSpec {
    /// Magnification and minification filter. Default linear.
    #[serde(default)]
    pub filter: Filter,
    /// Filter between mip levels. Default linear.
    #[serde(default)]
    pub mipmap_filter: Filter,
    /// Address mode on all axes. Default repeat.
    #[serde(default)]
    pub address: Address,
    /// Maximum anisotropy (1 = off; needs all filters linear). Default 1.
    #[serde(default = "default_aniso")]
    pub anisotropy: u16,
    /// The comparison of a `sampler_comparison` (default `less_equal`); an error on a plain
    /// sampler.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub compare: Option<Compare>,
}

impl Default for SamplerSpec {
    fn default() -> Self {
        SamplerSpec {
            filter: Filter::Linear,
            mipmap_filter: Filter::Linear,
            address: Address::Repeat,
            anisotropy: 1,
            compare: None,
        }
    }
}

fn default_aniso() -> u16 {
    1
}

#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize, Deserialize, JsonSchema)]
#[serde(rename_all = "lowercase")]
pub enum Filter {
    #[default]
    Linear,
    Nearest,
}

#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize, Deserialize, JsonSchema)]
#[serde(rename_all = "lowercase")]
pub enum Address {
    #[default]
    Repeat,
    Clamp,
    Mirror,
}

/// A depth-only pass that renders every object of the scene into a depth texture
/// (`depth32float`, cleared to 1, compare `less`, each object's face culling).
#[derive(Debug, Clone, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct DepthPass {
    /// Texture size in texels, `[width, height]`. Default: the session's resolution.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub size: Option<[u32; 2]>,
    /// The view-projection the objects are drawn with.
    pub view_proj: ViewProj,
}

/// The view-projection of a [`DepthPass`]: `"camera"` (the session camera's, a depth
/// pre-pass), `{"uniform": "light_view_proj"}` (the value of a uniform field the session gives,
/// so the pass and the shader agree by construction) or `{"matrix": [16 numbers, column-major]}`
/// (constant or `{"keys": ...}`).
#[derive(Debug, Clone, Serialize, Deserialize, JsonSchema)]
#[serde(rename_all = "snake_case", deny_unknown_fields)]
pub enum ViewProj {
    Camera,
    Uniform(String),
    Matrix(UniformValue),
}

/// Comparison function of a comparison sampler: the test is `reference OP texel`.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize, Deserialize, JsonSchema)]
#[serde(rename_all = "snake_case")]
pub enum Compare {
    Never,
    Less,
    Equal,
    #[default]
    LessEqual,
    Greater,
    NotEqual,
    GreaterEqual,
    Always,
}
