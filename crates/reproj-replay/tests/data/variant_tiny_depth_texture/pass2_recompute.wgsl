struct FragmentInput {
    @builtin(position) frag_coord: vec4<f32>,
    @location(0) world_pos: vec3<f32>,
    @location(1) normal: vec3<f32>,
    @location(2) uv: vec2<f32>,
}

struct Scene {
    camera_pos: vec3<f32>,
    time: f32,
    light_pos: vec3<f32>,
    gain: f32,
    tint: vec3<f32>,
}

@group(0) @binding(0) 
var<uniform> scene: Scene;
@group(1) @binding(0) 
var albedo_map: texture_2d<f32>;
@group(1) @binding(1) 
var albedo_sampler: sampler;

@fragment 
fn fs_main(in: FragmentInput) -> @location(0) vec4<f32> {
    let p = in.world_pos;
    let a = sin(((p * 7f) + vec3<f32>(0f, 1f, 2f)));
    let b = cos((p.yzx * 13f));
    let _e17 = textureSample(albedo_map, albedo_sampler, in.uv);
    let _e20 = scene.tint;
    let albedo = ((((vec3(0.5f) + (0.25f * a)) + (0.25f * b)) * _e17.xyz) * _e20);
    return vec4<f32>(albedo, 0f);
}
