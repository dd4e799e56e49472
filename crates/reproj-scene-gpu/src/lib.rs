//! The recorded scene on a wgpu device: each object's mesh and per-frame transforms, the session's
//! textures and samplers, uniform and storage buffers, and its depth passes (shadow maps, depth
//! pre-passes) — what is drawn before and around a shader's own pass.
//!
//! Two programs draw a session: the replay (`reproj-replay`, every figure reproj prints) and the
//! example host (an engine running an emitted variant through `reproj-runtime`). Both upload and
//! draw the scene through this crate, so the host's frames equal to the replay's check what
//! differs between them — the runtime and the manifest — not two copies of the scene.
//!
//! GPU objects only: the data (meshes, texels, uniform bytes, view-projections) is built by
//! `reproj-scene`, whose errors the caller reports; wgpu's validation errors surface in the
//! caller's error scope.

pub mod depth;
pub mod object;
pub mod sampler;
pub mod upload;

pub use depth::DepthPass;
pub use object::{SceneObject, Transforms, buffer, transform_layout};
pub use sampler::sampler_descriptor;
pub use upload::{MeshBuffers, mesh_buffers, texture, texture_format, view_dimension};

/// The depth format of the depth passes' textures (and of the frame's depth target where the
/// caller wants it the same).
pub const DEPTH_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Depth32Float;
