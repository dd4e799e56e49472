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
@group(2) @binding(3) 
var reproj_cur_payload: texture_2d<f32>;

@fragment 
fn fs_main(in: FragmentInput) -> @location(0) vec4<f32> {
    let n = normalize(in.normal);
    let _e5 = scene.light_pos;
    let p = in.world_pos;
    let l = normalize((_e5 - p));
    let _e11 = scene.camera_pos;
    let v = normalize((_e11 - p));
    let h = normalize((l + v));
    let _e21 = textureLoad(reproj_cur_payload, vec2<i32>(in.frag_coord.xy), 0i);
    let diffuse = max(dot(n, l), 0f);
    let spec = pow(max(dot(n, h), 0f), 32f);
    let _e32 = scene.gain;
    return vec4<f32>((((_e21.xyz * diffuse) * _e32) + vec3((spec * 0.3f))), 1f);
}
