//! The session document: its types, as serde reads them (field reference: `SESSION.md`).
//!
//! The document's root ([`Session`]), its error type and the fragment inputs' attributes are here;
//! the rest, a file per part of the document: `geometry.rs` (objects, meshes, glTF scenes,
//! transforms), `paths.rs` (the camera's and the light's paths), `uniforms.rs` (uniform and
//! storage-buffer values, constant or key-framed) and `textures.rs` (textures, samplers, depth
//! passes).

mod geometry;
mod paths;
mod textures;
mod uniforms;

use std::collections::BTreeMap;
use std::path::PathBuf;

use schemars::JsonSchema;
use serde::{Deserialize, Serialize};

pub use geometry::*;
pub use paths::*;
pub use textures::*;
pub use uniforms::*;

/// The value of the `schema` field.
pub const SESSION_SCHEMA: &str = "reproj.session";
/// The supported `version`.
pub const SESSION_VERSION: u32 = 1;

/// What [`reproj_io::parse_json`] expects of a session file.
pub const SESSION_KIND: reproj_io::Kind = reproj_io::Kind {
    schema: SESSION_SCHEMA,
    versions: SESSION_VERSION..=SESSION_VERSION,
    hint: "",
};

/// Errors loading or validating a session file. Every message names the file and, where it applies,
/// the JSON path of the field at fault.
#[derive(Debug, thiserror::Error)]
pub enum SessionError {
    /// The file cannot be read, is not JSON, is not a session of a version this reproj reads, or
    /// does not match the schema (the error names the field, e.g. `geometry.objects[0].mesh`).
    #[error(transparent)]
    Read(#[from] reproj_io::ReadError),
    /// The JSON matched the schema but a value is out of range or inconsistent.
    #[error("{path}: field `{field}`: {message}")]
    Invalid {
        path: PathBuf,
        field: String,
        message: String,
    },
}

fn default_fps() -> f32 {
    30.0
}
fn default_background() -> [f32; 4] {
    [0.0, 0.0, 0.0, 1.0]
}
fn default_inputs() -> BTreeMap<u32, Attribute> {
    BTreeMap::from([
        (0, Attribute::Position),
        (1, Attribute::Normal),
        (2, Attribute::Uv),
        (3, Attribute::Tangent),
        (4, Attribute::ObjectPosition),
    ])
}

/// A session: resolution, frame count, scene and the data bound to the shader's interface.
#[derive(Debug, Clone, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct Session {
    /// Always `"reproj.session"`.
    pub schema: String,
    /// Always 1.
    pub version: u32,
    /// Free text.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub description: Option<String>,
    /// Render target size in pixels, `[width, height]`.
    pub resolution: [u32; 2],
    /// Number of frames to render.
    pub frames: u32,
    /// Frames per second: `time = frame / fps` seconds. Default 30.
    #[serde(default = "default_fps")]
    pub fps: f32,
    /// Clear color of the frame (linear RGBA). Default `[0, 0, 0, 1]`.
    #[serde(default = "default_background")]
    pub background: [f32; 4],
    /// The objects drawn; may be left out when `gltf` brings them.
    #[serde(default)]
    pub geometry: Geometry,
    /// A glTF 2.0 scene whose mesh nodes become objects of `geometry` (animated by the file's
    /// node animations), and whose first camera `"camera": "gltf"` follows.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub gltf: Option<GltfScene>,
    pub camera: CameraPath,
    pub light: PointPath,
    /// Uniform struct fields by name (any struct, any uniform variable).
    #[serde(default)]
    pub uniforms: BTreeMap<String, UniformValue>,
    /// Textures by shader variable name.
    #[serde(default)]
    pub textures: BTreeMap<String, TextureSpec>,
    /// Samplers by shader variable name; one not listed is linear / repeat (a comparison sampler:
    /// linear / clamp, compare `less_equal`).
    #[serde(default)]
    pub samplers: BTreeMap<String, SamplerSpec>,
    /// Read-only storage buffers (`var<storage, read>`) by shader variable name: the buffer's
    /// contents as a uniform value — an object of the struct's members (nested structs as
    /// objects, arrays of structs as lists of objects, a runtime-sized array as long as the list
    /// given), or a list for a buffer that is an array. Leaves may be key-framed.
    #[serde(default)]
    pub buffers: BTreeMap<String, UniformValue>,
    /// Depth textures (`texture_depth_2d`) by shader variable name, each rendered every frame by
    /// a depth-only pass over the scene's objects before the shader's own pass: a shadow map
    /// from a light's view-projection, or a depth pre-pass from the camera.
    #[serde(default)]
    pub depth_passes: BTreeMap<String, DepthPass>,
    /// Fragment input `@location` → vertex attribute. Default: the shaders/README.md convention
    /// (0 position, 1 normal, 2 uv, 3 tangent, 4 object_position).
    #[serde(default = "default_inputs")]
    pub inputs: BTreeMap<u32, Attribute>,
    /// Directory that relative paths (OBJ files, images) are resolved against: the session file's
    /// directory. Not part of the file.
    #[serde(skip)]
    pub base_dir: PathBuf,
    /// Where the session was loaded from (for messages). Not part of the file.
    #[serde(skip)]
    pub path: PathBuf,
}

/// Vertex attributes a fragment input can be fed from.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize, JsonSchema)]
#[serde(rename_all = "snake_case")]
pub enum Attribute {
    /// World-space position (vec3; a vec4 input gets w = 1).
    Position,
    /// World-space normal, normalized per vertex (vec3; vec4 gets w = 0).
    Normal,
    /// Texture coordinates (vec2).
    Uv,
    /// World-space tangent along +u, normalized per vertex, w = handedness ±1 (vec4).
    Tangent,
    /// Object-space position (vec3; vec4 gets w = 1).
    ObjectPosition,
    /// Object-space normal (vec3; vec4 gets w = 0).
    ObjectNormal,
}

impl Attribute {
    /// Natural component count.
    pub fn components(self) -> u32 {
        match self {
            Attribute::Uv => 2,
            Attribute::Tangent => 4,
            _ => 3,
        }
    }
    /// Name as written in session files.
    pub fn name(self) -> &'static str {
        match self {
            Attribute::Position => "position",
            Attribute::Normal => "normal",
            Attribute::Uv => "uv",
            Attribute::Tangent => "tangent",
            Attribute::ObjectPosition => "object_position",
            Attribute::ObjectNormal => "object_normal",
        }
    }
}
