//! The one vertex layout every mesh source fills ([`Vertex`], [`MeshData`]), and the normals and
//! tangents computed for sources that lack them. Below both [`crate::mesh`] (procedural shapes,
//! OBJ) and `gltf` (glTF primitives), which fill it; imports nothing of the crate.

use bytemuck::{Pod, Zeroable};
use glam::{Vec2, Vec3};

/// One vertex: object-space position and normal, uv, object-space tangent (w = handedness).
/// 48 bytes, the layout of the generated vertex stage's `@location(0..=3)`.
#[derive(Debug, Clone, Copy, PartialEq, Pod, Zeroable)]
#[repr(C)]
pub struct Vertex {
    pub position: [f32; 3],
    pub normal: [f32; 3],
    pub uv: [f32; 2],
    pub tangent: [f32; 4],
}

/// Indexed triangle list, counter-clockwise front faces.
#[derive(Debug, Clone, Default)]
pub struct MeshData {
    pub vertices: Vec<Vertex>,
    pub indices: Vec<u32>,
}

/// Per-vertex tangents from uvs (accumulated per triangle, Gram–Schmidt against the normal).
pub(crate) fn compute_tangents(m: &mut MeshData) {
    let n = m.vertices.len();
    let mut tan = vec![Vec3::ZERO; n];
    let mut bit = vec![Vec3::ZERO; n];
    for tri in m.indices.chunks_exact(3) {
        let [a, b, c] = [tri[0] as usize, tri[1] as usize, tri[2] as usize];
        let (pa, pb, pc) = (
            Vec3::from(m.vertices[a].position),
            Vec3::from(m.vertices[b].position),
            Vec3::from(m.vertices[c].position),
        );
        let (ua, ub, uc) = (
            Vec2::from(m.vertices[a].uv),
            Vec2::from(m.vertices[b].uv),
            Vec2::from(m.vertices[c].uv),
        );
        let (e1, e2) = (pb - pa, pc - pa);
        let (d1, d2) = (ub - ua, uc - ua);
        let det = d1.x * d2.y - d2.x * d1.y;
        if det.abs() < 1e-12 {
            continue;
        }
        let r = 1.0 / det;
        let t = (e1 * d2.y - e2 * d1.y) * r;
        let bt = (e2 * d1.x - e1 * d2.x) * r;
        for i in [a, b, c] {
            tan[i] += t;
            bit[i] += bt;
        }
    }
    for (i, vert) in m.vertices.iter_mut().enumerate() {
        let nrm = Vec3::from(vert.normal);
        let mut t = tan[i] - nrm * nrm.dot(tan[i]);
        if t.length_squared() < 1e-20 {
            t = nrm.any_orthonormal_vector();
        }
        let t = t.normalize();
        let w = if nrm.cross(t).dot(bit[i]) < 0.0 {
            -1.0
        } else {
            1.0
        };
        vert.tangent = t.extend(w).into();
    }
}

pub(crate) fn smooth_normals(m: &mut MeshData) {
    let mut acc = vec![Vec3::ZERO; m.vertices.len()];
    for tri in m.indices.chunks_exact(3) {
        let [a, b, c] = [tri[0] as usize, tri[1] as usize, tri[2] as usize];
        let (pa, pb, pc) = (
            Vec3::from(m.vertices[a].position),
            Vec3::from(m.vertices[b].position),
            Vec3::from(m.vertices[c].position),
        );
        let n = (pb - pa).cross(pc - pa);
        for i in [a, b, c] {
            acc[i] += n;
        }
    }
    for (vert, n) in m.vertices.iter_mut().zip(acc) {
        vert.normal = n.normalize_or_zero().into();
    }
}
