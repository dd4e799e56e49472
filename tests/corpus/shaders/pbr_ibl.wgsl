// Metallic-roughness PBR (glTF material model) with image-based lighting, as in Filament / Bevy /
// the glTF sample viewer: GGX distribution, height-correlated Smith visibility, Schlick Fresnel for
// the point light; diffuse IBL from an irradiance cube map, specular IBL from a prefiltered cube map
// sampled at a roughness LOD and the analytic split-sum BRDF approximation (Karis, mobile);
// occlusion map, ACES filmic tone mapping, sRGB-ish gamma.

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
    exposure: f32,
    light_color: vec3<f32>,
    light_intensity: f32,
    base_color_factor: vec4<f32>,
    metallic_factor: f32,
    roughness_factor: f32,
    ibl_intensity: f32,
    max_reflection_lod: f32,
};

@group(0) @binding(0) var<uniform> scene: Scene;
@group(1) @binding(0) var base_color_map: texture_2d<f32>;
@group(1) @binding(1) var metallic_roughness_map: texture_2d<f32>;
@group(1) @binding(2) var normal_map: texture_2d<f32>;
@group(1) @binding(3) var occlusion_map: texture_2d<f32>;
@group(1) @binding(4) var irradiance_map: texture_cube<f32>;
@group(1) @binding(5) var prefiltered_map: texture_cube<f32>;
@group(1) @binding(6) var material_sampler: sampler;
@group(1) @binding(7) var cube_sampler: sampler;

const PI: f32 = 3.14159265;

fn d_ggx(n_dot_h: f32, alpha: f32) -> f32 {
    let a2 = alpha * alpha;
    let f = n_dot_h * n_dot_h * (a2 - 1.0) + 1.0;
    return a2 / (PI * f * f);
}

fn v_smith_ggx_correlated(n_dot_v: f32, n_dot_l: f32, alpha: f32) -> f32 {
    let a2 = alpha * alpha;
    let gv = n_dot_l * sqrt(n_dot_v * n_dot_v * (1.0 - a2) + a2);
    let gl = n_dot_v * sqrt(n_dot_l * n_dot_l * (1.0 - a2) + a2);
    return 0.5 / max(gv + gl, 1e-5);
}

fn f_schlick(f0: vec3<f32>, v_dot_h: f32) -> vec3<f32> {
    let f = pow(1.0 - v_dot_h, 5.0);
    return f0 + (vec3<f32>(1.0) - f0) * f;
}

fn env_brdf_approx(f0: vec3<f32>, roughness: f32, n_dot_v: f32) -> vec3<f32> {
    let c0 = vec4<f32>(-1.0, -0.0275, -0.572, 0.022);
    let c1 = vec4<f32>(1.0, 0.0425, 1.04, -0.04);
    let r = roughness * c0 + c1;
    let a004 = min(r.x * r.x, exp2(-9.28 * n_dot_v)) * r.x + r.y;
    let ab = vec2<f32>(-1.04, 1.04) * a004 + r.zw;
    return f0 * ab.x + vec3<f32>(ab.y);
}

fn aces_film(x: vec3<f32>) -> vec3<f32> {
    let y = (x * (2.51 * x + 0.03)) / (x * (2.43 * x + 0.59) + 0.14);
    return clamp(y, vec3<f32>(0.0), vec3<f32>(1.0));
}

@fragment
fn fs_main(in: FragmentInput) -> @location(0) vec4<f32> {
    let base = textureSample(base_color_map, material_sampler, in.uv) * scene.base_color_factor;
    let mr = textureSample(metallic_roughness_map, material_sampler, in.uv);
    let roughness = clamp(mr.g * scene.roughness_factor, 0.04, 1.0);
    let metallic = clamp(mr.b * scene.metallic_factor, 0.0, 1.0);
    let ao = textureSample(occlusion_map, material_sampler, in.uv).r;

    let geo_n = normalize(in.normal);
    let t = normalize(in.tangent.xyz - geo_n * dot(geo_n, in.tangent.xyz));
    let b = cross(geo_n, t) * in.tangent.w;
    let tn = textureSample(normal_map, material_sampler, in.uv).xyz * 2.0 - 1.0;
    let n = normalize(t * tn.x + b * tn.y + geo_n * tn.z);

    let v = normalize(scene.camera_pos - in.world_pos);
    let l = normalize(scene.light_pos - in.world_pos);
    let h = normalize(v + l);
    let n_dot_v = clamp(dot(n, v), 1e-4, 1.0);
    let n_dot_l = clamp(dot(n, l), 0.0, 1.0);
    let n_dot_h = clamp(dot(n, h), 0.0, 1.0);
    let v_dot_h = clamp(dot(v, h), 0.0, 1.0);

    let alpha = roughness * roughness;
    let f0 = mix(vec3<f32>(0.04), base.rgb, metallic);
    let diffuse_color = base.rgb * (1.0 - metallic);
    let fresnel = f_schlick(f0, v_dot_h);
    let specular = fresnel * (d_ggx(n_dot_h, alpha) * v_smith_ggx_correlated(n_dot_v, n_dot_l, alpha));
    let diffuse = (vec3<f32>(1.0) - fresnel) * diffuse_color / PI;
    let direct = (diffuse + specular) * scene.light_color * (scene.light_intensity * n_dot_l);

    let r = reflect(-v, n);
    let irradiance = textureSample(irradiance_map, cube_sampler, n).rgb;
    let prefiltered = textureSampleLevel(prefiltered_map, cube_sampler, r, roughness * scene.max_reflection_lod).rgb;
    let env_brdf = env_brdf_approx(f0, roughness, n_dot_v);
    let ambient = (diffuse_color * irradiance + prefiltered * env_brdf) * (ao * scene.ibl_intensity);

    let mapped = aces_film((direct + ambient) * scene.exposure);
    return vec4<f32>(pow(mapped, vec3<f32>(1.0 / 2.2)), 1.0);
}
