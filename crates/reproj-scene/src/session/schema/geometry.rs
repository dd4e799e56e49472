//! The scene's objects: meshes (procedural, OBJ), glTF scenes to import, and animated transforms.

use std::path::PathBuf;

use schemars::JsonSchema;
use serde::{Deserialize, Serialize};

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
