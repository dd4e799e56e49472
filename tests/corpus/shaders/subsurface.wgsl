// Cheap subsurface scattering for skin, wax and jade, as in engine "subsurface profile" fallbacks:
// wrap diffuse with a per-channel wrap amount, curvature estimated from screen-space derivatives
// of the normal and position (pre-integrated skin lookup replaced by its analytic fit), back-light
// transmission through a thickness map (Barré-Brisebois), and a dual-lobe specular.

struct FragmentInput {
    @location(0) world_pos: vec3<f32>,
    @location(1) normal: vec3<f32>,
    @location(2) uv: vec2<f32>,
};

struct Scene {
    camera_pos: vec3<f32>,
    time: f32,
    light_pos: vec3<f32>,
    curvature_scale: f32,
    light_color: vec3<f32>,
    transmission_power: f32,
    scatter_color: vec3<f32>,
    transmission_scale: f32,
    wrap: vec3<f32>,
    roughness: f32,
};

@group(0) @binding(0) var<uniform> scene: Scene;
@group(1) @binding(0) var albedo_map: texture_2d<f32>;
@group(1) @binding(1) var thickness_map: texture_2d<f32>;
@group(1) @binding(2) var linear_sampler: sampler;

fn specular_lobe(n_dot_h: f32, roughness: f32) -> f32 {
    let a2 = roughness * roughness * roughness * roughness;
    let d = n_dot_h * n_dot_h * (a2 - 1.0) + 1.0;
    return a2 / (3.14159265 * d * d);
}

@fragment
fn fs_main(in: FragmentInput) -> @location(0) vec4<f32> {
    let n = normalize(in.normal);
    let l = normalize(scene.light_pos - in.world_pos);
    let v = normalize(scene.camera_pos - in.world_pos);
    let h = normalize(l + v);
    let n_dot_l = dot(n, l);
    let curvature = clamp(length(fwidth(n)) / max(length(fwidth(in.world_pos)), 1e-4) * scene.curvature_scale, 0.0, 1.0);
    let wrap = scene.wrap * curvature;
    let diffuse = clamp((vec3<f32>(n_dot_l) + wrap) / ((vec3<f32>(1.0) + wrap) * (vec3<f32>(1.0) + wrap)), vec3<f32>(0.0), vec3<f32>(1.0));
    let scatter_tint = mix(vec3<f32>(1.0), scene.scatter_color, clamp(1.0 - n_dot_l, 0.0, 1.0) * curvature);
    let albedo = textureSample(albedo_map, linear_sampler, in.uv).rgb;
    let thickness = textureSample(thickness_map, linear_sampler, in.uv).r;
    let back = normalize(l + n * 0.3);
    let transmission = pow(clamp(dot(v, -back), 0.0, 1.0), scene.transmission_power) * scene.transmission_scale * (1.0 - thickness);
    let n_dot_h = max(dot(n, h), 0.0);
    let spec = 0.5 * (specular_lobe(n_dot_h, scene.roughness) + specular_lobe(n_dot_h, scene.roughness * 0.5)) * 0.028;
    let color = (albedo * diffuse * scatter_tint + scene.scatter_color * albedo * transmission + vec3<f32>(spec * max(n_dot_l, 0.0))) * scene.light_color + albedo * 0.05;
    return vec4<f32>(color / (color + vec3<f32>(1.0)), 1.0);
}
