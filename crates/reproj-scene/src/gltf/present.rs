//! glTF 2.0 scenes in sessions, through the `gltf` crate.
//!
//! A session's `gltf` field imports a scene when the session is loaded ([`expand`]): every node
//! with a mesh becomes one object per triangle primitive (`Mesh::Gltf`), its world transform
//! sampled at every frame from the file's animations, and `"camera": "gltf"` becomes one camera
//! key per frame from the first camera node. The renderer then sees an ordinary session; the mesh
//! data ([`mesh`]) and material textures ([`texture`]) are read from the file when the replay
//! builds its GPU assets. A file is imported once per process ([`import`]).

use std::collections::HashMap;
use std::path::{Path, PathBuf};
use std::sync::{Arc, Mutex, OnceLock};

use glam::{Mat4, Vec3};

use crate::geometry::{MeshData, Vertex, compute_tangents, smooth_normals};
use crate::session::{
    CameraKey, CameraPath, Cull, GltfTexture, MaterialSlot, Mesh, Object, Session, SessionError,
    Transform, TransformKey,
};

// This file is loaded by a `path` attribute (`gltf/absent.rs` stands in without the feature),
// so its submodule's path is spelt out.
#[path = "present/animation.rs"]
mod animation;

use animation::{channels, key, locals_at, world};

/// A file's document, buffers and decoded images.
pub(crate) struct Imported {
    doc: gltf::Document,
    buffers: Vec<gltf::buffer::Data>,
    images: Vec<gltf::image::Data>,
}

type Cache = Mutex<HashMap<PathBuf, Arc<Imported>>>;

/// Import `path` (resolved against the session), once per process.
pub(crate) fn import(session: &Session, path: &Path) -> Result<Arc<Imported>, String> {
    static CACHE: OnceLock<Cache> = OnceLock::new();
    let full = session.resolve(path)?;
    let cache = CACHE.get_or_init(Default::default);
    if let Some(i) = cache.lock().unwrap_or_else(|e| e.into_inner()).get(&full) {
        return Ok(i.clone());
    }
    // Only a regular file within the size limit: a pipe or a device would block or never end.
    reproj_io::check_input(&full, reproj_io::InputKind::Asset).map_err(|e| e.to_string())?;
    // The glTF's own files (buffers, images) obey the session's folder rule too.
    let gltf =
        gltf::Gltf::open(&full).map_err(|e| format!("cannot import {}: {e}", full.display()))?;
    let dir = path.parent().unwrap_or(Path::new(""));
    let uris = gltf
        .buffers()
        .filter_map(|b| match b.source() {
            gltf::buffer::Source::Uri(u) => Some(u.to_string()),
            gltf::buffer::Source::Bin => None,
        })
        .chain(gltf.images().filter_map(|i| match i.source() {
            gltf::image::Source::Uri { uri, .. } => Some(uri.to_string()),
            gltf::image::Source::View { .. } => None,
        }));
    for uri in uris.filter(|u| !u.starts_with("data:")) {
        let file = session
            .resolve(&dir.join(&uri))
            .map_err(|e| format!("{}: {e}", path.display()))?;
        reproj_io::check_input(&file, reproj_io::InputKind::Asset)
            .map_err(|e| format!("{}: {e}", path.display()))?;
    }
    let (doc, buffers, images) =
        gltf::import(&full).map_err(|e| format!("cannot import {}: {e}", full.display()))?;
    let imported = Arc::new(Imported {
        doc,
        buffers,
        images,
    });
    cache
        .lock()
        .unwrap_or_else(|e| e.into_inner())
        .insert(full, imported.clone());
    Ok(imported)
}

/// Triangles of primitive `primitive` of mesh `mesh`, in the mesh's space.
pub(crate) fn mesh(
    session: &Session,
    path: &Path,
    mesh: usize,
    primitive: usize,
) -> Result<MeshData, String> {
    let g = import(session, path)?;
    let file = path.display();
    let m = g
        .doc
        .meshes()
        .nth(mesh)
        .ok_or_else(|| format!("{file} has no mesh {mesh}"))?;
    let p = m
        .primitives()
        .nth(primitive)
        .ok_or_else(|| format!("{file}: mesh {mesh} has no primitive {primitive}"))?;
    if p.mode() != gltf::mesh::Mode::Triangles {
        return Err(format!(
            "{file}: mesh {mesh} primitive {primitive} draws {:?}; reproj draws triangles",
            p.mode()
        ));
    }
    let reader = p.reader(|b| g.buffers.get(b.index()).map(|d| &d.0[..]));
    let positions: Vec<[f32; 3]> = reader
        .read_positions()
        .ok_or_else(|| format!("{file}: mesh {mesh} primitive {primitive} has no POSITION"))?
        .collect();
    let normals: Option<Vec<[f32; 3]>> = reader.read_normals().map(Iterator::collect);
    let uvs: Option<Vec<[f32; 2]>> = reader.read_tex_coords(0).map(|t| t.into_f32().collect());
    let indices: Vec<u32> = match reader.read_indices() {
        Some(i) => i.into_u32().collect(),
        None => (0..positions.len() as u32).collect(),
    };
    if indices.len() < 3 || !indices.len().is_multiple_of(3) {
        return Err(format!(
            "{file}: mesh {mesh} primitive {primitive} has {} indices, not whole triangles",
            indices.len()
        ));
    }
    if let Some(&bad) = indices.iter().find(|&&i| i as usize >= positions.len()) {
        return Err(format!(
            "{file}: mesh {mesh} primitive {primitive}: index {bad} past its {} vertices",
            positions.len()
        ));
    }
    let n = positions.len();
    let same_len = |len: usize, what: &str| {
        if len == n {
            Ok(())
        } else {
            Err(format!(
                "{file}: mesh {mesh} primitive {primitive}: {len} {what} for {n} positions"
            ))
        }
    };
    if let Some(v) = &normals {
        same_len(v.len(), "normals")?;
    }
    if let Some(v) = &uvs {
        same_len(v.len(), "uvs")?;
    }
    let mut data = MeshData {
        vertices: (0..n)
            .map(|i| Vertex {
                position: positions[i],
                normal: normals.as_ref().map_or([0.0; 3], |v| v[i]),
                uv: uvs.as_ref().map_or([0.0; 2], |v| v[i]),
                tangent: [1.0, 0.0, 0.0, 1.0],
            })
            .collect(),
        indices,
    };
    if normals.is_none() {
        smooth_normals(&mut data);
    }
    compute_tangents(&mut data);
    Ok(data)
}

/// The texels (RGBA, linear f32 of the stored values) of a material's texture: width, height,
/// texels top row first.
pub(crate) fn texture(
    session: &Session,
    t: &GltfTexture,
) -> Result<(u32, u32, Vec<[f32; 4]>), String> {
    let g = import(session, &t.path)?;
    let file = t.path.display();
    let m = g
        .doc
        .materials()
        .nth(t.material)
        .ok_or_else(|| format!("{file} has no material {}", t.material))?;
    let texture = match t.slot {
        MaterialSlot::BaseColor => m
            .pbr_metallic_roughness()
            .base_color_texture()
            .map(|i| i.texture()),
        MaterialSlot::MetallicRoughness => m
            .pbr_metallic_roughness()
            .metallic_roughness_texture()
            .map(|i| i.texture()),
        MaterialSlot::Normal => m.normal_texture().map(|i| i.texture()),
        MaterialSlot::Occlusion => m.occlusion_texture().map(|i| i.texture()),
        MaterialSlot::Emissive => m.emissive_texture().map(|i| i.texture()),
    }
    .ok_or_else(|| {
        format!(
            "{file}: material {} has no {:?} texture",
            t.material, t.slot
        )
    })?;
    let image = g
        .images
        .get(texture.source().index())
        .ok_or_else(|| format!("{file}: image {} is missing", texture.source().index()))?;
    use gltf::image::Format as F;
    let channels = match image.format {
        F::R8 => 1,
        F::R8G8 => 2,
        F::R8G8B8 => 3,
        F::R8G8B8A8 => 4,
        other => {
            return Err(format!(
                "{file}: image {} is {other:?}; reproj reads 8-bit images",
                texture.source().index()
            ));
        }
    };
    let texels = image
        .pixels
        .chunks_exact(channels)
        .map(|p| {
            let c = |i: usize| f32::from(p[i.min(channels - 1)]) / 255.0;
            match channels {
                1 => [c(0), c(0), c(0), 1.0],
                2 => [c(0), c(0), c(0), c(1)],
                3 => [c(0), c(1), c(2), 1.0],
                _ => [c(0), c(1), c(2), c(3)],
            }
        })
        .collect();
    Ok((image.width, image.height, texels))
}

/// Import the session's `gltf` scene (see the module docs). A session without one is left as it is.
pub(crate) fn expand(session: &mut Session) -> Result<(), SessionError> {
    let Some(spec) = session.gltf.clone() else {
        if matches!(session.camera, CameraPath::Gltf) {
            return Err(session.invalid("camera", "\"gltf\" needs a `gltf` scene"));
        }
        return Ok(());
    };
    let bad = |field: &str, message: String| SessionError::Invalid {
        path: session.path.clone(),
        field: field.into(),
        message,
    };
    let g = import(session, &spec.path).map_err(|m| bad("gltf.path", m))?;
    let scene = match spec.scene {
        Some(i) => g.doc.scenes().nth(i).ok_or_else(|| {
            bad(
                "gltf.scene",
                format!(
                    "{} has {} scene(s), not {i}",
                    spec.path.display(),
                    g.doc.scenes().len()
                ),
            )
        })?,
        None => g
            .doc
            .default_scene()
            .or_else(|| g.doc.scenes().next())
            .ok_or_else(|| bad("gltf.path", format!("{} has no scene", spec.path.display())))?,
    };
    let channels = channels(&g);
    let frames = session.frames;
    let fps = session.fps;
    // World matrices per frame, by node index.
    let mut per_frame: Vec<HashMap<usize, Mat4>> = Vec::with_capacity(frames as usize);
    for f in 0..frames {
        let locals = locals_at(&g, &channels, f as f32 / fps);
        let w = world(&scene, &locals).map_err(|m| bad("gltf", m))?;
        per_frame.push(w.into_iter().map(|(n, m)| (n.index(), m)).collect());
    }
    let nodes = world(&scene, &locals_at(&g, &channels, 0.0)).map_err(|m| bad("gltf", m))?;
    let mut added = 0;
    for (node, _) in &nodes {
        let Some(mesh) = node.mesh() else { continue };
        let moving = per_frame
            .windows(2)
            .any(|w| w[0][&node.index()] != w[1][&node.index()]);
        let keys: Vec<TransformKey> = if moving {
            (0..frames)
                .map(|f| key(f as f32, per_frame[f as usize][&node.index()]))
                .collect()
        } else {
            vec![key(0.0, per_frame[0][&node.index()])]
        };
        for p in mesh.primitives() {
            if p.mode() != gltf::mesh::Mode::Triangles {
                return Err(bad(
                    "gltf",
                    format!(
                        "{}: node {} mesh {} primitive {} draws {:?}; reproj draws triangles",
                        spec.path.display(),
                        node.name().unwrap_or("?"),
                        mesh.index(),
                        p.index(),
                        p.mode()
                    ),
                ));
            }
            session.geometry.objects.push(Object {
                name: Some(format!(
                    "{}/{}",
                    node.name()
                        .map_or_else(|| format!("node {}", node.index()), str::to_owned),
                    p.index()
                )),
                mesh: Mesh::Gltf {
                    path: spec.path.clone(),
                    mesh: mesh.index(),
                    primitive: p.index(),
                },
                transform: Transform { keys: keys.clone() },
                // A double-sided material is drawn from both sides, as glTF asks.
                cull: if p.material().double_sided() {
                    Cull::None
                } else {
                    spec.cull
                },
            });
            added += 1;
        }
    }
    if added == 0 {
        return Err(bad(
            "gltf",
            format!("{}: the scene has no mesh to draw", spec.path.display()),
        ));
    }
    if matches!(session.camera, CameraPath::Gltf) {
        let Some((cam_node, camera)) = nodes
            .iter()
            .find_map(|(n, _)| n.camera().map(|c| (n.index(), c)))
        else {
            return Err(bad(
                "camera",
                format!(
                    "\"gltf\": {} has no camera in its scene",
                    spec.path.display()
                ),
            ));
        };
        let gltf::camera::Projection::Perspective(p) = camera.projection() else {
            return Err(bad(
                "camera",
                "\"gltf\": the file's camera is orthographic; reproj renders perspective".into(),
            ));
        };
        let near = p.znear();
        let far = p.zfar().unwrap_or(near * 10_000.0);
        let keys = (0..frames)
            .map(|f| {
                let m = per_frame[f as usize][&cam_node];
                let eye = m.transform_point3(Vec3::ZERO);
                let forward = m.transform_vector3(Vec3::NEG_Z).normalize_or(Vec3::NEG_Z);
                let up = m.transform_vector3(Vec3::Y).normalize_or(Vec3::Y);
                CameraKey {
                    frame: f as f32,
                    eye: eye.to_array(),
                    target: (eye + forward).to_array(),
                    up: up.to_array(),
                    fov_y_deg: p.yfov().to_degrees(),
                    near,
                    far,
                }
            })
            .collect();
        session.camera = CameraPath::Keys(keys);
    }
    Ok(())
}
