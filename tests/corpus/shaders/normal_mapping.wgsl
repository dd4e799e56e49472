// Normal mapping as in most engines' standard material: a tangent-space normal map (TBN from the
// interpolated tangent, w = bitangent sign, Gram–Schmidt re-orthogonalized), an albedo map, a
// specular mask in the albedo's alpha, hemisphere ambient, Blinn–Phong with energy normalization.

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
    shininess: f32,
    light_color: vec3<f32>,
    normal_strength: f32,
    sky_color: vec3<f32>,
    uv_scale: f32,
    ground_color: vec3<f32>,
};

@group(0) @binding(0) var<uniform> scene: Scene;
@group(1) @binding(0) var albedo_map: texture_2d<f32>;
@group(1) @binding(1) var normal_map: texture_2d<f32>;
@group(1) @binding(2) var linear_sampler: sampler;

fn perturb_normal(n: vec3<f32>, t: vec4<f32>, uv: vec2<f32>) -> vec3<f32> {
    let tangent = normalize(t.xyz - n * dot(n, t.xyz));
    let bitangent = cross(n, tangent) * t.w;
    let sampled = textureSample(normal_map, linear_sampler, uv).xyz * 2.0 - 1.0;
    let ts = vec3<f32>(sampled.xy * scene.normal_strength, sampled.z);
    return normalize(tangent * ts.x + bitangent * ts.y + n * ts.z);
}

@fragment
fn fs_main(in: FragmentInput) -> @location(0) vec4<f32> {
    let uv = in.uv * scene.uv_scale;
    let geo_n = normalize(in.normal);
    let n = perturb_normal(geo_n, in.tangent, uv);
    let texel = textureSample(albedo_map, linear_sampler, uv);
    let albedo = texel.rgb;
    let spec_mask = texel.a;
    let l = normalize(scene.light_pos - in.world_pos);
    let v = normalize(scene.camera_pos - in.world_pos);
    let h = normalize(l + v);
    let hemi = mix(scene.ground_color, scene.sky_color, n.y * 0.5 + 0.5);
    let n_dot_l = max(dot(n, l), 0.0);
    let norm_factor = (scene.shininess + 8.0) / 25.13274;
    let spec = norm_factor * pow(max(dot(n, h), 0.0), scene.shininess) * spec_mask * 0.04;
    let color = albedo * hemi * 0.3 + (albedo * n_dot_l + vec3<f32>(spec * n_dot_l)) * scene.light_color;
    return vec4<f32>(clamp(color, vec3<f32>(0.0), vec3<f32>(1.0)), 1.0);
}
