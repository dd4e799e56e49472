// Four bind groups, as engines lay them out (view, material, light, mesh): no group is left for
// the variant, so its bindings join group 3 past the shader's own (binding_base 1), and the
// replay draws its own vertex transforms in a fifth (it asks for the adapter's limits; a host
// binds only the four). Session: two_terms.json.
struct In {
    @location(0) world_pos: vec3<f32>,
    @location(1) normal: vec3<f32>,
};
struct View { camera_pos: vec3<f32>, time: f32 };
struct Material { tint: vec3<f32> };
struct Light { light_pos: vec3<f32> };
struct Mesh { gain: f32 };
@group(0) @binding(0) var<uniform> view: View;
@group(1) @binding(0) var<uniform> material: Material;
@group(2) @binding(0) var<uniform> light: Light;
@group(3) @binding(0) var<uniform> mesh: Mesh;

@fragment
fn fs_main(in: In) -> @location(0) vec4<f32> {
    let p = in.world_pos;
    var a = 0.0;
    for (var i = 0; i < 96; i++) {
        let f = 1.0 + f32(i) * 0.02;
        a += sin(p.x * f * 3.1 + cos(p.y * f * 2.3)) * exp(-0.01 * f32(i)) / f;
    }
    let albedo = 0.5 + 0.2 * a;
    let n = normalize(in.normal);
    let l = normalize(light.light_pos - p);
    let c = albedo * max(dot(n, l), 0.0) * material.tint * mesh.gain;
    return vec4<f32>(c, 1.0);
}
