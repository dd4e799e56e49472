//! The session document: its types, as serde reads them (field reference: `SESSION.md`).

use std::collections::BTreeMap;
use std::path::PathBuf;

use schemars::JsonSchema;
use serde::{Deserialize, Serialize};

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

/// The scene's objects, all drawn every frame with the same shader.
#[derive(Debug, Clone, Default, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct Geometry {
    pub objects: Vec<Object>,
}

/// One drawn object.
#[derive(Debug, Clone, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct Object {
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub name: Option<String>,
    pub mesh: Mesh,
    /// Model transform; default identity.
    #[serde(default)]
    pub transform: Transform,
    /// Face culling: `"back"` (default) or `"none"`.
    #[serde(default)]
    pub cull: Cull,
}

/// Face culling of an object (counter-clockwise triangles are front faces).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Hash, Serialize, Deserialize, JsonSchema)]
#[serde(rename_all = "lowercase")]
pub enum Cull {
    #[default]
    Back,
    None,
}

/// A mesh: procedural or loaded from an OBJ file. Written as a one-key object, e.g.
/// `{"sphere": {"radius": 1}}`.
#[derive(Debug, Clone, Serialize, Deserialize, JsonSchema)]
#[serde(rename_all = "snake_case", deny_unknown_fields)]
pub enum Mesh {
    /// UV sphere centred at the origin. `segments` around the Y axis (default 64), `rings` from
    /// pole to pole (default segments / 2).
    Sphere {
        radius: f32,
        #[serde(default = "default_segments")]
        segments: u32,
        #[serde(default)]
        rings: Option<u32>,
    },
    /// Torus around the Y axis: `major_radius` R (centre of the tube), `minor_radius` r (tube).
    Torus {
        major_radius: f32,
        minor_radius: f32,
        #[serde(default = "default_segments")]
        segments: u32,
        #[serde(default = "default_sides")]
        sides: u32,
    },
    /// Square in the XZ plane centred at the origin, normal +Y, side `size`; uv spans
    /// `[0, uv_scale]`. `subdivisions` quads per side (default 1).
    Plane {
        size: f32,
        #[serde(default = "default_one")]
        subdivisions: u32,
        #[serde(default = "default_uv_scale")]
        uv_scale: f32,
    },
    /// Axis-aligned box centred at the origin with side lengths `size` (x, y, z).
    Cube { size: [f32; 3] },
    /// Surface of revolution around the Y axis (chess-like pieces): `profile` is a list of
    /// `[radius, y]` points from bottom to top, revolved with `segments` steps.
    Lathe {
        profile: Vec<[f32; 2]>,
        #[serde(default = "default_segments")]
        segments: u32,
    },
    /// Wavefront OBJ file (path relative to the session file); triangulated. Missing normals are
    /// computed (smooth), missing uvs are 0, tangents come from the uvs.
    Obj {
        path: PathBuf,
        /// Uniform scale applied to the vertex positions. Default 1.
        #[serde(default = "default_uv_scale")]
        scale: f32,
    },
    /// One triangle primitive of a glTF 2.0 file's mesh, in the mesh's own space (the `gltf`
    /// scene import writes these). Missing normals are computed (smooth), missing uvs are 0.
    Gltf {
        path: PathBuf,
        #[serde(default)]
        mesh: usize,
        #[serde(default)]
        primitive: usize,
    },
}

/// A glTF 2.0 scene to import (`.gltf` with its buffers and images in files or data URIs, or
/// `.glb`). Every node of the scene that has a mesh becomes one object per triangle primitive,
/// with the node's world transform sampled at every frame (time = frame / fps) from the file's
/// animations (translation, rotation and scale channels; LINEAR, STEP and CUBICSPLINE).
#[derive(Debug, Clone, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct GltfScene {
    /// The file, relative to the session file.
    pub path: PathBuf,
    /// Scene index. Default: the file's default scene, else the first.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub scene: Option<usize>,
    /// Face culling of the imported objects. Default `"back"`; primitives whose material is
    /// double-sided are never culled.
    #[serde(default)]
    pub cull: Cull,
}

/// A texture of a glTF material, as a texture spec's `gltf` form.
#[derive(Debug, Clone, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct GltfTexture {
    /// The file, relative to the session file.
    pub path: PathBuf,
    /// Material index. Default 0.
    #[serde(default)]
    pub material: usize,
    /// Which of the material's textures. Default `base_color`.
    #[serde(default)]
    pub slot: MaterialSlot,
}

/// The textures a glTF material can name.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize, Deserialize, JsonSchema)]
#[serde(rename_all = "snake_case")]
pub enum MaterialSlot {
    #[default]
    BaseColor,
    MetallicRoughness,
    Normal,
    Occlusion,
    Emissive,
}

fn default_segments() -> u32 {
    64
}
fn default_sides() -> u32 {
    32
}
fn default_one() -> u32 {
    1
}
fn default_uv_scale() -> f32 {
    1.0
}

/// Animated model transform: `keys` interpolated over the frame index. The model matrix is
/// `translate * rotate * scale`.
#[derive(Debug, Clone, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct Transform {
    pub keys: Vec<TransformKey>,
}

impl Default for Transform {
    fn default() -> Self {
        Transform {
            keys: vec![TransformKey::default()],
        }
    }
}

/// One key of a [`Transform`].
#[derive(Debug, Clone, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct TransformKey {
    /// Frame index of the key (may be fractional). Default 0.
    #[serde(default)]
    pub frame: f32,
    /// World units. Default `[0, 0, 0]`.
    #[serde(default)]
    pub translation: [f32; 3],
    /// Default none.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub rotation: Option<Rotation>,
    /// A number (uniform) or `[x, y, z]`. Default 1.
    #[serde(default)]
    pub scale: Scale,
    /// The model matrix itself, 16 numbers column by column (as WGSL's `mat4x4<f32>` and
    /// `glam::Mat4::to_cols_array` hold it), in place of `translation`, `rotation` and `scale`:
    /// what an engine has, kept exactly (a session recorded with `reproj-runtime`'s capture
    /// writes one per frame). Affine (last row 0, 0, 0, 1). Default none.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub matrix: Option<[f32; 16]>,
}

impl Default for TransformKey {
    fn default() -> Self {
        TransformKey {
            frame: 0.0,
            translation: [0.0; 3],
            rotation: None,
            scale: Scale::default(),
            matrix: None,
        }
    }
}

/// A rotation, `{"axis_angle": {"axis": [0,1,0], "deg": 90}}` or `{"euler_deg": [x, y, z]}`
/// (applied in X, then Y, then Z order). Between two keys of the same form the parameters
/// (angle, Euler angles) are interpolated, so 0° → 360° is a full turn; between keys of different
/// forms the rotations are slerped.
#[derive(Debug, Clone, Serialize, Deserialize, JsonSchema)]
#[serde(rename_all = "snake_case", deny_unknown_fields)]
pub enum Rotation {
    AxisAngle { axis: [f32; 3], deg: f32 },
    EulerDeg([f32; 3]),
}

/// Scale of a transform key.
#[derive(Debug, Clone, Copy, Serialize, Deserialize, JsonSchema)]
#[serde(untagged)]
pub enum Scale {
    Uniform(f32),
    PerAxis([f32; 3]),
}

impl Default for Scale {
    fn default() -> Self {
        Scale::Uniform(1.0)
    }
}

/// Camera path: `{"keys": [...]}` or `{"orbit": {...}}`.
#[derive(Debug, Clone, Serialize, Deserialize, JsonSchema)]
#[serde(rename_all = "snake_case", deny_unknown_fields)]
pub enum CameraPath {
    Keys(Vec<CameraKey>),
    Orbit(CameraOrbit),
    /// `"gltf"`: the first camera of the `gltf` scene (perspective), following its node; turned
    /// into `keys`, one per frame, when the session is loaded.
    Gltf,
}

/// One camera key. Projection: perspective, right-handed, depth range [0, 1].
#[derive(Debug, Clone, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct CameraKey {
    #[serde(default)]
    pub frame: f32,
    pub eye: [f32; 3],
    pub target: [f32; 3],
    #[serde(default = "default_up")]
    pub up: [f32; 3],
    /// Vertical field of view in degrees. Default 45.
    #[serde(default = "default_fov")]
    pub fov_y_deg: f32,
    /// Default 0.1.
    #[serde(default = "default_near")]
    pub near: f32,
    /// Default 100.
    #[serde(default = "default_far")]
    pub far: f32,
}

/// A camera circling `center` at `radius` and `height` above it, looking at `center`; the angle
/// goes linearly from `start_deg` at frame 0 to `end_deg` at the last frame (0° is +X, 90° is +Z).
#[derive(Debug, Clone, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct CameraOrbit {
    #[serde(default)]
    pub center: [f32; 3],
    pub radius: f32,
    #[serde(default)]
    pub height: f32,
    #[serde(default)]
    pub start_deg: f32,
    #[serde(default)]
    pub end_deg: f32,
    #[serde(default = "default_up")]
    pub up: [f32; 3],
    #[serde(default = "default_fov")]
    pub fov_y_deg: f32,
    #[serde(default = "default_near")]
    pub near: f32,
    #[serde(default = "default_far")]
    pub far: f32,
}

fn default_up() -> [f32; 3] {
    [0.0, 1.0, 0.0]
}
fn default_fov() -> f32 {
    45.0
}
fn default_near() -> f32 {
    0.1
}
fn default_far() -> f32 {
    100.0
}

/// A moving point (the light): `{"keys": [{"frame": 0, "position": [x,y,z]}, ...]}` or
/// `{"orbit": {"center", "radius", "height", "start_deg", "end_deg"}}`.
#[derive(Debug, Clone, Serialize, Deserialize, JsonSchema)]
#[serde(rename_all = "snake_case", deny_unknown_fields)]
pub enum PointPath {
    Keys(Vec<PointKey>),
    Orbit(PointOrbit),
}

#[derive(Debug, Clone, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct PointKey {
    #[serde(default)]
    pub frame: f32,
    pub position: [f32; 3],
}

#[derive(Debug, Clone, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct PointOrbit {
    #[serde(default)]
    pub center: [f32; 3],
    pub radius: f32,
    #[serde(default)]
    pub height: f32,
    #[serde(default)]
    pub start_deg: f32,
    #[serde(default)]
    pub end_deg: f32,
}

/// A uniform field value: a constant (number, array, nested arrays: flattened in order),
/// `{"keys": [{"frame": f, "value": ...}, ...]}` interpolated per component, an object of a
/// struct's members by name (`{"color": [1, 1, 1], "intensity": 3}`, nesting as deep as the
/// structs do), or a list of such objects for an array of structs. An object whose only key is
/// `keys` is key frames, never a struct with a member named `keys`.
///
/// Read by hand rather than by serde's untagged enums so that a bad value names what was expected
/// and what was found.
#[derive(Debug, Clone, Serialize, JsonSchema)]
#[serde(untagged)]
pub enum UniformValue {
    Keys {
        keys: Vec<UniformKey>,
    },
    Const(Value),
    /// A struct's members by name.
    Struct(BTreeMap<String, UniformValue>),
    /// The elements of an array of structs.
    Array(Vec<UniformValue>),
}

/// One step of the path of a uniform leaf inside a (nested) struct: a member name or an index.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum PathStep<'a> {
    Member(&'a str),
    Index(usize),
}

/// The steps of a leaf path as reflection writes it (`sun.color`, `lights[2].position`).
pub fn path_steps(path: &str) -> Vec<PathStep<'_>> {
    let mut out = Vec::new();
    for part in path.split('.') {
        let (name, rest) = part.split_once('[').unwrap_or((part, ""));
        if !name.is_empty() {
            out.push(PathStep::Member(name));
        }
        for idx in rest.split('[') {
            if let Ok(i) = idx.trim_end_matches(']').parse() {
                out.push(PathStep::Index(i));
            }
        }
    }
    out
}

impl UniformValue {
    /// The value at `steps` below this one (`self` for no steps). An index into a constant list
    /// of numbers is not a step: arrays of scalars and vectors are one leaf.
    pub fn lookup(&self, steps: &[PathStep<'_>]) -> Option<&UniformValue> {
        let Some((first, rest)) = steps.split_first() else {
            return Some(self);
        };
        match (self, first) {
            (UniformValue::Struct(m), PathStep::Member(n)) => m.get(*n)?.lookup(rest),
            (UniformValue::Array(a), PathStep::Index(i)) => a.get(*i)?.lookup(rest),
            _ => None,
        }
    }

    /// Whether this is a leaf (numbers, constant or key-framed) rather than a struct or an array
    /// of structs.
    pub fn is_leaf(&self) -> bool {
        matches!(self, UniformValue::Keys { .. } | UniformValue::Const(_))
    }

    /// Read one value from JSON; the error says what was expected and what was found.
    pub fn from_json(v: serde_json::Value) -> Result<UniformValue, String> {
        use serde_json::Value as J;
        let kind = |v: &J| match v {
            J::Null => "null",
            J::Bool(_) => "a boolean",
            J::Number(_) => "a number",
            J::String(_) => "a string",
            J::Array(_) => "a list",
            J::Object(_) => "an object",
        };
        const EXPECTED: &str = "expected a number, a list of numbers, {\"keys\": [{\"frame\", \"value\"}, ...]}, an object of struct members or a list of such objects";
        match v {
            J::Object(m) if m.len() == 1 && m.contains_key("keys") => {
                let keys = m.into_iter().next().map(|(_, k)| k).unwrap_or(J::Null);
                serde_json::from_value(keys)
                    .map(|keys| UniformValue::Keys { keys })
                    .map_err(|e| format!("key frames: {e}"))
            }
            J::Object(m) => {
                let mut out = BTreeMap::new();
                for (k, v) in m {
                    let v = UniformValue::from_json(v).map_err(|e| format!("member `{k}`: {e}"))?;
                    out.insert(k, v);
                }
                Ok(UniformValue::Struct(out))
            }
            J::Array(items) if !items.is_empty() && items.iter().all(J::is_object) => {
                let mut out = Vec::new();
                for (i, v) in items.into_iter().enumerate() {
                    out.push(UniformValue::from_json(v).map_err(|e| format!("[{i}]: {e}"))?);
                }
                Ok(UniformValue::Array(out))
            }
            v => {
                let found = kind(&v);
                Value::from_json(&v)
                    .map(UniformValue::Const)
                    .ok_or_else(|| format!("{EXPECTED}; found {found}"))
            }
        }
    }
}

impl<'de> Deserialize<'de> for UniformValue {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        let v = serde_json::Value::deserialize(d)?;
        UniformValue::from_json(v).map_err(serde::de::Error::custom)
    }
}

/// One key of an animated uniform.
#[derive(Debug, Clone, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct UniformKey {
    #[serde(default)]
    pub frame: f32,
    pub value: Value,
}

/// A number or a (nested) list of numbers.
#[derive(Debug, Clone, Serialize, Deserialize, JsonSchema)]
#[serde(untagged)]
pub enum Value {
    Number(f64),
    List(Vec<Value>),
}

impl Value {
    /// A number or a (nested) list of numbers; `None` for anything else (an empty list is a list).
    fn from_json(v: &serde_json::Value) -> Option<Value> {
        match v {
            serde_json::Value::Number(n) => n.as_f64().map(Value::Number),
            serde_json::Value::Array(items) => items
                .iter()
                .map(Value::from_json)
                .collect::<Option<Vec<_>>>()
                .map(Value::List),
            _ => None,
        }
    }

    /// All numbers, depth first.
    pub fn flatten(&self) -> Vec<f64> {
        let mut out = Vec::new();
        fn go(v: &Value, out: &mut Vec<f64>) {
            match v {
                Value::Number(x) => out.push(*x),
                Value::List(l) => l.iter().for_each(|v| go(v, out)),
            }
        }
        go(self, &mut out);
        out
    }
}

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
