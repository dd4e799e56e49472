//! The variant manifest: everything a host engine needs to run a cached variant without reading our
//! code. Serialized as `manifest.json`, schema `reproj.manifest` version [`MANIFEST_VERSION`].

use serde::{Deserialize, Serialize};

/// Version of the manifest schema. Bump on any incompatible change.
pub const MANIFEST_VERSION: u32 = 1;

/// Cache payload texel format.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, Default)]
#[serde(rename_all = "lowercase")]
pub enum CacheFormat {
    /// Exact: 32-bit float per channel (default).
    #[default]
    Rgba32float,
    /// The paper's 16 bits per channel.
    Rgba16float,
}

/// Which of the three passes.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum PassKind {
    Reproject,
    Recompute,
    Shade,
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
    pub color: ColorTarget,
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
    /// `"current cache payload"` or `"frame color"`.
    pub target: String,
    /// Texture format (WebGPU name), or `"same as the original shader's target"`.
    pub format: String,
    /// `"clear"` (to zero) or `"load"`.
    pub load: String,
    pub store: String,
}

/// Depth (and stencil) state of a pass. All passes share the current frame's depth texture,
/// format `depth32float`; it becomes the previous depth for the next frame.
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
