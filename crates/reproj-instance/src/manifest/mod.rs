//! The variant manifest: everything a host engine needs to run a cached variant without reading our
//! code. Serialized as `manifest.json`, schema `reproj.manifest` version [`MANIFEST_VERSION`].

use schemars::JsonSchema;
use serde::{Deserialize, Serialize};

/// Version of the manifest schema. Bump on any incompatible change.
/// Version 2: `strategy`, `reconstruct`, per-pass `colors` (several targets, by location) instead
/// of one `color`, narrow cache formats.
/// Version 3: fully machine-readable: structured layout entries and resources per binding, the
/// textures and samplers to create, the ping-pong plan, load/clear values as numbers, conventions,
/// the vertex-stage contract, the params layout field by field.
/// Version 4: `also` (several nodes in one payload).
/// Version 5: `params.schedule`, the run-time Δn schedule by motion band.
/// Version 6: `reprojection` (the engine's motion vectors instead of the vertex stage's previous
/// clip position, which `vertex.prev_clip_location` then leaves out), `bytes_per_pixel`.
pub const MANIFEST_VERSION: u32 = 7;

/// What [`reproj_io::read_json`] expects of a `manifest.json`.
pub const MANIFEST_KIND: reproj_io::Kind = reproj_io::Kind {
    schema: "reproj.manifest",
    versions: 3..=MANIFEST_VERSION,
    hint: "write the variant again with `reproj instance` or `reproj emit`",
};

mod choices;
pub use choices::*;

/// The manifest of one variant: everything a host needs to run it, as data (`docs/SCHEMAS.md`,
/// JSON Schema `docs/manifest.schema.json`).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
pub struct Manifest {
    /// Always `"reproj.manifest"`.
    pub schema: String,
    pub version: u32,
    /// Original shader file name and fragment entry point.
    pub shader: String,
    pub entry: String,
    /// [`ir_hash`] of the original shader: a variant is only rendered, or run, with the shader it
    /// was made from (up to comments and formatting). Absent in manifests written before it.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub shader_ir_hash: Option<String>,
    /// The cached node (the first, at payload offset 0, when several are cached together).
    pub node: NodeInfo,
    /// Further nodes cached in the same payload, each at its `offset` (version 4; empty: one node).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub also: Vec<NodeInfo>,
    /// How the passes are laid out.
    pub strategy: Strategy,
    /// How the first pass reconstructs the previous payload.
    pub reconstruct: Reconstruct,
    pub cache_format: CacheFormat,
    /// The payload channel that holds the fragment's depth (version 7): the passes that write the
    /// cache write `@builtin(position).z` there, its clear value there is 1.0, and the lookup reads
    /// the previous depth from it in the payload's one filtered fetch. Absent: the depth copy
    /// (`cur_depth_copy` / `prev_depth_copy`, r32float) holds it.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub depth_channel: Option<u32>,
    /// WebGPU device features the passes need (`float32-filterable` to filter a 32-bit float
    /// cache).
    pub required_features: Vec<String>,
    /// Bind group of the bindings the instancer added (`--group`, else the lowest one the shader
    /// does not use, else the shader's highest).
    pub group: u32,
    /// The first binding number of the added bindings in `group` (absent: 0). Above 0 where
    /// `group` is also the shader's: its own bindings there are below this number, and a host
    /// binds them and the added ones in one bind group.
    #[serde(default, skip_serializing_if = "is_zero")]
    pub binding_base: u32,
    /// Coordinate and depth conventions the passes assume.
    pub conventions: Conventions,
    /// Where the lookup finds a fragment in the previous frame (version 6; absent: `vertex`).
    #[serde(default, skip_serializing_if = "Reprojection::is_vertex")]
    pub reprojection: Reprojection,
    /// What the host's vertex stage must provide.
    pub vertex: VertexContract,
    /// The runtime parameters (uniform buffer `reproj_params`).
    pub params: Params,
    /// Textures the host creates for the variant (besides its own frame target).
    pub textures: Vec<TextureDesc>,
    /// Bytes per frame pixel of `textures` apart from the depth attachment (which the host's
    /// frame has anyway): the variant's memory is this times width times height (version 6).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub bytes_per_pixel: Option<u32>,
    /// Samplers the host creates for the variant.
    pub samplers: Vec<SamplerDesc>,
    /// Which texture plays which role on each frame.
    pub frames: FramePlan,
    /// Passes in draw order, all drawing the same geometry with the same vertex stage each frame.
    pub passes: Vec<Pass>,
    /// Plain-language notes for a reader; everything in them is also in the fields above.
    pub notes: Vec<String>,
    /// The push constants the passes read (the shader's own: WGSL `var<immediate>`, GLSL
    /// `layout(push_constant)`), which a host sets before each draw; each language says where in
    /// `languages[].immediates`. Absent when the shader has none.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub immediates: Option<Immediates>,
    /// The passes in other languages (`--lang`), each with its files and how it binds every
    /// resource. Absent when only WGSL was written.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub languages: Vec<LanguageOutput>,
}

/// The passes written in one other language, and that language's bindings.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
pub struct LanguageOutput {
    /// `glsl`, `hlsl`, `msl` or `spirv` (as `--lang` takes it).
    pub lang: String,
    /// One file per pass, in the order of `passes`.
    pub files: Vec<String>,
    /// Every resource of the passes as this language binds it: the same slot in every pass.
    pub bindings: Vec<LanguageBinding>,
    /// The language's binding model in words (heaps, combined samplers, extra buffers).
    pub notes: Vec<String>,
    /// Where this language's passes read the push constants (`immediates`); absent when the
    /// shader has none.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub immediates: Option<LanguageImmediates>,
}

/// The shader's push constants (naga's immediates), which every pass that reads them reads at
/// the same offsets.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
pub struct Immediates {
    /// The variable's name in the shader (`var<immediate> NAME`, or the GLSL block's instance).
    pub name: String,
    /// Its WGSL type (`Locals`, `vec4<f32>`).
    #[serde(rename = "type")]
    pub ty: String,
    /// Bytes a host sets, at offset 0, laid out as the WGSL type is (wgpu: `immediate_size` of
    /// the pipeline layout at least this, `set_immediates(0, bytes)`; Vulkan: a push-constant
    /// range of the fragment stage).
    pub size: u32,
}

/// Where one language reads the push constants.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
pub struct LanguageImmediates {
    /// The number the language binds them by where it binds them like a resource: OpenGL's
    /// uniform block binding (GLSL; absent where the block has no OpenGL form), the HLSL
    /// register number, MSL's buffer index; absent for SPIR-V (a push-constant range).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub slot: Option<u32>,
    /// HLSL's register space.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub space: Option<u32>,
    /// As the file writes it: `layout(push_constant) uniform` (Vulkan GLSL) and `layout(std140,
    /// binding = 3) uniform` (OpenGL), `register(b0, space254)`, `[[buffer(2)]]`,
    /// `PushConstant`.
    pub target: String,
}

/// One resource in one language.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
pub struct LanguageBinding {
    /// The WGSL resource (`passes[].bindings`).
    pub group: u32,
    pub binding: u32,
    pub name: String,
    /// `uniform`, `storage`, `read-only-storage`, `texture`, `storage-texture` or `sampler`.
    pub kind: String,
    /// The number the language binds it by: GLSL's `binding`, HLSL's register number (for a
    /// sampler: its index in the group's sampler index buffer), MSL's buffer, texture or sampler
    /// index, SPIR-V's binding.
    pub slot: u32,
    /// HLSL's register space or SPIR-V's descriptor set; absent for GLSL, MSL and HLSL samplers.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub space: Option<u32>,
    /// As the file writes it: `layout(binding = 2)`, `register(t3, space1)`, `[[texture(1)]]`,
    /// `DescriptorSet 1, Binding 3`.
    pub target: String,
}

/// The cached node.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
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
    /// Index of its first float in the payload (version 4; 0 before).
    #[serde(default, skip_serializing_if = "is_zero")]
    pub offset: u32,
}

fn is_zero(v: &u32) -> bool {
    *v == 0
}

/// Coordinate conventions (WebGPU's).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
pub struct Conventions {
    /// NDC x and y range, y pointing up.
    pub ndc_xy: [f32; 2],
    /// NDC depth range: 0 at the near plane, 1 at the far plane.
    pub ndc_z: [f32; 2],
    /// Texture coordinates of an NDC point: `u = x * uv_from_ndc[0] + uv_from_ndc[1]`,
    /// `v = y * uv_from_ndc[2] + uv_from_ndc[3]` (framebuffer origin top-left).
    pub uv_from_ndc: [f32; 4],
    /// Depth value of empty pixels (what every depth texture is cleared to).
    pub depth_clear: f32,
}

impl Manifest {
    /// Where the bindings reproj added are: `group`, from `binding_base` on.
    pub fn added_place(&self) -> crate::contract::AddedPlace {
        crate::contract::AddedPlace {
            group: self.group,
            base: self.binding_base,
        }
    }
}

impl Default for Conventions {
    fn default() -> Self {
        Conventions {
            ndc_xy: [-1.0, 1.0],
            ndc_z: [0.0, 1.0],
            uv_from_ndc: [0.5, 0.5, -0.5, 0.5],
            depth_clear: 1.0,
        }
    }
}

/// What the host's vertex stage must do for every pass.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
pub struct VertexContract {
    /// The clip position must be `@builtin(position) @invariant`, so every pass rasterizes the
    /// same depths as the others.
    pub invariant_position: bool,
    /// `@location` of the extra vertex output: the vertex's clip-space position in the previous
    /// frame, `vec4<f32>`. Absent with `reprojection: motion_vectors` (version 6), where the
    /// vertex stage writes nothing extra.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub prev_clip_location: Option<u32>,
    /// Data the host supplies to compute it (per object and frame), by name.
    pub inputs: Vec<VertexInput>,
    /// A WGSL function computing the output from those inputs; call it in the vertex stage.
    pub wgsl: String,
}

/// One value the vertex contract needs.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
pub struct VertexInput {
    pub name: String,
    /// WGSL type.
    #[serde(rename = "type")]
    pub ty: String,
    pub meaning: String,
}

/// Runtime parameters: defaults and the layout of the `reproj_params` uniform buffer.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
pub struct Params {
    /// Refresh period Δn (1 = refresh every pixel every frame: the original shader).
    pub delta_n: u32,
    /// Refresh block size k in pixels (k×k blocks aligned to 2×2 quads).
    pub block: u32,
    /// Relative depth tolerance ε of the hit test.
    pub depth_epsilon: f32,
    /// Size in bytes of the `reproj_params` uniform buffer.
    pub size: u32,
    /// The buffer's fields, each with its value per frame.
    pub fields: Vec<ParamField>,
    /// Run-time adaptation (version 5; empty: keep `delta_n`): the longest Δn predicted within
    /// the budget for each band of motion, slowest band first. A host measures its frame's
    /// on-screen motion (pixels a visible surface point moved since the previous frame) and
    /// writes the Δn of the first band whose `up_to_pixels_per_frame` is at least that
    /// ([`Params::delta_n_for`]); Δn is a uniform, so it may change every frame.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub schedule: Vec<DeltaNBand>,
}

/// One band of [`Params::schedule`].
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize, JsonSchema)]
pub struct DeltaNBand {
    /// The fastest motion of the band, pixels per frame (`null`: any faster: the last band).
    pub up_to_pixels_per_frame: Option<f64>,
    /// Δn to use in the band (1: recompute every pixel, the original shader's result).
    pub delta_n: u32,
}

impl Params {
    /// The Δn for a frame whose on-screen motion is `pixels_per_frame`: the first band of the
    /// schedule that reaches it (the last band beyond), or `delta_n` without a schedule. A motion
    /// that is not a number takes the last band (the fastest: the cautious side).
    pub fn delta_n_for(&self, pixels_per_frame: f64) -> u32 {
        let Some(last) = self.schedule.last() else {
            return self.delta_n;
        };
        if !pixels_per_frame.is_finite() {
            return last.delta_n;
        }
        self.schedule
            .iter()
            .find(|b| {
                b.up_to_pixels_per_frame
                    .is_none_or(|m| pixels_per_frame <= m)
            })
            .unwrap_or(last)
            .delta_n
    }
}

/// A field of `reproj_params`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
pub struct ParamField {
    pub name: String,
    /// Byte offset in the buffer.
    pub offset: u32,
    #[serde(rename = "type")]
    pub ty: ScalarType,
    /// What to write each frame.
    pub value: ParamValue,
}

/// A 4-byte scalar.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, JsonSchema)]
#[serde(rename_all = "lowercase")]
pub enum ScalarType {
    U32,
    F32,
}

/// The value of a parameter on a frame.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(rename_all = "snake_case", tag = "kind")]
pub enum ParamValue {
    /// The same every frame.
    Constant {
        #[serde(serialize_with = "number")]
        value: f64,
    },
    /// `value`, except `first` on the first frame and after a camera cut (the previous frame's
    /// textures hold nothing usable).
    Steady {
        #[serde(serialize_with = "number")]
        value: f64,
        #[serde(serialize_with = "number")]
        first: f64,
    },
    /// The frame index, counting from 0.
    FrameIndex,
}

/// A parameter's value as JSON: a whole number as an integer (a `u32` parameter reads `13`, not
/// `13.0`), any other as a float. Read back as the same `f64` either way.
fn number<S: serde::Serializer>(v: &f64, s: S) -> Result<S::Ok, S::Error> {
    const EXACT: f64 = 9_007_199_254_740_992.0; // 2^53: every integer below is an exact f64
    if v.fract() == 0.0 && v.abs() < EXACT {
        s.serialize_i64(*v as i64)
    } else {
        s.serialize_f64(*v)
    }
}

/// How big a texture is.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, JsonSchema)]
#[serde(rename_all = "snake_case")]
pub enum TextureSize {
    /// The frame target's size.
    Frame,
}

/// A texture usage (WebGPU names).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, JsonSchema)]
#[serde(rename_all = "snake_case")]
pub enum TextureUsage {
    RenderAttachment,
    TextureBinding,
    CopySrc,
    CopyDst,
}

/// A texture the host creates for the variant.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
pub struct TextureDesc {
    /// Name used in [`FramePlan`].
    pub name: String,
    /// WebGPU format name.
    pub format: String,
    pub size: TextureSize,
    pub usage: Vec<TextureUsage>,
    pub mip_levels: u32,
    pub sample_count: u32,
}

/// A sampler the host creates for the variant (WebGPU names).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
pub struct SamplerDesc {
    /// Name used by [`BindingResource::Sampler`].
    pub name: String,
    pub mag_filter: Filter,
    pub min_filter: Filter,
    pub mipmap_filter: Filter,
    /// `clamp-to-edge` on u, v and w.
    pub address_mode: String,
}

/// A filter mode.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, JsonSchema)]
#[serde(rename_all = "lowercase")]
pub enum Filter {
    Nearest,
    Linear,
}

/// Texture roles per frame: frame `i` uses `ping_pong[i % ping_pong.len()]`, which maps each role
/// (`cur_payload`, `prev_payload`, `cur_depth_copy`, `prev_depth_copy`, `cur_depth`) to a texture of
/// [`Manifest::textures`]. What a frame writes as `cur_*` it reads as `prev_*` the next frame.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
pub struct FramePlan {
    pub ping_pong: Vec<std::collections::BTreeMap<String, String>>,
}

/// One render pass of the variant.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
pub struct Pass {
    pub kind: PassKind,
    /// WGSL file written beside the manifest.
    pub file: String,
    /// Fragment entry point in that file.
    pub entry: String,
    /// Bindings of the module (the shader's own plus the instancer's), for building layouts.
    /// Visibility: fragment.
    pub bindings: Vec<Binding>,
    /// Color attachments, one per fragment output `@location`.
    pub colors: Vec<ColorTarget>,
    pub depth: DepthState,
}

/// A resource binding of a pass module.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
pub struct Binding {
    pub group: u32,
    pub binding: u32,
    pub name: String,
    /// WGSL type as declared, e.g. `texture_2d<f32>`, `uniform ReprojParams`, `sampler`.
    #[serde(rename = "type")]
    pub ty: String,
    /// True for bindings the instancer added (the host owns them); false for the shader's own.
    pub added: bool,
    /// The bind group layout entry (WebGPU's `GPUBindGroupLayoutEntry`, fragment visibility).
    pub layout: LayoutEntry,
    /// What to bind.
    pub resource: BindingResource,
}

/// A bind group layout entry, as WebGPU's.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(rename_all = "snake_case", tag = "type")]
pub enum LayoutEntry {
    Buffer {
        /// `uniform`, `storage` or `read-only-storage`.
        buffer_type: String,
        /// Bytes (the WGSL type's size).
        min_binding_size: u64,
    },
    Texture {
        /// `float`, `unfilterable-float`, `depth`, `sint` or `uint`.
        sample_type: String,
        /// `1d`, `2d`, `2d-array`, `cube`, `cube-array` or `3d`.
        view_dimension: String,
        multisampled: bool,
    },
    Sampler {
        /// `filtering`, `non-filtering` or `comparison`.
        sampler_type: String,
    },
    StorageTexture {
        format: String,
        /// `read-only`, `write-only` or `read-write`.
        access: String,
        view_dimension: String,
    },
}

/// What a binding takes.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(rename_all = "snake_case", tag = "kind")]
pub enum BindingResource {
    /// The shader's own resource, bound as for the original shader.
    Own,
    /// The `reproj_params` uniform buffer ([`Params`]).
    Params,
    /// The texture playing this role this frame ([`FramePlan`]), whole, default view.
    Texture { role: String },
    /// The host's motion-vector texture of this frame (`reprojection: motion_vectors`), whole,
    /// default view: a float format, read with `textureLoad` (unfilterable is enough).
    Motion,
    /// A sampler of [`Manifest::samplers`].
    Sampler { name: String },
}

/// A load operation with its clear value.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(rename_all = "snake_case", tag = "op")]
pub enum LoadOp {
    /// Clear to `value` (RGBA or depth); `null`: the host's own clear color for its frame, as
    /// for the original shader.
    Clear { value: Option<Vec<f64>> },
    /// Keep what is there.
    Load,
}

impl LoadOp {
    pub fn is_load(&self) -> bool {
        matches!(self, LoadOp::Load)
    }
}

/// A color attachment of a pass.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
pub struct ColorTarget {
    /// The fragment output `@location` (the attachment index).
    pub location: u32,
    /// `frame` (the host's frame target) or a texture role of [`FramePlan`] (`cur_payload`).
    pub attachment: String,
    /// Texture format (WebGPU name); `null` for the frame: the original shader's target format.
    pub format: Option<String>,
    pub load: LoadOp,
    pub store: bool,
    /// Blending: `null`, replace (no blending).
    pub blend: Option<String>,
}

/// Depth state and attachment of a pass (no stencil).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
pub struct DepthState {
    /// A texture role of [`FramePlan`] (`cur_depth`).
    pub attachment: String,
    pub format: String,
    /// WebGPU compare function name (`less`, `equal`, ...).
    pub compare: String,
    pub write: bool,
    pub load: LoadOp,
    pub store: bool,
    /// Stencil state: `null`, none.
    pub stencil: Option<String>,
}

/// The `$id` of the manifest's JSON Schema (the repository's copy, `docs/manifest.schema.json`).
pub const MANIFEST_SCHEMA_ID: &str = "https://example.invalid/reproj/docs/manifest.schema.json";

/// The manifest's JSON Schema (draft 2020-12), as published in `docs/manifest.schema.json`: with
/// its `$id`, and `schema` and `version` held to this writer's by `const`.
pub fn manifest_schema() -> serde_json::Value {
    let mut schema =
        serde_json::to_value(schemars::schema_for!(Manifest)).expect("a schema serializes");
    let root = schema.as_object_mut().expect("a schema is an object");
    root.insert("$id".into(), MANIFEST_SCHEMA_ID.into());
    let properties = root
        .get_mut("properties")
        .and_then(|p| p.as_object_mut())
        .expect("the manifest has properties");
    for (field, value) in [
        ("schema", serde_json::Value::from(MANIFEST_KIND.schema)),
        ("version", serde_json::Value::from(MANIFEST_VERSION)),
    ] {
        if let Some(p) = properties.get_mut(field).and_then(|p| p.as_object_mut()) {
            p.insert("const".into(), value);
        }
    }
    schema
}

/// FNV-1a 64 of the shader's IR written back as WGSL by naga: the same for two sources that differ
/// only in comments and formatting, and one hash for a shader however it was read: a GLSL
/// shader's WGSL form ([`reproj_front::Shader::to_wgsl`], what `analyze` and `emit` use) hashes
/// its source, which is the WGSL written of the GLSL shader's IR, so it and the shader `instance`,
/// `render` and `bench` read from the file hash alike (writing that WGSL's IR again could differ
/// by naga's renamings).
pub fn ir_hash(shader: &reproj_front::Shader) -> String {
    if shader.wgsl_form {
        return reproj_io::content_hash(shader.source.as_bytes());
    }
    let text = reproj_front::validator()
        .validate(&shader.module)
        .ok()
        .and_then(|info| crate::write_wgsl(&shader.module, &info).ok())
        .unwrap_or_else(|| shader.source.clone());
    reproj_io::content_hash(text.as_bytes())
}
