//! `manifest.json`, read with this host's own types.
//!
//! These structs mirror the published schema (`docs/manifest.schema.json`, schema
//! `reproj.manifest`, version 3) and nothing else: an engine in any language can read the same
//! JSON the same way. Only the fields this host uses are declared; serde ignores the others (the
//! node, the notes, the WGSL types of bindings...). Enumerations are kept as the strings the schema
//! uses (WebGPU names), converted to wgpu values where they are used (`webgpu.rs`), so a value this
//! host does not know is an error naming it rather than a parse failure.

use std::collections::BTreeMap;
use std::path::Path;

use anyhow::{Context, bail};
use serde::Deserialize;

/// The schema name and the versions this host reads (version 4 only added which nodes the payload
/// holds, which a host need not know; version 5 the run-time Δn schedule, `params.schedule`,
/// which `--adaptive` follows).
pub const SCHEMA: &str = "reproj.manifest";
pub const VERSION: u64 = 5;
pub const OLDEST_VERSION: u64 = 3;

#[derive(Debug, Deserialize)]
pub struct Manifest {
    /// The original shader's file name and fragment entry point.
    pub shader: String,
    pub entry: String,
    /// `3pass`, `2pass` or `fused` (for messages; the passes below say everything).
    pub strategy: String,
    /// WebGPU feature names the device must have.
    pub required_features: Vec<String>,
    /// The bind group the instancer added (no engine resource may live there).
    pub group: u32,
    pub conventions: Conventions,
    pub vertex: VertexContract,
    pub params: Params,
    pub textures: Vec<TextureDesc>,
    pub samplers: Vec<SamplerDesc>,
    pub frames: FramePlan,
    pub passes: Vec<Pass>,
}

#[derive(Debug, Deserialize)]
pub struct Conventions {
    /// NDC x/y and depth ranges, and texture coordinates from NDC (`u = x·a + b`, `v = y·c + d`).
    pub ndc_xy: [f64; 2],
    pub ndc_z: [f64; 2],
    pub uv_from_ndc: [f64; 4],
    /// What every depth texture holds where nothing was drawn.
    pub depth_clear: f64,
}

impl Conventions {
    /// WebGPU's (and so wgpu's): the passes' arithmetic is only right for an engine that uses
    /// them. An engine on another API with other conventions would have to convert.
    fn are_webgpu(&self) -> bool {
        self.ndc_xy == [-1.0, 1.0]
            && self.ndc_z == [0.0, 1.0]
            && self.uv_from_ndc == [0.5, 0.5, -0.5, 0.5]
    }
}

#[derive(Debug, Deserialize)]
pub struct VertexContract {
    pub invariant_position: bool,
    /// `@location` of the extra `vec4<f32>` vertex output: the previous frame's clip position.
    pub prev_clip_location: u32,
    /// The values the helper function takes, in argument order.
    pub inputs: Vec<VertexInput>,
    /// WGSL source of the helper function; pasted into the host's vertex module.
    pub wgsl: String,
}

#[derive(Debug, Deserialize)]
pub struct VertexInput {
    pub name: String,
}

#[derive(Debug, Deserialize)]
pub struct Params {
    /// Bytes of the `reproj_params` uniform buffer.
    pub size: u32,
    pub fields: Vec<ParamField>,
    /// Run-time Δn by motion band, slowest first (manifest version 5; empty: a fixed Δn).
    #[serde(default)]
    pub schedule: Vec<DeltaNBand>,
}

/// One band of [`Params::schedule`]: up to this motion (pixels per frame; `None`: any), this Δn.
#[derive(Debug, Clone, Copy, Deserialize)]
pub struct DeltaNBand {
    pub up_to_pixels_per_frame: Option<f64>,
    pub delta_n: u32,
}

impl Params {
    /// The scheduled Δn at a frame's motion: the first band that reaches it, the last beyond
    /// (and for a motion that is not a number).
    pub fn scheduled_delta_n(&self, pixels_per_frame: f64) -> Option<u32> {
        let last = self.schedule.last()?;
        if !pixels_per_frame.is_finite() {
            return Some(last.delta_n);
        }
        Some(
            self.schedule
                .iter()
                .find(|b| {
                    b.up_to_pixels_per_frame
                        .is_none_or(|m| pixels_per_frame <= m)
                })
                .unwrap_or(last)
                .delta_n,
        )
    }
}

#[derive(Debug, Deserialize)]
pub struct ParamField {
    pub name: String,
    pub offset: u32,
    /// `u32` or `f32`.
    #[serde(rename = "type")]
    pub ty: String,
    pub value: ParamValue,
}

/// The value of a parameter on a frame.
#[derive(Debug, Clone, Deserialize)]
#[serde(rename_all = "snake_case", tag = "kind")]
pub enum ParamValue {
    Constant {
        value: f64,
    },
    /// `first` on frame 0 (no previous frame to reuse), `value` after.
    Steady {
        value: f64,
        first: f64,
    },
    FrameIndex,
}

#[derive(Debug, Deserialize)]
pub struct TextureDesc {
    pub name: String,
    /// WebGPU format name.
    pub format: String,
    /// `frame`: the frame target's size (the only size in version 3).
    pub size: String,
    /// `render_attachment`, `texture_binding`, `copy_src`, `copy_dst`.
    pub usage: Vec<String>,
    pub mip_levels: u32,
    pub sample_count: u32,
}

#[derive(Debug, Deserialize)]
pub struct SamplerDesc {
    pub name: String,
    pub mag_filter: String,
    pub min_filter: String,
    pub mipmap_filter: String,
    pub address_mode: String,
}

#[derive(Debug, Deserialize)]
pub struct FramePlan {
    /// Frame `i` resolves roles with `ping_pong[i % len]`: role → texture name.
    pub ping_pong: Vec<BTreeMap<String, String>>,
}

#[derive(Debug, Deserialize)]
pub struct Pass {
    pub kind: String,
    pub file: String,
    pub entry: String,
    pub bindings: Vec<Binding>,
    pub colors: Vec<ColorTarget>,
    pub depth: DepthState,
}

#[derive(Debug, Deserialize)]
pub struct Binding {
    pub group: u32,
    pub binding: u32,
    pub name: String,
    pub layout: LayoutEntry,
    pub resource: Resource,
}

/// WebGPU's `GPUBindGroupLayoutEntry` (fragment visibility).
#[derive(Debug, Deserialize)]
#[serde(rename_all = "snake_case", tag = "type")]
pub enum LayoutEntry {
    Buffer {
        buffer_type: String,
        min_binding_size: u64,
    },
    Texture {
        sample_type: String,
        view_dimension: String,
        multisampled: bool,
    },
    Sampler {
        sampler_type: String,
    },
    StorageTexture {
        format: String,
        access: String,
        view_dimension: String,
    },
}

/// What to bind.
#[derive(Debug, Deserialize)]
#[serde(rename_all = "snake_case", tag = "kind")]
pub enum Resource {
    /// The engine's own resource at this group and binding (as for the original shader).
    Own,
    /// The `reproj_params` uniform buffer.
    Params,
    /// The texture playing `role` this frame.
    Texture { role: String },
    /// A sampler of `samplers`.
    Sampler { name: String },
}

#[derive(Debug, Deserialize)]
#[serde(rename_all = "snake_case", tag = "op")]
pub enum LoadOp {
    /// Clear to `value`; `null`: the engine's own clear value (its clear color for the frame).
    Clear {
        value: Option<Vec<f64>>,
    },
    Load,
}

#[derive(Debug, Deserialize)]
pub struct ColorTarget {
    pub location: u32,
    /// `frame` (the engine's frame target) or a texture role.
    pub attachment: String,
    /// `null` for the frame: the engine's frame format.
    pub format: Option<String>,
    pub load: LoadOp,
    pub store: bool,
    /// `null`: no blending (the only value in version 3).
    pub blend: Option<String>,
}

#[derive(Debug, Deserialize)]
pub struct DepthState {
    /// A texture role.
    pub attachment: String,
    pub format: String,
    pub compare: String,
    pub write: bool,
    pub load: LoadOp,
    pub store: bool,
    /// `null`: no stencil (the only value in version 3).
    pub stencil: Option<String>,
}

/// The color attachment name that means the engine's own frame target.
pub const FRAME: &str = "frame";

impl Manifest {
    /// Read `dir/manifest.json`: the schema name and version first (an older or newer manifest
    /// gets a message naming its version, not the first field that differs), then the rest.
    pub fn load(dir: &Path) -> anyhow::Result<Manifest> {
        let path = dir.join("manifest.json");
        let text = std::fs::read_to_string(&path)
            .with_context(|| format!("reading {}", path.display()))?;
        let head: serde_json::Value = serde_json::from_str(&text)
            .with_context(|| format!("{} is not JSON", path.display()))?;
        let schema = head.get("schema").and_then(|v| v.as_str());
        if schema != Some(SCHEMA) {
            bail!(
                "{}: `schema` is {:?}, expected \"{SCHEMA}\": not a reproj variant manifest",
                path.display(),
                schema.unwrap_or("(missing)")
            );
        }
        let version = head.get("version").and_then(|v| v.as_u64());
        if !version.is_some_and(|v| (OLDEST_VERSION..=VERSION).contains(&v)) {
            bail!(
                "{}: manifest version {} is not supported: this host reads versions {OLDEST_VERSION} to {VERSION} (write the variant again with a reproj that writes version {VERSION}, or update the host)",
                path.display(),
                version.map_or_else(|| "(missing)".to_string(), |v| v.to_string())
            );
        }
        let m: Manifest = serde_json::from_str(&text)
            .with_context(|| format!("{}: does not match the version 3 schema", path.display()))?;
        if m.frames.ping_pong.is_empty() {
            bail!("{}: `frames.ping_pong` is empty", path.display());
        }
        if !m.conventions.are_webgpu() {
            bail!(
                "{}: the passes assume the conventions {:?}, not WebGPU's, which this host uses",
                path.display(),
                m.conventions
            );
        }
        if m.passes.is_empty() {
            bail!("{}: no passes", path.display());
        }
        Ok(m)
    }

    /// The texture playing `role` on frame `frame`: through `frames.ping_pong[frame % len]`, or a
    /// texture named `role` directly if no frame maps that role.
    pub fn texture_for<'a>(&'a self, role: &'a str, frame: u32) -> anyhow::Result<&'a str> {
        let plan = &self.frames.ping_pong;
        let map = &plan[frame as usize % plan.len()];
        if let Some(t) = map.get(role) {
            return Ok(t);
        }
        if self.textures.iter().any(|t| t.name == role) {
            return Ok(role);
        }
        bail!("the manifest maps no texture to the role `{role}` (frames.ping_pong, textures)")
    }
}
