// Shadow-mapped sun light, in the style of the WebGPU samples' "shadowMapping" fragment shader:
// the world position is projected by the light's view-projection into a depth shadow map rendered
// by a shadow pass, 3×3 PCF through a comparison sampler (`textureSampleCompareLevel`), a
// slope-scaled bias, textured Lambert + Blinn–Phong, shadowed diffuse and specular.

struct FragmentInput {
    @location(0) world_pos: vec3<f32>,
    @location(1) normal: vec3<f32>,
    @location(2) uv: vec2<f32>,
};

struct Scene {
    camera_pos: vec3<f32>,
    time: f32,
    light_pos: vec3<f32>,
    shadow_bias: f32,
    light_view_proj: mat4x4<f32>,
    light_color: vec3<f32>,
    shininess: f32,
    ambient_color: vec3<f32>,
    shadow_map_size: f32,
};

@group(0) @binding(0) var<uniform> scene: Scene;
@group(1) @binding(0) var albedo_map: texture_2d<f32>;
@group(1) @binding(1) var linear_sampler: sampler;
@group(1) @binding(2) var shadow_map: texture_depth_2d;
@group(1) @binding(3) var shadow_sampler: sampler_comparison;

fn shadow_visibility(world_pos: vec3<f32>, n_dot_l: f32) -> f32 {
    let clip = scene.light_view_proj * vec4<f32>(world_pos, 1.0);
    let ndc = clip.xyz / clip.w;
    let shadow_uv = vec2<f32>(ndc.x * 0.5 + 0.5, ndc.y * -0.5 + 0.5);
    let slope = sqrt(max(1.0 - n_dot_l * n_dot_l, 0.0)) / max(n_dot_l, 0.05);
    let bias = clamp(scene.shadow_bias * slope, 0.0, 0.01);
    let ref_depth = ndc.z - bias;
    let texel = 1.0 / scene.shadow_map_size;
    var visibility = 0.0;
    for (var y = -1; y <= 1; y++) {
        for (var x = -1; x <= 1; x++) {
            let offset = vec2<f32>(f32(x), f32(y)) * texel;
            visibility += textureSampleCompareLevel(shadow_map, shadow_sampler, shadow_uv + offset, ref_depth);
        }
    }
    return visibility / 9.0;
}

@fragment
fn fs_main(in: FragmentInput) -> @location(0) vec4<f32> {
    let n = normalize(in.normal);
    let l = normalize(scene.light_pos - in.world_pos);
    let v = normalize(scene.camera_pos - in.world_pos);
    let h = normalize(l + v);
    let n_dot_l = max(dot(n, l), 0.0);
    let albedo = textureSample(albedo_map, linear_sampler, in.uv).rgb;
    let visibility = shadow_visibility(in.world_pos, n_dot_l);
    let diffuse = albedo * n_dot_l;
    let specular = pow(max(dot(n, h), 0.0), scene.shininess) * 0.3;
    let lit = (diffuse + vec3<f32>(specular)) * scene.light_color * visibility;
    let color = scene.ambient_color * albedo + lit;
    return vec4<f32>(clamp(color, vec3<f32>(0.0), vec3<f32>(1.0)), 1.0);
}
