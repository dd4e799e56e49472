// Alpha-tested foliage, as in engine vegetation shaders: the leaf atlas's alpha is tested against a
// cutoff and the fragment is `discard`ed below it; two-sided lighting flips the normal on back
// faces, light passing through the leaf adds a translucent term, a wind-driven color variation
// from world position and time.

struct FragmentInput {
    @builtin(front_facing) front_facing: bool,
    @location(0) world_pos: vec3<f32>,
    @location(1) normal: vec3<f32>,
    @location(2) uv: vec2<f32>,
};

struct Scene {
    camera_pos: vec3<f32>,
    time: f32,
    light_pos: vec3<f32>,
    alpha_cutoff: f32,
    light_color: vec3<f32>,
    translucency: f32,
    tint_a: vec3<f32>,
    wind_frequency: f32,
    tint_b: vec3<f32>,
};

@group(0) @binding(0) var<uniform> scene: Scene;
@group(1) @binding(0) var leaf_atlas: texture_2d<f32>;
@group(1) @binding(1) var linear_sampler: sampler;

@fragment
fn fs_main(in: FragmentInput) -> @location(0) vec4<f32> {
    let texel = textureSample(leaf_atlas, linear_sampler, in.uv);
    if texel.a < scene.alpha_cutoff {
        discard;
    }
    let n = normalize(select(-in.normal, in.normal, in.front_facing));
    let l = normalize(scene.light_pos - in.world_pos);
    let v = normalize(scene.camera_pos - in.world_pos);
    let sway = 0.5 + 0.5 * sin(dot(in.world_pos, vec3<f32>(1.3, 0.7, 1.1)) * 2.0 + scene.time * scene.wind_frequency);
    let albedo = texel.rgb * mix(scene.tint_a, scene.tint_b, sway);
    let front = max(dot(n, l), 0.0);
    let back = pow(max(dot(v, -l), 0.0), 4.0) * max(dot(-n, l), 0.0) * scene.translucency;
    let color = albedo * (0.15 + front * scene.light_color) + albedo * back * scene.light_color;
    return vec4<f32>(color, 1.0);
}
