//! How the camera and the light move: key frames or an orbit.

use schemars::JsonSchema;
use serde::{Deserialize, Serialize};

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
