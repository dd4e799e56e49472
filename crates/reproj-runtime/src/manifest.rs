//! `manifest.json`, read with this crate's own types.
//!
//! These structs mirror the published schema (`docs/manifest.schema.json`, schema
//! `reproj.manifest`, versions 3 to 7) and nothing else: an engine in any language reads the same
//! JSON the same way. Only the fields the runtime uses are declared; serde ignores the others (the
//! node, the notes, the WGSL types of bindings...). Enumerations are kept as the strings the schema
//! uses (WebGPU names) and converted to wgpu values when the variant is loaded (`plan.rs`), so a
//! value this runtime does not know is an error naming its field rather than a parse failure.

use std::collections::BTreeMap;
use std::path::Path;

use serde::Deserialize;

use crate::RuntimeError;
use crate::files::{self, ReadLimits};

/// The schema name and the versions this runtime reads (version 4 only added which nodes the
/// payload holds, which a host need not know; version 5 the run-time Δn schedule,
/// `params.schedule`; version 6 `reprojection`, the engine's motion vectors; version 7
/// `depth_channel`, the depth in the payload, which the textures, targets and clear values
/// already say).
pub const SCHEMA: &str = "reproj.manifest";
pub const VERSION: u64 = 7;
pub const OLDEST_VERSION: u64 = 3;

/// `reprojection` before it was written.
fn vertex() -> String {
    "vertex".into()
}

/// The color attachment name that means the application's own frame target.
pub const FRAME: &str = "frame";

/// The `steady` parameter that holds the refresh period Δn.
pub const DELTA_N: &str = "delta_n";

#[derive(Debug, Clone, Deserialize)]
pub struct Manifest {
    /// The original shader's file name and fragment entry point.
    pub shader: String,
    pub entry: String,
    /// `3pass`, `2pass` or `fused` (for messages; the passes below say everything).
    pub strategy: String,
    /// WebGPU feature names the device must have.
    pub required_features: Vec<String>,
    /// The bind group of the bindings the instancer added.
    pub group: u32,
    /// The first binding number of the added bindings in `group` (absent: 0, the group is the
    /// variant's own and no engine resource may live there). Above 0: the group is also the
    /// shader's, whose own bindings there are below this number.
    #[serde(default)]
    pub binding_base: u32,
    pub conventions: Conventions,
    /// Where the lookup finds a fragment in the previous frame: `vertex` (the vertex stage's
    /// previous clip position; the default before version 6) or `motion_vectors` (the
    /// application's motion-vector texture, [`crate::Setup::motion`]).
    #[serde(default = "vertex")]
    pub reprojection: String,
    pub vertex: VertexContract,
    pub params: Params,
    pub textures: Vec<TextureDesc>,
    pub samplers: Vec<SamplerDesc>,
    pub frames: FramePlan,
    pub passes: Vec<Pass>,
}

#[derive(Debug, Clone, Deserialize)]
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
    pub fn are_webgpu(&self) -> bool {
        self.ndc_xy == [-1.0, 1.0]
            && self.ndc_z == [0.0, 1.0]
            && self.uv_from_ndc == [0.5, 0.5, -0.5, 0.5]
    }
}

#[derive(Debug, Clone, Deserialize)]
pub struct VertexContract {
    pub invariant_position: bool,
    /// `@location` of the extra `vec4<f32>` vertex output: the previous frame's clip position
    /// (absent with `reprojection: motion_vectors`: the vertex stage writes nothing extra).
    #[serde(default)]
    pub prev_clip_location: Option<u32>,
    /// The values the helper function takes, in argument order.
    pub inputs: Vec<VertexInput>,
    /// WGSL source of the helper function; pasted into the host's vertex module.
    pub wgsl: String,
}

#[derive(Debug, Clone, Deserialize)]
pub struct VertexInput {
    pub name: String,
}

#[derive(Debug, Clone, Deserialize)]
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

#[derive(Debug, Clone, Deserialize)]
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

#[derive(Debug, Clone, Deserialize)]
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

#[derive(Debug, Clone, Deserialize)]
pub struct SamplerDesc {
    pub name: String,
    pub mag_filter: String,
    pub min_filter: String,
    pub mipmap_filter: String,
    pub address_mode: String,
}

#[derive(Debug, Clone, Deserialize)]
pub struct FramePlan {
    /// Frame `i` resolves roles with `ping_pong[i % len]`: role → texture name.
    pub ping_pong: Vec<BTreeMap<String, String>>,
}

#[derive(Debug, Clone, Deserialize)]
pub struct Pass {
    pub kind: String,
    pub file: String,
    pub entry: String,
    pub bindings: Vec<Binding>,
    pub colors: Vec<ColorTarget>,
    pub depth: DepthState,
}

#[derive(Debug, Clone, Deserialize)]
pub struct Binding {
    pub group: u32,
    pub binding: u32,
    pub name: String,
    pub layout: LayoutEntry,
    pub resource: Resource,
}

/// WebGPU's `GPUBindGroupLayoutEntry` (fragment visibility).
#[derive(Debug, Clone, Deserialize)]
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
#[derive(Debug, Clone, Deserialize)]
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
    /// The application's motion-vector texture ([`crate::Setup::motion`]).
    Motion,
}

#[derive(Debug, Clone, Deserialize)]
#[serde(rename_all = "snake_case", tag = "op")]
pub enum LoadOp {
    /// Clear to `value`; `null`: the engine's own clear value (its clear color for the frame).
    Clear {
        value: Option<Vec<f64>>,
    },
    Load,
}

#[derive(Debug, Clone, Deserialize)]
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

#[derive(Debug, Clone, Deserialize)]
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

impl Manifest {
    /// Read `path` (a variant's `manifest.json`): the schema name and version first (an older or
    /// newer manifest gets a message naming its version, not the first field that differs), then
    /// the rest, typed with the failing field's path. Only a regular file within the default
    /// [`ReadLimits`] is read ([`crate::files`]).
    pub fn read(path: &Path) -> Result<Manifest, RuntimeError> {
        Manifest::read_with(path, &ReadLimits::default())
    }

    /// [`Manifest::read`] within `limits`.
    pub fn read_with(path: &Path, limits: &ReadLimits) -> Result<Manifest, RuntimeError> {
        let text = files::read_text(path, files::FileKind::Json, limits)?;
        Manifest::parse(path, &text)
    }

    /// [`Manifest::read`] of text already in memory (`path` names it in errors).
    pub fn parse(path: &Path, text: &str) -> Result<Manifest, RuntimeError> {
        let head: serde_json::Value =
            serde_json::from_str(text).map_err(|e| RuntimeError::Parse {
                path: path.to_owned(),
                field: ".".into(),
                message: format!("not JSON: {e}"),
            })?;
        let schema = head.get("schema").and_then(|v| v.as_str());
        if schema != Some(SCHEMA) {
            return Err(RuntimeError::Schema {
                path: path.to_owned(),
                found: schema.map_or_else(|| "(missing)".into(), |s| format!("{s:?}")),
            });
        }
        let version = head.get("version").and_then(|v| v.as_u64());
        if !version.is_some_and(|v| (OLDEST_VERSION..=VERSION).contains(&v)) {
            return Err(RuntimeError::Version {
                path: path.to_owned(),
                found: head
                    .get("version")
                    .map_or_else(|| "(missing)".into(), |v| v.to_string()),
            });
        }
        serde_path_to_error::deserialize(head).map_err(|e| RuntimeError::Parse {
            path: path.to_owned(),
            field: e.path().to_string(),
            message: e.inner().to_string(),
        })
    }

    /// The texture name playing `role` on frame `frame`: through `frames.ping_pong[frame % len]`,
    /// or a texture named `role` directly if no entry maps that role.
    pub fn texture_for<'a>(&'a self, role: &'a str, frame: usize) -> Option<&'a str> {
        let plan = &self.frames.ping_pong;
        if let Some(t) = plan
            .get(frame % plan.len().max(1))
            .and_then(|m| m.get(role))
        {
            return Some(t);
        }
        self.textures.iter().any(|t| t.name == role).then_some(role)
    }

    /// Whether the application's frame must hold what lies behind before the first pass: the
    /// first pass that draws to `frame` loads it (written with `--frame-load load`).
    pub fn loads_frame_first(&self) -> bool {
        self.passes
            .iter()
            .flat_map(|p| &p.colors)
            .find(|c| c.attachment == FRAME)
            .is_some_and(|c| matches!(c.load, LoadOp::Load))
    }

    /// Whether the application's depth target must hold its own depth before the first pass: the
    /// first pass loads it (written with `--depth-load load`).
    pub fn loads_depth_first(&self) -> bool {
        self.passes
            .first()
            .is_some_and(|p| matches!(p.depth.load, LoadOp::Load))
    }

    /// The `value` of the `delta_n` parameter: the refresh period the variant was emitted with.
    pub fn delta_n(&self) -> Option<u32> {
        self.params
            .fields
            .iter()
            .find(|f| f.name == DELTA_N)
            .and_then(|f| match f.value {
                ParamValue::Steady { value, .. } | ParamValue::Constant { value } => {
                    Some(value.round().max(1.0) as u32)
                }
                ParamValue::FrameIndex => None,
            })
    }
}
