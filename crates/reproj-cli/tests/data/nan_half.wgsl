// Non-finite fixture (`crates/reproj-cli/tests/nonfinite.rs`): the tiny test shader with a bug of
// its own, a NaN color wherever world x > 0. No error can be measured against those pixels.
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

fn pattern(p: vec3<f32>) -> vec3<f32> {
    let a = sin(p * 7.0 + vec3<f32>(0.0, 1.0, 2.0));
    let b = cos(p.yzx * 13.0);
    return 0.5 + 0.25 * a + 0.25 * b;
}

@fragment
fn fs_main(in: FragmentInput) -> @location(0) vec4<f32> {
    let n = normalize(in.normal);
    let l = normalize(scene.light_pos - in.world_pos);
    let v = normalize(scene.camera_pos - in.world_pos);
    let h = normalize(l + v);
    let albedo = pattern(in.world_pos) * textureSample(albedo_map, albedo_sampler, in.uv).rgb * scene.tint;
    let diffuse = max(dot(n, l), 0.0);
    let spec = pow(max(dot(n, h), 0.0), 32.0);
    let color = albedo * diffuse * scene.gain + vec3<f32>(spec * 0.3);
    // The shader's own bug: NaN on half the object.
    let bad = bitcast<f32>(0x7fc00000u | u32(in.uv.x * 0.0));
    return vec4<f32>(select(color, vec3<f32>(bad), in.world_pos.x > 0.0), 1.0);
}
