//! The session's meshes and textures on the GPU, kept by the [`Renderer`] and keyed by their
//! description in the session, so that the replays of one session (`analyze` makes dozens) build
//! and upload them once.
//!
//! A key is the JSON of the mesh or texture spec (with the shader's texture dimensionality), plus
//! the session's directory when the spec names files: files are read once per renderer, so a file
//! changed on disk during the renderer's life is not seen again. Everything built stays until the
//! renderer is dropped. Per-object transform buffers and uniforms are per replay, not cached.

use std::collections::HashMap;
use std::sync::Mutex;
use std::sync::atomic::{AtomicU64, Ordering};

use crate::error::ReplayError;
use crate::gpu::Gpu;
use reproj_scene::mesh;
use reproj_scene::reflect::TexDim;
use reproj_scene::session::{Mesh, Session, TextureSpec};
use reproj_scene::textures;
use reproj_scene_gpu::MeshBuffers;

/// Meshes and texture views built so far, by key.
#[derive(Debug, Default)]
pub(crate) struct Assets {
    meshes: Mutex<HashMap<String, MeshBuffers>>,
    textures: Mutex<HashMap<String, wgpu::TextureView>>,
    /// Builds skipped because the asset was already built.
    hits: AtomicU64,
}

/// `spec`'s JSON, with the session's directory when `files` (paths are resolved against it).
fn key(spec: &impl serde::Serialize, extra: &str, files: bool, session: &Session) -> String {
    let json = serde_json::to_string(spec).unwrap_or_default();
    if files {
        format!("{extra}|{}|{json}", session.base_dir.display())
    } else {
        format!("{extra}|{json}")
    }
}

impl Assets {
    /// Builds skipped so far because the asset was already on the GPU.
    pub(crate) fn hits(&self) -> u64 {
        self.hits.load(Ordering::Relaxed)
    }

    fn hit(&self) {
        self.hits.fetch_add(1, Ordering::Relaxed);
    }

    /// The vertex and index buffers of `m`, built on first use.
    pub(crate) fn mesh(
        &self,
        r: &Gpu,
        session: &Session,
        m: &Mesh,
    ) -> Result<MeshBuffers, ReplayError> {
        let k = key(
            m,
            "mesh",
            matches!(m, Mesh::Obj { .. } | Mesh::Gltf { .. }),
            session,
        );
        let mut cache = self.meshes.lock().unwrap_or_else(|e| e.into_inner());
        if let Some(g) = cache.get(&k) {
            self.hit();
            return Ok(g.clone());
        }
        let data = mesh::build(session, m).map_err(|message| ReplayError::Asset { message })?;
        let g = reproj_scene_gpu::mesh_buffers(&r.device, &data);
        cache.insert(k, g.clone());
        Ok(g)
    }

    /// The view of texture `name` built from `spec` for a shader variable of dimensionality
    /// `dim`, built and uploaded on first use.
    pub(crate) fn texture(
        &self,
        r: &Gpu,
        session: &Session,
        name: &str,
        spec: &TextureSpec,
        dim: TexDim,
    ) -> Result<wgpu::TextureView, ReplayError> {
        let files = spec.file.is_some()
            || spec.faces.is_some()
            || spec.gltf.is_some()
            || spec
                .layers
                .iter()
                .flatten()
                .any(|l| l.file.is_some() || l.faces.is_some());
        let k = key(spec, &format!("{dim:?}"), files, session);
        let mut cache = self.textures.lock().unwrap_or_else(|e| e.into_inner());
        if let Some(v) = cache.get(&k) {
            self.hit();
            return Ok(v.clone());
        }
        let data = textures::build(session, name, spec, dim)
            .map_err(|message| ReplayError::Asset { message })?;
        let view = reproj_scene_gpu::texture(&r.device, &r.queue, name, &data, dim);
        cache.insert(k, view.clone());
        Ok(view)
    }
}
