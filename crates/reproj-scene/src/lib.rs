//! reproj scenes: what a recorded session puts in front of a fragment shader, GPU-free. The
//! replay's renderer draws it; a host that renders a session itself (`examples/host`, the
//! runtime's test app) builds the same scene from it.
//!
//! Layered bottom-up, each module importing only from those above it in this list:
//!
//! - [`reflect`]: the fragment entry point's interface from the naga module: inputs, uniform
//!   structs with their layouts, textures, samplers, storage buffers, by group and binding.
//! - [`session`] (schema in `SESSION.md`): the session's types, validation
//!   ([`Session::validate`] only checks) and animation (the scene at a frame).
//! - [`geometry`]: the vertex layout every mesh source fills.
//! - `gltf`: a session's glTF scene expanded into objects and keys; primitives and material
//!   textures read from the file, one import per file per process. Feature `gltf` (default);
//!   without it (`gltf/absent.rs`; with it `gltf/present.rs`) a session naming a glTF file is refused when loaded.
//! - [`mesh`]: procedural shapes, OBJ files, glTF primitives ([`mesh::build`]).
//! - [`textures`]: procedural, file, cube, array and glTF textures ([`textures::build`]); image
//!   files through `image` with feature `images` (default), refused by name without it.
//! - `load`: [`Session::load`] and [`Session::from_json`] (parse, expand the glTF scene, sort
//!   keys, validate).
//! - [`uniforms`]: the bytes of the shader's own uniform and storage buffers at a frame.
//! - [`vertex`]: the vertex stage's per-object uniform and the WGSL feeding each fragment input
//!   from its session attribute, shared by the replay's vertex module and the example host's.
//! - [`init`]: a starting session from a shader's interface (`reproj session init`).

mod load;

pub mod geometry;
#[cfg_attr(feature = "gltf", path = "gltf/present.rs")]
#[cfg_attr(not(feature = "gltf"), path = "gltf/absent.rs")]
mod gltf;
pub mod init;
pub mod mesh;
pub mod reflect;
pub mod session;
pub mod textures;
pub mod uniforms;
pub mod vertex;

pub use session::{Session, SessionError};
