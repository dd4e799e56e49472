// Terrain splatting, as in Unity/Unreal/Bevy terrain materials: a splat control map's RGBA weights
// blend four material layers held in one `texture_2d_array` (albedo) plus a second array of
// normal maps, with height-based blending sharpening transitions (layer height in albedo alpha),
// tiled detail uvs, Lambert sun light.

struct FragmentInput {
    @location(0) world_pos: vec3<f32>,
    @location(1) normal: vec3<f32>,
    @location(2) uv: vec2<f32>,
    @location(3) tangent: vec4<f32>,
};

struct Scene {
    camera_pos: vec3<f32>,
    time: f32,
    light_pos: vec3<f32>,
    detail_tiling: f32,
    light_color: vec3<f32>,
    blend_depth: f32,
};

@group(0) @binding(0) var<uniform> scene: Scene;
@group(1) @binding(0) var splat_map: texture_2d<f32>;
@group(1) @binding(1) var layer_albedo: texture_2d_array<f32>;
@group(1) @binding(2) var layer_normal: texture_2d_array<f32>;
@group(1) @binding(3) var linear_sampler: sampler;

@fragment
fn fs_main(in: FragmentInput) -> @location(0) vec4<f32> {
    let control = textureSample(splat_map, linear_sampler, in.uv);
    let duv = in.uv * scene.detail_tiling;
    let a0 = textureSample(layer_albedo, linear_sampler, duv, 0);
    let a1 = textureSample(layer_albedo, linear_sampler, duv, 1);
    let a2 = textureSample(layer_albedo, linear_sampler, duv, 2);
    let a3 = textureSample(layer_albedo, linear_sampler, duv, 3);
    let heights = vec4<f32>(a0.a, a1.a, a2.a, a3.a) + control;
    let top = max(max(heights.x, heights.y), max(heights.z, heights.w)) - scene.blend_depth;
    let hw = max(heights - vec4<f32>(top), vec4<f32>(0.0));
    let w = hw / (hw.x + hw.y + hw.z + hw.w);
    let albedo = a0.rgb * w.x + a1.rgb * w.y + a2.rgb * w.z + a3.rgb * w.w;
    let tn = (textureSample(layer_normal, linear_sampler, duv, 0).xyz * w.x
        + textureSample(layer_normal, linear_sampler, duv, 1).xyz * w.y
        + textureSample(layer_normal, linear_sampler, duv, 2).xyz * w.z
        + textureSample(layer_normal, linear_sampler, duv, 3).xyz * w.w) * 2.0 - 1.0;
    let n0 = normalize(in.normal);
    let t = normalize(in.tangent.xyz - n0 * dot(n0, in.tangent.xyz));
    let b = cross(n0, t) * in.tangent.w;
    let n = normalize(t * tn.x + b * tn.y + n0 * tn.z);
    let l = normalize(scene.light_pos - in.world_pos);
    let color = albedo * (0.2 + max(dot(n, l), 0.0) * scene.light_color);
    return vec4<f32>(color, 1.0);
}
