// Lit surface under exponential height fog with in-scattering toward the sun, laid out the way
// engines (Bevy, Godot) pass it: the uniform block nests a `DirectionalLight` and a `FogSettings`
// struct inside the per-view struct. Fog integral of density a·e^(−b·y) along the view ray (Quílez),
// sun-colored inscatter lobe, Lambert + Blinn–Phong underneath.

struct FragmentInput {
    @location(0) world_pos: vec3<f32>,
    @location(1) normal: vec3<f32>,
    @location(2) uv: vec2<f32>,
};

struct DirectionalLight {
    color: vec3<f32>,
    intensity: f32,
    direction: vec3<f32>,
    shininess: f32,
};

struct FogSettings {
    color: vec3<f32>,
    density: f32,
    sun_color: vec3<f32>,
    height_falloff: f32,
};

struct Scene {
    camera_pos: vec3<f32>,
    time: f32,
    light_pos: vec3<f32>,
    _pad0: f32,
    sun: DirectionalLight,
    fog: FogSettings,
};

@group(0) @binding(0) var<uniform> scene: Scene;
@group(1) @binding(0) var albedo_map: texture_2d<f32>;
@group(1) @binding(1) var linear_sampler: sampler;

fn fog_amount(origin: vec3<f32>, ray: vec3<f32>, dist: f32) -> f32 {
    let b = scene.fog.height_falloff;
    let rd_y = select(ray.y, 1e-4, abs(ray.y) < 1e-4);
    let integral = scene.fog.density * exp(-origin.y * b) * (1.0 - exp(-dist * rd_y * b)) / (rd_y * b);
    return clamp(integral, 0.0, 1.0);
}

@fragment
fn fs_main(in: FragmentInput) -> @location(0) vec4<f32> {
    let n = normalize(in.normal);
    let l = normalize(-scene.sun.direction);
    let to_frag = in.world_pos - scene.camera_pos;
    let dist = length(to_frag);
    let ray = to_frag / dist;
    let h = normalize(l - ray);
    let albedo = textureSample(albedo_map, linear_sampler, in.uv).rgb;
    let diffuse = albedo * max(dot(n, l), 0.0);
    let spec = pow(max(dot(n, h), 0.0), scene.sun.shininess) * 0.2;
    let lit = albedo * 0.15 + (diffuse + vec3<f32>(spec)) * scene.sun.color * scene.sun.intensity;
    let sun_amount = pow(max(dot(ray, l), 0.0), 8.0);
    let fog_color = mix(scene.fog.color, scene.fog.sun_color, sun_amount);
    let fog = fog_amount(scene.camera_pos, ray, dist);
    return vec4<f32>(mix(lit, fog_color, fog), 1.0);
}
