//! Meshes: procedural shapes, OBJ files and glTF primitives, as one interleaved vertex layout.

use std::f32::consts::{PI, TAU};

use glam::{Vec2, Vec3, Vec4};

pub use crate::geometry::{MeshData, Vertex};
use crate::geometry::{compute_tangents, smooth_normals};
use crate::session::{Mesh, Session};

fn v(p: Vec3, n: Vec3, uv: Vec2, t: Vec4) -> Vertex {
    Vertex {
        position: p.into(),
        normal: n.into(),
        uv: uv.into(),
        tangent: t.into(),
    }
}

/// Grid of (cols+1)×(rows+1) vertices, two triangles per cell; `f(u, v)` gives a vertex for
/// u, v ∈ [0, 1]. Triangles are wound so that the cross product of ∂/∂u and ∂/∂v faces out when
/// `flip` is false.
fn grid(cols: u32, rows: u32, flip: bool, mut f: impl FnMut(f32, f32) -> Vertex) -> MeshData {
    let mut m = MeshData::default();
    for j in 0..=rows {
        for i in 0..=cols {
            m.vertices
                .push(f(i as f32 / cols as f32, j as f32 / rows as f32));
        }
    }
    let w = cols + 1;
    for j in 0..rows {
        for i in 0..cols {
            let a = j * w + i;
            let b = a + 1;
            let c = a + w;
            let d = c + 1;
            if flip {
                m.indices.extend_from_slice(&[a, c, b, b, c, d]);
            } else {
                m.indices.extend_from_slice(&[a, b, c, b, d, c]);
            }
        }
    }
    m
}

fn sphere(radius: f32, segments: u32, rings: u32) -> MeshData {
    // u around +Y (φ), v from the north pole (θ = 0) to the south pole.
    grid(segments, rings, true, |u, vv| {
        let phi = u * TAU;
        let theta = vv * PI;
        let n = Vec3::new(
            theta.sin() * phi.cos(),
            theta.cos(),
            -theta.sin() * phi.sin(),
        );
        let t = Vec3::new(-phi.sin(), 0.0, -phi.cos());
        v(n * radius, n, Vec2::new(u, vv), t.extend(1.0))
    })
}

fn torus(big_r: f32, r: f32, segments: u32, sides: u32) -> MeshData {
    grid(segments, sides, false, |u, vv| {
        let phi = u * TAU;
        let theta = vv * TAU;
        let dir = Vec3::new(phi.cos(), 0.0, -phi.sin());
        let n = dir * theta.cos() + Vec3::Y * theta.sin();
        let p = dir * big_r + n * r;
        let t = Vec3::new(-phi.sin(), 0.0, -phi.cos());
        v(p, n, Vec2::new(u, vv), t.extend(1.0))
    })
}

fn plane(size: f32, subdivisions: u32, uv_scale: f32) -> MeshData {
    grid(subdivisions, subdivisions, true, |u, vv| {
        let p = Vec3::new((u - 0.5) * size, 0.0, (vv - 0.5) * size);
        v(
            p,
            Vec3::Y,
            Vec2::new(u, vv) * uv_scale,
            Vec4::new(1.0, 0.0, 0.0, 1.0),
        )
    })
}

fn cube(size: [f32; 3]) -> MeshData {
    let h = Vec3::from(size) * 0.5;
    let mut m = MeshData::default();
    // (normal, tangent (u direction), bitangent (v direction))
    let faces = [
        (Vec3::X, Vec3::NEG_Z, Vec3::NEG_Y),
        (Vec3::NEG_X, Vec3::Z, Vec3::NEG_Y),
        (Vec3::Y, Vec3::X, Vec3::Z),
        (Vec3::NEG_Y, Vec3::X, Vec3::NEG_Z),
        (Vec3::Z, Vec3::X, Vec3::NEG_Y),
        (Vec3::NEG_Z, Vec3::NEG_X, Vec3::NEG_Y),
    ];
    for (n, t, b) in faces {
        let base = m.vertices.len() as u32;
        for (du, dv) in [(0.0, 0.0), (1.0, 0.0), (0.0, 1.0), (1.0, 1.0)] {
            let p = (n + t * (2.0 * du - 1.0) + b * (2.0 * dv - 1.0)) * h;
            // handedness: sign of dot(cross(n, t), b)
            let w = if n.cross(t).dot(b) > 0.0 { 1.0 } else { -1.0 };
            m.vertices.push(v(p, n, Vec2::new(du, dv), t.extend(w)));
        }
        // counter-clockwise seen from outside
        let (a, bb, c, d) = (base, base + 1, base + 2, base + 3);
        if n.dot(t.cross(b)) > 0.0 {
            m.indices.extend_from_slice(&[a, bb, c, bb, d, c]);
        } else {
            m.indices.extend_from_slice(&[a, c, bb, bb, c, d]);
        }
    }
    m
}

fn lathe(profile: &[[f32; 2]], segments: u32) -> MeshData {
    // Arc length along the profile for v, smooth normals from the profile's tangent.
    let pts: Vec<Vec2> = profile.iter().map(|p| Vec2::new(p[0], p[1])).collect();
    let mut arc = vec![0.0f32];
    for w in pts.windows(2) {
        let l = arc.last().copied().unwrap_or(0.0) + (w[1] - w[0]).length();
        arc.push(l);
    }
    let total = arc.last().copied().unwrap_or(1.0).max(1e-6);
    let n_pts = pts.len();
    let tangent2 = |i: usize| -> Vec2 {
        let a = pts[i.saturating_sub(1)];
        let b = pts[(i + 1).min(n_pts - 1)];
        let d = b - a;
        if d.length_squared() > 0.0 {
            d.normalize()
        } else {
            Vec2::Y
        }
    };
    let mut m = MeshData::default();
    for (i, p) in pts.iter().enumerate() {
        let t2 = tangent2(i);
        // outward normal of the profile curve in (r, y): rotate the tangent by −90°.
        let n2 = Vec2::new(t2.y, -t2.x);
        for s in 0..=segments {
            let u = s as f32 / segments as f32;
            let phi = u * TAU;
            let dir = Vec3::new(phi.cos(), 0.0, -phi.sin());
            let pos = dir * p.x + Vec3::Y * p.y;
            let n = (dir * n2.x + Vec3::Y * n2.y).normalize_or_zero();
            let t = Vec3::new(-phi.sin(), 0.0, -phi.cos());
            m.vertices
                .push(v(pos, n, Vec2::new(u, arc[i] / total), t.extend(1.0)));
        }
    }
    let w = segments + 1;
    for j in 0..(n_pts as u32 - 1) {
        for i in 0..segments {
            let a = j * w + i;
            let b = a + 1;
            let c = a + w;
            let d = c + 1;
            // profile goes bottom → top (v up), u goes counter-clockwise seen from above
            m.indices.extend_from_slice(&[a, b, c, b, d, c]);
        }
    }
    m
}

fn obj(session: &Session, path: &std::path::Path, scale: f32) -> Result<MeshData, String> {
    let full = session.resolve(path)?;
    // Only a regular file within the size limit: `/dev/zero` or a pipe would never end.
    let text =
        reproj_io::read_input(&full, reproj_io::InputKind::Asset).map_err(|e| e.to_string())?;
    obj_mesh(&full, &text, scale)
}

/// The mesh of OBJ text `text` (read from `full`, which messages name), its positions times
/// `scale`: triangulated, one index per vertex, smooth normals where the file has none. A NaN or
/// infinite number, which would only show as a mesh that covers no pixel, and an index past the
/// data are refused by name ([`check_obj_text`]).
/// Materials are not read: an `mtllib` line opens no other file.
pub fn obj_mesh(full: &std::path::Path, text: &[u8], scale: f32) -> Result<MeshData, String> {
    check_obj_text(full, text)?;
    let (models, _) = tobj::load_obj_buf(
        &mut std::io::Cursor::new(text),
        &tobj::LoadOptions {
            triangulate: true,
            single_index: true,
            ..Default::default()
        },
        |_| Err(tobj::LoadError::OpenFileFailed),
    )
    .map_err(|e| format!("cannot load OBJ {}: {e}", full.display()))?;
    let mut m = MeshData::default();
    let mut need_normals = false;
    for model in models {
        let mesh = model.mesh;
        let base = m.vertices.len() as u32;
        let nv = mesh.positions.len() / 3;
        if mesh.normals.len() != nv * 3 {
            need_normals = true;
        }
        for i in 0..nv {
            let p = Vec3::from_slice(&mesh.positions[i * 3..i * 3 + 3]) * scale;
            if !p.is_finite() {
                return Err(format!(
                    "OBJ {}: vertex {i} of `{}` scaled by {scale} is {p}, past the f32 range",
                    full.display(),
                    model.name
                ));
            }
            let n = if mesh.normals.len() == nv * 3 {
                Vec3::from_slice(&mesh.normals[i * 3..i * 3 + 3]).normalize_or_zero()
            } else {
                Vec3::ZERO
            };
            let uv = if mesh.texcoords.len() == nv * 2 {
                Vec2::from_slice(&mesh.texcoords[i * 2..i * 2 + 2])
            } else {
                Vec2::ZERO
            };
            m.vertices.push(v(p, n, uv, Vec4::new(1.0, 0.0, 0.0, 1.0)));
        }
        m.indices.extend(mesh.indices.iter().map(|i| i + base));
    }
    if m.indices.is_empty() {
        return Err(format!("OBJ {} has no triangles", full.display()));
    }
    if m.indices.iter().any(|&i| i as usize >= m.vertices.len()) {
        return Err(format!("OBJ {} has out-of-range indices", full.display()));
    }
    if need_normals {
        smooth_normals(&mut m);
    }
    compute_tangents(&mut m);
    Ok(m)
}

/// Refuse an OBJ whose vertex data (`v`, `vn`, `vt`) holds a number that is not finite as an
/// f32 (`nan`, `inf`, or past ±3.4e38), or whose face or line (`f`, `l`) names a vertex, texture
/// coordinate or normal that no line before it defines, naming the file, the line and the number.
/// tobj computes with such an index unchecked (`-11` counts back past the start and wraps): an
/// overflow, or another vertex's data.
pub fn check_obj_text(path: &std::path::Path, bytes: &[u8]) -> Result<(), String> {
    // Lines seen so far of each kind: positions, texture coordinates, normals.
    let mut counts = [0u64; 3];
    const KINDS: [&str; 3] = ["vertex position", "texture coordinate", "normal"];
    for (i, line) in bytes.split(|&b| b == b'\n').enumerate() {
        let at = || format!("OBJ {}:{}", path.display(), i + 1);
        let line = String::from_utf8_lossy(line);
        let mut words = line.split_whitespace();
        let kind = match words.next() {
            Some("v") => 0,
            Some("vt") => 1,
            Some("vn") => 2,
            Some("f" | "l") => {
                for word in words {
                    for (k, part) in word.split('/').take(3).enumerate() {
                        let Ok(x) = part.parse::<i64>() else { continue };
                        if x.unsigned_abs() > counts[k] {
                            return Err(format!(
                                "{}: `{x}` names no {} ({} defined before this line; OBJ indices count from 1, or back from -1)",
                                at(),
                                KINDS[k],
                                counts[k]
                            ));
                        }
                    }
                }
                continue;
            }
            _ => continue,
        };
        counts[kind] += 1;
        for w in words {
            if w.parse::<f32>().is_ok_and(|x| !x.is_finite()) {
                let w: String = w.chars().take(40).collect();
                return Err(format!(
                    "{}: {} `{w}` is not a finite number (NaN, infinite, or past the f32 range ±3.4e38)",
                    at(),
                    KINDS[kind]
                ));
            }
        }
    }
    Ok(())
}

/// Build the mesh of a session object. Errors are one-line messages (file problems).
pub fn build(session: &Session, mesh: &Mesh) -> Result<MeshData, String> {
    Ok(match mesh {
        Mesh::Sphere {
            radius,
            segments,
            rings,
        } => sphere(*radius, *segments, rings.unwrap_or((*segments / 2).max(2))),
        Mesh::Torus {
            major_radius,
            minor_radius,
            segments,
            sides,
        } => torus(*major_radius, *minor_radius, *segments, *sides),
        Mesh::Plane {
            size,
            subdivisions,
            uv_scale,
        } => plane(*size, *subdivisions, *uv_scale),
        Mesh::Cube { size } => cube(*size),
        Mesh::Lathe { profile, segments } => lathe(profile, *segments),
        Mesh::Obj { path, scale } => obj(session, path, *scale)?,
        Mesh::Gltf {
            path,
            mesh,
            primitive,
        } => crate::gltf::mesh(session, path, *mesh, *primitive)?,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn check_outward(m: &MeshData) {
        // Every triangle's geometric normal agrees with its vertex normals (CCW front faces).
        for tri in m.indices.chunks_exact(3) {
            let p: Vec<Vec3> = tri
                .iter()
                .map(|&i| Vec3::from(m.vertices[i as usize].position))
                .collect();
            let gn = (p[1] - p[0]).cross(p[2] - p[0]);
            let shortest = (p[1] - p[0])
                .length()
                .min((p[2] - p[0]).length())
                .min((p[2] - p[1]).length());
            if shortest < 1e-5 || gn.length() < 1e-9 {
                continue;
            }
            let vn: Vec3 = tri
                .iter()
                .map(|&i| Vec3::from(m.vertices[i as usize].normal))
                .sum();
            assert!(gn.dot(vn) > 0.0, "inward triangle {tri:?}");
        }
    }

    #[test]
    fn shapes_face_outward() {
        check_outward(&sphere(1.0, 16, 8));
        check_outward(&torus(1.0, 0.3, 16, 8));
        check_outward(&plane(2.0, 3, 1.0));
        check_outward(&cube([1.0, 2.0, 3.0]));
        check_outward(&lathe(
            &[[0.5, 0.0], [0.4, 0.5], [0.2, 1.0], [0.0, 1.2]],
            16,
        ));
    }
}
