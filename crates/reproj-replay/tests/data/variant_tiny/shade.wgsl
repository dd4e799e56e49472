// Hand-written pass 3 (shade) of tiny.wgsl: `albedo` read from the current cache.
struct FragmentInput {
    @builtin(position) frag_coord: vec4<f32>,
    @location(0) world_pos: vec3<f32>,
    @location(1) normal: vec3<f32>,
};

struct Scene {
    camera_pos: vec3<f32>,
    time: f32,
    light_pos: vec3<f32>,
    gain: f32,
    tint: vec3<f32>,
};

@group(0) @binding(0) var<uniform> scene: Scene;
@group(2) @binding(3) var reproj_cur_payload: texture_2d<f32>;

@fragment
fn shade_main(in: FragmentInput) -> @location(0) vec4<f32> {
    let n = normalize(in.normal);
    let l = normalize(scene.light_pos - in.world_pos);
    let v = normalize(scene.camera_pos - in.world_pos);
    let h = normalize(l + v);
    let albedo = textureLoad(reproj_cur_payload, vec2<i32>(in.frag_coord.xy), 0).rgb;
    let diffuse = max(dot(n, l), 0.0);
    let spec = pow(max(dot(n, h), 0.0), 32.0);
    return vec4<f32>(albedo * diffuse * scene.gain + vec3<f32>(spec * 0.3), 1.0);
}
