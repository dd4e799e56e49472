// Simplification fixture (the interface of crates/reproj-replay/tests/data/tiny.wgsl, so its
// sessions render it): `flat` is costly and depends on uniforms only, the same value at every
// pixel of every frame, so replacing it (or `0.2 + 0.1 * flat`) by its mean costs no error and
// saves the most; `stripes` and the texture vary over the surface.
struct FragmentInput {
    @builtin(position) frag_coord: vec4<f32>,
    @location(0) world_pos: vec3<f32>,
    @location(1) normal: vec3<f32>,
    @location(2) uv: vec2<f32>,
};

struct Scene {
    camera_pos: vec3<f32>,
    time: f32,
    light_pos: vec3<f32>,
    gain: f32,
    tint: vec3<f32>,
};

@group(0) @binding(0) var<uniform> scene: Scene;
@group(1) @binding(0) var albedo_map: texture_2d<f32>;
@group(1) @binding(1) var albedo_sampler: sampler;

@fragment
fn fs_main(in: FragmentInput) -> @location(0) vec4<f32> {
    let g = scene.gain;
    let flat = sin(g * 1.3) * cos(g * 0.7) + sqrt(g * 2.0) * exp(-g) + pow(g, 1.5) * log(g + 2.0);
    let stripes = 0.5 + 0.5 * sin(in.world_pos.x * 40.0);
    let tex = textureSample(albedo_map, albedo_sampler, in.uv).rgb;
    return vec4<f32>(tex * stripes * (0.2 + 0.1 * flat), 1.0);
}
