//! The vertex stage a recorded scene is drawn with, its GPU-free parts: the per-object transform
//! uniform, the WGSL that feeds a fragment input from a session attribute, and an input's
//! interpolation qualifier. The replay's generated vertex module and the example host's vertex
//! stage are written from these, so both rasterize the same positions and interpolate the same
//! values (their frames are compared bit for bit).
//!
//! The expressions name the vertex stage's locals: `world` (world-space position, vec4),
//! `world_normal` (vec3), `world_tangent` (vec4, w the handedness) and the vertex input `v`
//! (`position`, `normal`, `uv`, `tangent`: [`crate::mesh::Vertex`]).

use bytemuck::{Pod, Zeroable};

use crate::reflect::FragInput;
use crate::session::Attribute;

/// The vertex stage's per-object uniform: this frame's and the previous frame's matrices, 320
/// bytes.
#[derive(Debug, Clone, Copy, Pod, Zeroable)]
#[repr(C)]
pub struct TransformUniform {
    pub view_proj: [[f32; 4]; 4],
    pub prev_view_proj: [[f32; 4]; 4],
    pub model: [[f32; 4]; 4],
    pub prev_model: [[f32; 4]; 4],
    /// Inverse transpose of `model` (upper 3×3 used).
    pub normal_matrix: [[f32; 4]; 4],
}

impl TransformUniform {
    pub fn new(
        view_proj: glam::Mat4,
        prev_view_proj: glam::Mat4,
        model: glam::Mat4,
        prev_model: glam::Mat4,
    ) -> Self {
        let nm = glam::Mat4::from_mat3(glam::Mat3::from_mat4(model).inverse().transpose());
        TransformUniform {
            view_proj: view_proj.to_cols_array_2d(),
            prev_view_proj: prev_view_proj.to_cols_array_2d(),
            model: model.to_cols_array_2d(),
            prev_model: prev_model.to_cols_array_2d(),
            normal_matrix: nm.to_cols_array_2d(),
        }
    }
}

/// WGSL expression of `attr` with `n` components (truncated, or padded with 0 and a final
/// component of 1 for positions, 0 for directions).
pub fn attribute_expr(attr: Attribute, n: u32) -> String {
    let (src, m, w) = match attr {
        Attribute::Position => ("world.xyz", 3, "1.0"),
        Attribute::Normal => ("world_normal", 3, "0.0"),
        Attribute::Uv => ("v.uv", 2, "0.0"),
        Attribute::Tangent => ("world_tangent", 4, "1.0"),
        Attribute::ObjectPosition => ("v.position", 3, "1.0"),
        Attribute::ObjectNormal => ("v.normal", 3, "0.0"),
    };
    const SWIZZLE: [&str; 5] = ["", "x", "xy", "xyz", "xyzw"];
    match n.cmp(&m) {
        std::cmp::Ordering::Equal => src.to_owned(),
        std::cmp::Ordering::Less => format!("{src}.{}", SWIZZLE[n as usize]),
        std::cmp::Ordering::Greater => {
            let mut parts = vec![src.to_owned()];
            parts.extend((m..n - 1).map(|_| "0.0".to_owned()));
            parts.push(w.to_owned());
            format!("vec{n}<f32>({})", parts.join(", "))
        }
    }
}

/// The `@interpolate(…) ` qualifier (with its trailing space) of a fragment input as the
/// fragment shader declares it, for the vertex output that feeds it; empty where it declares none.
pub fn interpolation(i: &FragInput) -> String {
    match (&i.interpolation, &i.sampling) {
        (None, _) => String::new(),
        (Some(interp), Some(s)) if interp != "flat" || s == "first" || s == "either" => {
            format!("@interpolate({interp}, {s}) ")
        }
        (Some(interp), _) => format!("@interpolate({interp}) "),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn attributes_are_truncated_or_padded_as_positions_or_directions() {
        assert_eq!(attribute_expr(Attribute::Position, 3), "world.xyz");
        assert_eq!(attribute_expr(Attribute::Position, 2), "world.xyz.xy");
        assert_eq!(
            attribute_expr(Attribute::Position, 4),
            "vec4<f32>(world.xyz, 1.0)"
        );
        assert_eq!(
            attribute_expr(Attribute::Normal, 4),
            "vec4<f32>(world_normal, 0.0)"
        );
        assert_eq!(
            attribute_expr(Attribute::Uv, 4),
            "vec4<f32>(v.uv, 0.0, 0.0)"
        );
        assert_eq!(attribute_expr(Attribute::Tangent, 1), "world_tangent.x");
    }
}
