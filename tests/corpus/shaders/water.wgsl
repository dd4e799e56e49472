// Water surface, in the style of engine ocean/lake shaders: two normal maps scrolled in different
// directions over time and blended (whiteout), Schlick Fresnel between a depth-tinted body color
// and the reflected sky (equirectangular environment map), a sharp sun glint, and noise-driven
// foam crests.

struct FragmentInput {
    @location(0) world_pos: vec3<f32>,
    @location(1) normal: vec3<f32>,
    @location(2) uv: vec2<f32>,
};

struct Scene {
    camera_pos: vec3<f32>,
    time: f32,
    light_pos: vec3<f32>,
    wave_scale: f32,
    deep_color: vec3<f32>,
    wave_strength: f32,
    shallow_color: vec3<f32>,
    foam_amount: f32,
    flow_a: vec2<f32>,
    flow_b: vec2<f32>,
};

@group(0) @binding(0) var<uniform> scene: Scene;
@group(1) @binding(0) var wave_normals: texture_2d<f32>;
@group(1) @binding(1) var foam_noise: texture_2d<f32>;
@group(1) @binding(2) var sky_map: texture_2d<f32>;
@group(1) @binding(3) var linear_sampler: sampler;

const PI: f32 = 3.14159265;

fn equirect_uv(d: vec3<f32>) -> vec2<f32> {
    return vec2<f32>(atan2(d.z, d.x) / (2.0 * PI) + 0.5, acos(clamp(d.y, -1.0, 1.0)) / PI);
}

@fragment
fn fs_main(in: FragmentInput) -> @location(0) vec4<f32> {
    let uv = in.world_pos.xz * scene.wave_scale;
    let na = textureSample(wave_normals, linear_sampler, uv + scene.flow_a * scene.time).xyz * 2.0 - 1.0;
    let nb = textureSample(wave_normals, linear_sampler, uv * 1.7 + scene.flow_b * scene.time).xyz * 2.0 - 1.0;
    let blended = normalize(vec3<f32>(na.xy + nb.xy, na.z * nb.z));
    let n = normalize(vec3<f32>(blended.x * scene.wave_strength, 1.0, blended.y * scene.wave_strength));
    let v = normalize(scene.camera_pos - in.world_pos);
    let l = normalize(scene.light_pos - in.world_pos);
    let n_dot_v = max(dot(n, v), 0.0);
    let fresnel = 0.02 + 0.98 * pow(1.0 - n_dot_v, 5.0);
    let r = reflect(-v, n);
    let sky = textureSampleLevel(sky_map, linear_sampler, equirect_uv(r), 0.0).rgb;
    let body = mix(scene.shallow_color, scene.deep_color, clamp(1.0 - n_dot_v, 0.0, 1.0));
    let h = normalize(l + v);
    let glint = pow(max(dot(n, h), 0.0), 400.0) * 4.0;
    let foam_tex = textureSample(foam_noise, linear_sampler, uv * 0.5 - scene.flow_a * scene.time * 0.5).r;
    let crest = clamp(blended.x + blended.y, 0.0, 1.0);
    let foam = smoothstep(1.0 - scene.foam_amount, 1.0, foam_tex * crest + foam_tex * 0.5);
    let water = mix(body, sky, fresnel) + vec3<f32>(glint);
    let color = mix(water, vec3<f32>(0.9, 0.95, 1.0), foam);
    return vec4<f32>(color / (color + vec3<f32>(1.0)) * 1.6, 1.0);
}
