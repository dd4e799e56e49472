//! Session files: what a scene needs to drive a fragment shader, and nothing more.
//!
//! A session is a JSON document (`sessions/*.json`) with `"schema": "reproj.session"` and
//! `"version": 1`. The full field reference, with units and defaults, is `SESSION.md` beside this
//! crate's `Cargo.toml`; in short:
//!
//! ```json
//! {
//!   "schema": "reproj.session", "version": 1,
//!   "resolution": [256, 256], "frames": 150, "fps": 30,
//!   "geometry": { "objects": [ { "mesh": { "sphere": { "radius": 1.0, "segments": 64 } },
//!                                "transform": { "keys": [ { "frame": 0, "rotation": { "axis_angle": { "axis": [0,1,0], "deg": 0 } } },
//!                                                         { "frame": 149, "rotation": { "axis_angle": { "axis": [0,1,0], "deg": 90 } } } ] } } ] },
//!   "camera": { "orbit": { "center": [0,0,0], "radius": 3, "height": 0.5, "start_deg": 0, "end_deg": 30 } },
//!   "light":  { "keys": [ { "frame": 0, "position": [4,4,4] } ] },
//!   "uniforms": { "shininess": 32, "base_color": [1, 0.9, 0.8], "wobble": { "keys": [ { "frame": 0, "value": 0 }, { "frame": 149, "value": 1 } ] } },
//!   "textures": { "albedo_map": { "kind": "noise", "size": 256, "params": { "scale": 8 } } },
//!   "samplers": { "linear_sampler": { "filter": "linear", "address": "repeat" } },
//!   "inputs": { "0": "position", "1": "normal", "2": "uv" }
//! }
//! ```
//!
//! Every key-framed quantity is linearly interpolated over the frame index and held constant
//! before its first key and after its last one; a single key is a constant.
//! Loading reports malformed documents with the JSON path of the offending field
//! (`camera.keys[1].eye: invalid length 2, expected an array of length 3`).

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use glam::{Mat4, Quat, Vec3};
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

/// True for finite numbers > 0 (false for NaN).
fn positive(x: f32) -> bool {
    x.is_finite() && x > 0.0
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
#[derive(Debug, Clone, Serialize, Deserialize)]
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
    pub geometry: Geometry,
    pub camera: CameraPath,
    pub light: PointPath,
    /// Uniform struct fields by name (any struct, any uniform variable).
    #[serde(default)]
    pub uniforms: BTreeMap<String, UniformValue>,
    /// Textures by shader variable name.
    #[serde(default)]
    pub textures: BTreeMap<String, TextureSpec>,
    /// Samplers by shader variable name; one not listed is linear / repeat.
    #[serde(default)]
    pub samplers: BTreeMap<String, SamplerSpec>,
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
#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Geometry {
    pub objects: Vec<Object>,
}

/// One drawn object.
#[derive(Debug, Clone, Serialize, Deserialize)]
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
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Cull {
    #[default]
    Back,
    None,
}

/// A mesh: procedural or loaded from an OBJ file. Written as a one-key object, e.g.
/// `{"sphere": {"radius": 1}}`.
#[derive(Debug, Clone, Serialize, Deserialize)]
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
#[derive(Debug, Clone, Serialize, Deserialize)]
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
#[derive(Debug, Clone, Serialize, Deserialize)]
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
}

impl Default for TransformKey {
    fn default() -> Self {
        TransformKey {
            frame: 0.0,
            translation: [0.0; 3],
            rotation: None,
            scale: Scale::default(),
        }
    }
}

/// A rotation, `{"axis_angle": {"axis": [0,1,0], "deg": 90}}` or `{"euler_deg": [x, y, z]}`
/// (applied in X, then Y, then Z order). Between two keys of the same form the parameters
/// (angle, Euler angles) are interpolated, so 0° → 360° is a full turn; between keys of different
/// forms the rotations are slerped.
#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(rename_all = "snake_case", deny_unknown_fields)]
pub enum Rotation {
    AxisAngle { axis: [f32; 3], deg: f32 },
    EulerDeg([f32; 3]),
}

/// Scale of a transform key.
#[derive(Debug, Clone, Copy, Serialize, Deserialize)]
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

impl Scale {
    fn vec(self) -> Vec3 {
        match self {
            Scale::Uniform(s) => Vec3::splat(s),
            Scale::PerAxis(v) => Vec3::from(v),
        }
    }
}

/// Camera path: `{"keys": [...]}` or `{"orbit": {...}}`.
#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(rename_all = "snake_case", deny_unknown_fields)]
pub enum CameraPath {
    Keys(Vec<CameraKey>),
    Orbit(CameraOrbit),
}

/// One camera key. Projection: perspective, right-handed, depth range [0, 1].
#[derive(Debug, Clone, Serialize, Deserialize)]
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
#[derive(Debug, Clone, Serialize, Deserialize)]
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
#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(rename_all = "snake_case", deny_unknown_fields)]
pub enum PointPath {
    Keys(Vec<PointKey>),
    Orbit(PointOrbit),
}

#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PointKey {
    #[serde(default)]
    pub frame: f32,
    pub position: [f32; 3],
}

#[derive(Debug, Clone, Serialize, Deserialize)]
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

/// A uniform field value: a constant (number, array, nested arrays: flattened in order) or
/// `{"keys": [{"frame": f, "value": ...}, ...]}` interpolated per component.
#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(untagged)]
pub enum UniformValue {
    Keys { keys: Vec<UniformKey> },
    Const(Value),
}

/// One key of an animated uniform.
#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct UniformKey {
    #[serde(default)]
    pub frame: f32,
    pub value: Value,
}

/// A number or a (nested) list of numbers.
#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(untagged)]
pub enum Value {
    Number(f64),
    List(Vec<Value>),
}

impl Value {
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

/// A texture bound to a shader variable: generated (`kind`) or read from an image file (`file`,
/// or `faces` for a cube map). Exactly one of `kind`, `file`, `faces`.
#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TextureSpec {
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub kind: Option<TextureKind>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub file: Option<PathBuf>,
    /// Six images +X, −X, +Y, −Y, +Z, −Z for a `texture_cube`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub faces: Option<Vec<PathBuf>>,
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
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
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
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum TexFormat {
    Rgba8unorm,
    Rgba8unormSrgb,
    Rgba16float,
}

/// Parameters of generated textures; each kind reads the ones it needs.
#[derive(Debug, Clone, Serialize, Deserialize)]
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
#[derive(Debug, Clone, Serialize, Deserialize)]
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
}

impl Default for SamplerSpec {
    fn default() -> Self {
        SamplerSpec {
            filter: Filter::Linear,
            mipmap_filter: Filter::Linear,
            address: Address::Repeat,
            anisotropy: 1,
        }
    }
}

fn default_aniso() -> u16 {
    1
}

#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Filter {
    #[default]
    Linear,
    Nearest,
}

#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Address {
    #[default]
    Repeat,
    Clamp,
    Mirror,
}

/// Vertex attributes a fragment input can be fed from.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize)]
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

/// Camera state of one frame.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CameraState {
    pub eye: Vec3,
    pub target: Vec3,
    pub up: Vec3,
    pub fov_y_deg: f32,
    pub near: f32,
    pub far: f32,
    pub view: Mat4,
    pub proj: Mat4,
    pub view_proj: Mat4,
}

/// Everything the scene contributes to one frame.
#[derive(Debug, Clone)]
pub struct FrameState {
    pub frame: u32,
    /// Seconds since frame 0: `frame / fps`.
    pub time: f32,
    pub camera: CameraState,
    pub light_pos: Vec3,
    /// Model matrix of each object, in `geometry.objects` order.
    pub models: Vec<Mat4>,
}

/// Interpolation position within a sorted list of key frames: (index a, index b, t).
fn segment(frames: &[f32], f: f32) -> (usize, usize, f32) {
    let n = frames.len();
    if n == 1 || f <= frames[0] {
        return (0, 0, 0.0);
    }
    if f >= frames[n - 1] {
        return (n - 1, n - 1, 0.0);
    }
    let mut i = 0;
    while i + 1 < n && frames[i + 1] <= f {
        i += 1;
    }
    if i + 1 >= n {
        return (n - 1, n - 1, 0.0);
    }
    let span = frames[i + 1] - frames[i];
    let t = if span > 0.0 {
        (f - frames[i]) / span
    } else {
        0.0
    };
    (i, i + 1, t)
}

fn lerp3(a: [f32; 3], b: [f32; 3], t: f32) -> Vec3 {
    Vec3::from(a).lerp(Vec3::from(b), t)
}

fn rotation_quat(r: &Option<Rotation>) -> Quat {
    match r {
        None => Quat::IDENTITY,
        Some(Rotation::AxisAngle { axis, deg }) => {
            let a = Vec3::from(*axis);
            if a.length_squared() == 0.0 {
                Quat::IDENTITY
            } else {
                Quat::from_axis_angle(a.normalize(), deg.to_radians())
            }
        }
        Some(Rotation::EulerDeg(e)) => Quat::from_euler(
            glam::EulerRot::ZYX,
            e[2].to_radians(),
            e[1].to_radians(),
            e[0].to_radians(),
        ),
    }
}

fn rotation_lerp(a: &Option<Rotation>, b: &Option<Rotation>, t: f32) -> Quat {
    if t == 0.0 {
        return rotation_quat(a);
    }
    match (a, b) {
        (
            Some(Rotation::AxisAngle { axis: xa, deg: da }),
            Some(Rotation::AxisAngle { axis: xb, deg: db }),
        ) => rotation_quat(&Some(Rotation::AxisAngle {
            axis: lerp3(*xa, *xb, t).into(),
            deg: da + (db - da) * t,
        })),
        (Some(Rotation::EulerDeg(ea)), Some(Rotation::EulerDeg(eb))) => {
            rotation_quat(&Some(Rotation::EulerDeg(lerp3(*ea, *eb, t).into())))
        }
        (None, Some(Rotation::AxisAngle { axis, deg })) => {
            rotation_quat(&Some(Rotation::AxisAngle {
                axis: *axis,
                deg: deg * t,
            }))
        }
        (Some(Rotation::AxisAngle { axis, deg }), None) => {
            rotation_quat(&Some(Rotation::AxisAngle {
                axis: *axis,
                deg: deg * (1.0 - t),
            }))
        }
        (None, Some(Rotation::EulerDeg(e))) => {
            rotation_quat(&Some(Rotation::EulerDeg((Vec3::from(*e) * t).into())))
        }
        (Some(Rotation::EulerDeg(e)), None) => rotation_quat(&Some(Rotation::EulerDeg(
            (Vec3::from(*e) * (1.0 - t)).into(),
        ))),
        _ => rotation_quat(a).slerp(rotation_quat(b), t),
    }
}

impl Transform {
    /// Model matrix at a (fractional) frame index.
    pub fn matrix(&self, frame: f32) -> Mat4 {
        let frames: Vec<f32> = self.keys.iter().map(|k| k.frame).collect();
        let (i, j, t) = segment(&frames, frame);
        let (a, b) = (&self.keys[i], &self.keys[j]);
        let tr = lerp3(a.translation, b.translation, t);
        let sc = a.scale.vec().lerp(b.scale.vec(), t);
        let rot = rotation_lerp(&a.rotation, &b.rotation, t);
        Mat4::from_scale_rotation_translation(sc, rot, tr)
    }
}

fn orbit_angle(start: f32, end: f32, frame: f32, frames: u32) -> f32 {
    let last = frames.saturating_sub(1).max(1) as f32;
    let t = (frame / last).clamp(0.0, 1.0);
    (start + (end - start) * t).to_radians()
}

impl PointPath {
    /// Position at a frame.
    pub fn position(&self, frame: f32, frames: u32) -> Vec3 {
        match self {
            PointPath::Keys(keys) => {
                let fs: Vec<f32> = keys.iter().map(|k| k.frame).collect();
                let (i, j, t) = segment(&fs, frame);
                lerp3(keys[i].position, keys[j].position, t)
            }
            PointPath::Orbit(o) => {
                let a = orbit_angle(o.start_deg, o.end_deg, frame, frames);
                Vec3::from(o.center) + Vec3::new(o.radius * a.cos(), o.height, o.radius * a.sin())
            }
        }
    }
}

impl CameraPath {
    /// Camera at a frame, for an image of `aspect` = width / height.
    pub fn state(&self, frame: f32, frames: u32, aspect: f32) -> CameraState {
        let (eye, target, up, fov, near, far) = match self {
            CameraPath::Keys(keys) => {
                let fs: Vec<f32> = keys.iter().map(|k| k.frame).collect();
                let (i, j, t) = segment(&fs, frame);
                let (a, b) = (&keys[i], &keys[j]);
                (
                    lerp3(a.eye, b.eye, t),
                    lerp3(a.target, b.target, t),
                    lerp3(a.up, b.up, t),
                    a.fov_y_deg + (b.fov_y_deg - a.fov_y_deg) * t,
                    a.near + (b.near - a.near) * t,
                    a.far + (b.far - a.far) * t,
                )
            }
            CameraPath::Orbit(o) => {
                let a = orbit_angle(o.start_deg, o.end_deg, frame, frames);
                let c = Vec3::from(o.center);
                (
                    c + Vec3::new(o.radius * a.cos(), o.height, o.radius * a.sin()),
                    c,
                    Vec3::from(o.up),
                    o.fov_y_deg,
                    o.near,
                    o.far,
                )
            }
        };
        let view = glam::camera::rh::view::look_at_mat4(eye, target, up);
        let proj =
            glam::camera::rh::proj::directx::perspective(fov.to_radians(), aspect, near, far);
        CameraState {
            eye,
            target,
            up,
            fov_y_deg: fov,
            near,
            far,
            view,
            proj,
            view_proj: proj * view,
        }
    }
}

impl UniformValue {
    /// Value at a frame, flattened (see [`Value::flatten`]).
    pub fn at(&self, frame: f32) -> Vec<f64> {
        match self {
            UniformValue::Const(v) => v.flatten(),
            UniformValue::Keys { keys } => {
                let fs: Vec<f32> = keys.iter().map(|k| k.frame).collect();
                let (i, j, t) = segment(&fs, frame);
                let a = keys[i].value.flatten();
                let b = keys[j].value.flatten();
                a.iter()
                    .zip(b.iter())
                    .map(|(x, y)| x + (y - x) * t as f64)
                    .collect()
            }
        }
    }

    /// Number of components (of the first key for key-framed values).
    pub fn len(&self) -> usize {
        match self {
            UniformValue::Const(v) => v.flatten().len(),
            UniformValue::Keys { keys } => {
                keys.first().map(|k| k.value.flatten().len()).unwrap_or(0)
            }
        }
    }

    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }
}

impl Session {
    /// Read, parse and validate a session file. Relative paths inside it resolve against its
    /// directory.
    pub fn load(path: impl AsRef<Path>) -> Result<Session, SessionError> {
        let path = path.as_ref();
        let text = std::fs::read_to_string(path).map_err(|source| reproj_io::ReadError::Io {
            path: path.to_owned(),
            source,
        })?;
        let base = path.parent().map(Path::to_owned).unwrap_or_default();
        Self::from_json(&text, path, &base)
    }

    /// Parse and validate session JSON text. `path` is used in messages, `base_dir` resolves
    /// relative paths.
    pub fn from_json(text: &str, path: &Path, base_dir: &Path) -> Result<Session, SessionError> {
        let mut s: Session = reproj_io::parse_json(text, path, &SESSION_KIND)?;
        s.base_dir = base_dir.to_owned();
        s.path = path.to_owned();
        s.validate()?;
        Ok(s)
    }

    fn invalid(&self, field: impl Into<String>, message: impl Into<String>) -> SessionError {
        SessionError::Invalid {
            path: self.path.clone(),
            field: field.into(),
            message: message.into(),
        }
    }

    /// Range and consistency checks (called by [`Session::load`]).
    pub fn validate(&mut self) -> Result<(), SessionError> {
        if self.schema != SESSION_SCHEMA {
            return Err(self.invalid(
                "schema",
                format!("expected \"{SESSION_SCHEMA}\", found \"{}\"", self.schema),
            ));
        }
        if self.version != SESSION_VERSION {
            return Err(self.invalid(
                "version",
                format!(
                    "unsupported version {} (this reproj reads version {SESSION_VERSION})",
                    self.version
                ),
            ));
        }
        let [w, h] = self.resolution;
        if w == 0 || h == 0 || w > 8192 || h > 8192 {
            return Err(self.invalid(
                "resolution",
                format!("{w}×{h} is out of range (1..=8192 each)"),
            ));
        }
        if self.frames == 0 {
            return Err(self.invalid("frames", "must be at least 1"));
        }
        if !(self.fps.is_finite() && self.fps > 0.0) {
            return Err(self.invalid("fps", "must be a positive number"));
        }
        if self.geometry.objects.is_empty() {
            return Err(self.invalid("geometry.objects", "the scene has no objects"));
        }
        for (i, o) in self.geometry.objects.iter_mut().enumerate() {
            let f = format!("geometry.objects[{i}]");
            if o.transform.keys.is_empty() {
                return Err(SessionError::Invalid {
                    path: self.path.clone(),
                    field: format!("{f}.transform.keys"),
                    message: "needs at least one key".into(),
                });
            }
            o.transform.keys.sort_by(|a, b| a.frame.total_cmp(&b.frame));
            let bad = |m: &str| SessionError::Invalid {
                path: self.path.clone(),
                field: format!("{f}.mesh"),
                message: m.to_owned(),
            };
            match &o.mesh {
                Mesh::Sphere {
                    radius,
                    segments,
                    rings,
                } => {
                    if !positive(*radius) || *segments < 3 || rings.is_some_and(|r| r < 2) {
                        return Err(bad("sphere needs radius > 0, segments ≥ 3, rings ≥ 2"));
                    }
                }
                Mesh::Torus {
                    major_radius,
                    minor_radius,
                    segments,
                    sides,
                } => {
                    if !(positive(*major_radius) && positive(*minor_radius))
                        || *segments < 3
                        || *sides < 3
                    {
                        return Err(bad("torus needs radii > 0, segments ≥ 3, sides ≥ 3"));
                    }
                }
                Mesh::Plane {
                    size, subdivisions, ..
                } => {
                    if !positive(*size) || *subdivisions == 0 || *subdivisions > 1024 {
                        return Err(bad("plane needs size > 0 and 1 ≤ subdivisions ≤ 1024"));
                    }
                }
                Mesh::Cube { size } => {
                    if size.iter().any(|s| !positive(*s)) {
                        return Err(bad("cube needs every size > 0"));
                    }
                }
                Mesh::Lathe { profile, segments } => {
                    if profile.len() < 2 || *segments < 3 || profile.iter().any(|p| p[0] < 0.0) {
                        return Err(bad(
                            "lathe needs ≥ 2 profile points with radius ≥ 0 and segments ≥ 3",
                        ));
                    }
                }
                Mesh::Obj { .. } => {}
            }
            if [
                matches!(&o.mesh, Mesh::Sphere { segments, rings, .. } if *segments > 4096 || rings.is_some_and(|r| r > 4096)),
                matches!(&o.mesh, Mesh::Torus { segments, sides, .. } if *segments > 4096 || *sides > 4096),
                matches!(&o.mesh, Mesh::Lathe { segments, .. } if *segments > 4096),
            ]
            .iter()
            .any(|b| *b)
            {
                return Err(bad("at most 4096 segments"));
            }
        }
        match &mut self.camera {
            CameraPath::Keys(keys) => {
                if keys.is_empty() {
                    return Err(self.invalid("camera.keys", "needs at least one key"));
                }
                keys.sort_by(|a, b| a.frame.total_cmp(&b.frame));
                for (i, k) in keys.iter().enumerate() {
                    if !(k.near > 0.0 && k.far > k.near && k.fov_y_deg > 0.0 && k.fov_y_deg < 180.0)
                    {
                        return Err(SessionError::Invalid {
                            path: self.path.clone(),
                            field: format!("camera.keys[{i}]"),
                            message: "needs 0 < near < far and 0 < fov_y_deg < 180".into(),
                        });
                    }
                    if Vec3::from(k.eye) == Vec3::from(k.target) {
                        return Err(SessionError::Invalid {
                            path: self.path.clone(),
                            field: format!("camera.keys[{i}]"),
                            message: "eye and target coincide".into(),
                        });
                    }
                }
            }
            CameraPath::Orbit(o) => {
                if !(o.near > 0.0 && o.far > o.near && o.fov_y_deg > 0.0 && o.fov_y_deg < 180.0) {
                    return Err(self.invalid(
                        "camera.orbit",
                        "needs 0 < near < far and 0 < fov_y_deg < 180",
                    ));
                }
                if !positive(o.radius) {
                    return Err(self.invalid("camera.orbit.radius", "must be > 0"));
                }
            }
        }
        if let PointPath::Keys(keys) = &mut self.light {
            if keys.is_empty() {
                return Err(self.invalid("light.keys", "needs at least one key"));
            }
            keys.sort_by(|a, b| a.frame.total_cmp(&b.frame));
        }
        for (name, u) in self.uniforms.iter_mut() {
            if let UniformValue::Keys { keys } = u {
                if keys.is_empty() {
                    return Err(SessionError::Invalid {
                        path: self.path.clone(),
                        field: format!("uniforms.{name}.keys"),
                        message: "needs at least one key".into(),
                    });
                }
                keys.sort_by(|a, b| a.frame.total_cmp(&b.frame));
                let n = keys[0].value.flatten().len();
                if keys.iter().any(|k| k.value.flatten().len() != n) {
                    return Err(SessionError::Invalid {
                        path: self.path.clone(),
                        field: format!("uniforms.{name}.keys"),
                        message: "every key needs the same number of components".into(),
                    });
                }
            }
        }
        for (name, t) in &self.textures {
            let forms =
                t.kind.is_some() as u32 + t.file.is_some() as u32 + t.faces.is_some() as u32;
            if forms != 1 {
                return Err(self.invalid(
                    format!("textures.{name}"),
                    "give exactly one of `kind`, `file`, `faces`",
                ));
            }
            if let Some(f) = &t.faces
                && f.len() != 6
            {
                return Err(self.invalid(
                    format!("textures.{name}.faces"),
                    "needs six images (+X, −X, +Y, −Y, +Z, −Z)",
                ));
            }
            if t.size == 0 || t.size > 4096 {
                return Err(self.invalid(format!("textures.{name}.size"), "must be in 1..=4096"));
            }
        }
        for (name, s) in &self.samplers {
            if s.anisotropy == 0 || s.anisotropy > 16 {
                return Err(
                    self.invalid(format!("samplers.{name}.anisotropy"), "must be in 1..=16")
                );
            }
        }
        Ok(())
    }

    /// Width / height.
    pub fn aspect(&self) -> f32 {
        self.resolution[0] as f32 / self.resolution[1] as f32
    }

    /// The scene at frame `frame` (any index; paths clamp outside their keys).
    pub fn frame_state(&self, frame: u32) -> FrameState {
        let f = frame as f32;
        FrameState {
            frame,
            time: f / self.fps,
            camera: self.camera.state(f, self.frames, self.aspect()),
            light_pos: self.light.position(f, self.frames),
            models: self
                .geometry
                .objects
                .iter()
                .map(|o| o.transform.matrix(f))
                .collect(),
        }
    }

    /// Resolve a path from the session file against its directory.
    pub fn resolve(&self, p: &Path) -> PathBuf {
        if p.is_absolute() {
            p.to_owned()
        } else {
            self.base_dir.join(p)
        }
    }

    /// A short name for reports: the file name, else the description.
    pub fn display_name(&self) -> String {
        if self.path.as_os_str().is_empty() {
            self.description
                .clone()
                .unwrap_or_else(|| "(inline session)".into())
        } else {
            self.path.display().to_string()
        }
    }
}
