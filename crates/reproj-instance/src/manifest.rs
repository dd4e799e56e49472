//! The variant manifest: everything a host engine needs to run a cached variant without reading our
//! code. Serialized as `manifest.json`, schema `reproj.manifest` version [`MANIFEST_VERSION`].

use serde::{Deserialize, Serialize};

/// Version of the manifest schema. Bump on any incompatible change.
/// Version 2: `strategy`, `reconstruct`, per-pass `colors` (several targets, by location) instead
/// of one `color`, narrow cache formats.
pub const MANIFEST_VERSION: u32 = 2;

/// Cache payload texel format (WebGPU names).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, Default)]
#[serde(rename_all = "lowercase")]
pub enum CacheFormat {
    /// Exact: 32-bit float per channel (default for 3- and 4-float payloads).
    #[default]
    Rgba32float,
    /// Two exact floats.
    Rg32float,
    /// One exact float.
    R32float,
    /// The paper's 16 bits per channel.
    Rgba16float,
    Rg16float,
    R16float,
}

impl CacheFormat {
    /// The narrowest format of the given precision that holds `components` floats (there is no
    /// renderable three-channel format, so 3 takes 4).
    pub fn narrowest(components: u32, half: bool) -> CacheFormat {
        match (components, half) {
            (1, false) => CacheFormat::R32float,
            (2, false) => CacheFormat::Rg32float,
            (_, false) => CacheFormat::Rgba32float,
            (1, true) => CacheFormat::R16float,
            (2, true) => CacheFormat::Rg16float,
            (_, true) => CacheFormat::Rgba16float,
        }
    }

    /// Floats per texel.
    pub fn channels(self) -> u32 {
        match self {
            CacheFormat::R32float | CacheFormat::R16float => 1,
            CacheFormat::Rg32float | CacheFormat::Rg16float => 2,
            CacheFormat::Rgba32float | CacheFormat::Rgba16float => 4,
        }
    }

    /// 16-bit floats (filterable everywhere; 32-bit floats need `float32-filterable`).
    pub fn is_half(self) -> bool {
        matches!(
            self,
            CacheFormat::R16float | CacheFormat::Rg16float | CacheFormat::Rgba16float
        )
    }

    /// The WebGPU format name.
    pub fn name(self) -> &'static str {
        match self {
            CacheFormat::Rgba32float => "rgba32float",
            CacheFormat::Rg32float => "rg32float",
            CacheFormat::R32float => "r32float",
            CacheFormat::Rgba16float => "rgba16float",
            CacheFormat::Rg16float => "rg16float",
            CacheFormat::R16float => "r16float",
        }
    }
}

/// How a variant's passes are laid out (`docs/PASSES.md`).
#[derive(
    Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize, Deserialize, Default,
)]
pub enum Strategy {
    /// The paper's three passes: reproject, recompute (through the depth test), shade. One color
    /// target per pass, no branch.
    #[default]
    #[serde(rename = "3pass")]
    ThreePass,
    /// Two passes: reproject and shade the hits (discarding misses), then the whole shader where
    /// pass 1 left the pixel open (through the depth test). Two color targets, no branch.
    #[serde(rename = "2pass")]
    TwoPass,
    /// One pass: reproject; on a miss or refresh compute the node inline (a branch); shade; write
    /// color and cache (two color targets).
    #[serde(rename = "fused")]
    Fused,
}

impl Strategy {
    pub const ALL: [Strategy; 3] = [Strategy::ThreePass, Strategy::TwoPass, Strategy::Fused];

    /// The name used on the command line and in files.
    pub fn name(self) -> &'static str {
        match self {
            Strategy::ThreePass => "3pass",
            Strategy::TwoPass => "2pass",
            Strategy::Fused => "fused",
        }
    }

    /// Default refresh block size k: the fused pass branches per pixel, so its refresh blocks are
    /// as large as a GPU's execution group (8×8 = 64 lanes) to keep the branch coherent.
    pub fn default_block(self) -> u32 {
        match self {
            Strategy::Fused => 8,
            _ => 4,
        }
    }
}

impl std::fmt::Display for Strategy {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

impl std::str::FromStr for Strategy {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, String> {
        Strategy::ALL
            .into_iter()
            .find(|k| k.name() == s)
            .ok_or_else(|| format!("unknown strategy `{s}` (expected 3pass, 2pass or fused)"))
    }
}

/// How pass 1 reconstructs the previous payload at the reprojected position.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize, Default)]
#[serde(rename_all = "lowercase")]
pub enum Reconstruct {
    /// One filtered fetch (linear sampler): the paper's bilinear reconstruction.
    #[default]
    Bilinear,
    /// One `textureLoad` of the nearest texel: cheaper, needs no filtering, blockier.
    Nearest,
}

/// Which pass of a variant.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum PassKind {
    /// 3pass, pass 1: keep the reprojected payload at hits.
    Reproject,
    /// 3pass, pass 2: compute the node where pass 1 left the pixel open.
    Recompute,
    /// 3pass, pass 3: the shader with the node read from the cache.
    Shade,
    /// fused: the whole variant in one pass.
    Fused,
    /// 2pass, pass 1: reproject and shade the hits.
    ShadeHits,
    /// 2pass, pass 2: the whole shader where pass 1 left the pixel open.
    ShadeMisses,
}

/// The manifest of one variant.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Manifest {
    /// Always `"reproj.manifest"`.
    pub schema: String,
    pub version: u32,
    /// Original shader file name and fragment entry point.
    pub shader: String,
    pub entry: String,
    pub node: NodeInfo,
    /// How the passes are laid out.
    pub strategy: Strategy,
    /// How pass 1 reconstructs the previous payload.
    pub reconstruct: Reconstruct,
    pub cache_format: CacheFormat,
    /// WebGPU device features the passes need (`float32-filterable` to filter an rgba32float cache).
    #[serde(default)]
    pub required_features: Vec<String>,
    /// `@location` of the extra vertex output every pass's vertex stage must write: the previous
    /// frame's clip-space position of the vertex (`prev_view_proj * prev_model * position`), vec4<f32>.
    pub prev_clip_location: u32,
    /// Bind group the instancer added (the lowest one the shader does not use).
    pub group: u32,
    /// Runtime parameters and their defaults (uniform buffer `reproj_params`).
    pub params: Params,
    /// Passes in draw order, all drawing the same geometry with the same vertex stage each frame.
    pub passes: Vec<Pass>,
    /// Plain-language notes for the host (cache swap, first frame, ...).
    pub notes: Vec<String>,
}

/// The cached node.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct NodeInfo {
    /// Node id from `reproj nodes`, or `"root"`.
    pub id: String,
    pub text: String,
    pub line: u32,
    pub col: u32,
    /// WGSL type, e.g. `vec3<f32>`.
    #[serde(rename = "type")]
    pub ty: String,
    /// Number of payload floats (1..=4).
    pub components: u32,
}

/// Defaults of the runtime parameters. Layout of `reproj_params` (16 bytes, std140-compatible):
/// `delta_n: u32, clock: u32, block: u32, depth_epsilon: f32`.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Params {
    /// Refresh period Δn (1 = refresh every pixel every frame: the original shader).
    pub delta_n: u32,
    /// Refresh block size k in pixels (k×k blocks aligned to 2×2 quads).
    pub block: u32,
    /// Depth tolerance ε of the hit test, in NDC depth units.
    pub depth_epsilon: f32,
    /// Size in bytes of the `reproj_params` uniform buffer.
    pub size: u32,
}

/// One render pass of the variant.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Pass {
    pub kind: PassKind,
    /// WGSL file written beside the manifest.
    pub file: String,
    /// Fragment entry point in that file.
    pub entry: String,
    /// Bindings of the module (the shader's own plus the instancer's), for building layouts.
    pub bindings: Vec<Binding>,
    /// Color attachments, one per fragment output `@location`.
    pub colors: Vec<ColorTarget>,
    pub depth: DepthState,
}

/// A resource binding of a pass module.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Binding {
    pub group: u32,
    pub binding: u32,
    pub name: String,
    /// WGSL type as written, e.g. `texture_2d<f32>`, `uniform ReprojParams`, `sampler`.
    #[serde(rename = "type")]
    pub ty: String,
    /// True for bindings the instancer added (the host owns them); false for the shader's own.
    pub added: bool,
    /// What the host must bind there, and when it changes.
    pub contents: String,
}

/// The color attachment of a pass.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ColorTarget {
    /// The fragment output `@location` (the attachment index).
    pub location: u32,
    /// `"current cache payload"`, `"frame color"` or `"current depth copy"` (the fragment's depth,
    /// `@builtin(position).z`, that the next frame's lookup reads as its previous depth).
    pub target: String,
    /// Texture format (WebGPU name), or `"same as the original shader's target"`.
    pub format: String,
    /// `"clear"` (frame color: to the scene's background; cache: to zero; depth copy: to 1.0) or
    /// `"load"`.
    pub load: String,
    pub store: String,
}

/// Depth (and stencil) state of a pass. All passes share the current frame's depth texture,
/// format `depth32float`; the next frame reads the depth copy instead, never this texture.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct DepthState {
    pub format: String,
    /// WebGPU compare function name (`less`, `equal`, ...).
    pub compare: String,
    pub write: bool,
    /// `"clear 1.0"` or `"load"`.
    pub load: String,
    pub store: String,
}
