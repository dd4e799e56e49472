// Hand-written pass 2 (recompute) of tiny.wgsl: only node `albedo`, zero-padded to vec4.
struct FragmentInput {
    @location(0) world_pos: vec3<f32>,
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

fn pattern(p: vec3<f32>) -> vec3<f32> {
    let a = sin(p * 7.0 + vec3<f32>(0.0, 1.0, 2.0));
    let b = cos(p.yzx * 13.0);
    return 0.5 + 0.25 * a + 0.25 * b;
}

@fragment
fn recompute_main(in: FragmentInput) -> @location(0) vec4<f32> {
    let albedo = pattern(in.world_pos) * textureSample(albedo_map, albedo_sampler, in.uv).rgb * scene.tint;
    return vec4<f32>(albedo, 0.0);
}
