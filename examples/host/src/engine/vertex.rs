//! The engine's vertex stage: its WGSL (one output per input of the original fragment shader,
//! fed from the session's attribute mapping, and for a variant the manifest's previous clip
//! position) and the scene's vertex buffer layout.

use std::fmt::Write as _;

use anyhow::{anyhow, bail};
use reproj_runtime::manifest::VertexContract;
use reproj_scene::mesh;
use reproj_scene::vertex;

use super::{Engine, VERTEX_ENTRY};

/// The scene's vertex layout: position, normal, uv, tangent (`mesh::Vertex`).
const VERTEX_ATTRIBUTES: [wgpu::VertexAttribute; 4] =
    wgpu::vertex_attr_array![0 => Float32x3, 1 => Float32x3, 2 => Float32x2, 3 => Float32x4];
pub(super) const VERTEX_BUFFERS: [Option<wgpu::VertexBufferLayout<'static>>; 1] =
    [Some(wgpu::VertexBufferLayout {
        array_stride: size_of::<mesh::Vertex>() as u64,
        step_mode: wgpu::VertexStepMode::Vertex,
        attributes: &VERTEX_ATTRIBUTES,
    })];

/// The name of the first function a WGSL snippet declares.
fn first_fn_name(wgsl: &str) -> Option<&str> {
    let at = wgsl.find("fn ")? + 3;
    let rest = &wgsl[at..];
    let end = rest.find(|c: char| !(c.is_alphanumeric() || c == '_'))?;
    Some(rest[..end].trim()).filter(|n| !n.is_empty())
}

impl Engine {
    /// The engine's vertex stage: invariant clip position, one output per input of the original
    /// fragment shader (fed from the session's attribute mapping) and, for a variant, the
    /// previous frame's clip position at `contract.prev_clip_location`, computed by the
    /// manifest's helper function.
    pub fn vertex_wgsl(&self, contract: Option<&VertexContract>) -> anyhow::Result<String> {
        let mut s = String::new();
        let g = self.vertex_group;
        s.push_str(
            "// reproj-host: the engine's vertex stage.\n\
             struct HostObject {\n    view_proj: mat4x4<f32>,\n    prev_view_proj: mat4x4<f32>,\n    \
             model: mat4x4<f32>,\n    prev_model: mat4x4<f32>,\n    normal_matrix: mat4x4<f32>,\n};\n",
        );
        let _ = writeln!(
            s,
            "@group({g}) @binding(0) var<uniform> host_object: HostObject;"
        );
        s.push_str(
            "struct HostVertexIn {\n    @location(0) position: vec3<f32>,\n    @location(1) normal: vec3<f32>,\n    \
             @location(2) uv: vec2<f32>,\n    @location(3) tangent: vec4<f32>,\n};\n",
        );
        // The clip position must be @invariant: every pass rasterizes the same depths.
        s.push_str("struct HostVertexOut {\n    @builtin(position) @invariant clip: vec4<f32>,\n");
        let mut body = String::new();
        let mut missing = Vec::new();
        for i in &self.iface.inputs {
            if i.scalar.is_integer() {
                // An integer input (flat): 0, the one instance drawn, as the replay feeds it.
                let ty = i.scalar.wgsl_type(i.components);
                let _ = writeln!(
                    s,
                    "    @location({}) {}o{}: {ty},",
                    i.location,
                    vertex::interpolation(i),
                    i.location
                );
                let _ = writeln!(body, "    out.o{} = {ty}();", i.location);
                continue;
            }
            let Some(attr) = self.session.inputs.get(&i.location) else {
                missing.push(format!("@location({}) `{}`", i.location, i.name));
                continue;
            };
            let _ = writeln!(
                s,
                "    @location({}) {}o{}: {},",
                i.location,
                vertex::interpolation(i),
                i.location,
                i.scalar.wgsl_type(i.components)
            );
            let _ = writeln!(
                body,
                "    out.o{} = {};",
                i.location,
                vertex::attribute_expr(*attr, i.components)
            );
        }
        if !missing.is_empty() {
            bail!(
                "the session's `inputs` maps no vertex attribute to the fragment input(s) {}",
                missing.join(", ")
            );
        }
        if let Some(c) = contract {
            let Some(loc) = c.prev_clip_location else {
                bail!(
                    "the variant reads the engine's motion vectors (manifest `reprojection: motion_vectors`); this host has no velocity pass: write it with `--reproject vertex`"
                );
            };
            if self.iface.inputs.iter().any(|i| i.location == loc) {
                bail!("the manifest's prev_clip_location {loc} is an input of the shader itself");
            }
            if !c.invariant_position {
                eprintln!(
                    "note: the manifest does not ask for an invariant position; it is invariant anyway"
                );
            }
            let f = first_fn_name(&c.wgsl)
                .ok_or_else(|| anyhow!("the manifest's vertex.wgsl declares no function"))?;
            // The helper's arguments, by the names the manifest gives them.
            let args = c
                .inputs
                .iter()
                .map(|i| match i.name.as_str() {
                    "prev_view_proj" => Ok("host_object.prev_view_proj"),
                    "prev_model" => Ok("host_object.prev_model"),
                    "view_proj" => Ok("host_object.view_proj"),
                    "model" => Ok("host_object.model"),
                    "position" => Ok("v.position"),
                    other => Err(anyhow!(
                        "the manifest's vertex contract needs `{other}`, which this host does not supply"
                    )),
                })
                .collect::<anyhow::Result<Vec<_>>>()?;
            let _ = writeln!(s, "    @location({loc}) prev_clip: vec4<f32>,");
            let _ = writeln!(body, "    out.prev_clip = {f}({});", args.join(", "));
        }
        s.push_str("};\n");
        if let Some(c) = contract {
            s.push_str(&c.wgsl);
        }
        let _ = write!(
            s,
            "@vertex\nfn {VERTEX_ENTRY}(v: HostVertexIn) -> HostVertexOut {{\n    \
             let world = host_object.model * vec4<f32>(v.position, 1.0);\n    \
             let world_normal = normalize((host_object.normal_matrix * vec4<f32>(v.normal, 0.0)).xyz);\n    \
             let world_tangent = vec4<f32>(normalize((host_object.model * vec4<f32>(v.tangent.xyz, 0.0)).xyz), v.tangent.w);\n    \
             var out: HostVertexOut;\n    \
             out.clip = host_object.view_proj * world;\n{body}    return out;\n}}\n"
        );
        Ok(s)
    }
}
