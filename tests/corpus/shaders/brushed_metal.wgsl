// Brushed metal: an anisotropic GGX lobe (Filament's parameterization) oriented by the brushing
// direction (the mesh tangent, bent by a scratch texture; a negative anisotropy widens the lobe
// across the grooves, so a can brushed around shows a vertical streak), height-correlated
// anisotropic Smith visibility, a Schlick Fresnel on the metal's F0, and a thin clear coat. Material knobs the pipeline bakes in are `override`
// constants with defaults; the per-draw parameters are a uniform struct that nests a `Material` and
// a `PointLight`, as engines group them.

struct FragmentInput {
    @location(0) world_pos: vec3<f32>,
    @location(1) normal: vec3<f32>,
    @location(2) uv: vec2<f32>,
    @location(3) tangent: vec4<f32>,
};

struct Material {
    base_color: vec3<f32>,
    roughness: f32,
    scratch_color: vec3<f32>,
    anisotropy: f32,
};

struct PointLight {
    color: vec3<f32>,
    intensity: f32,
    range: f32,
    _pad0: f32,
    _pad1: f32,
    _pad2: f32,
};

struct Scene {
    camera_pos: vec3<f32>,
    time: f32,
    light_pos: vec3<f32>,
    uv_scale: f32,
    material: Material,
    light: PointLight,
    ambient: vec3<f32>,
    exposure: f32,
};

override brush_strength: f32 = 0.35;
override clear_coat: f32 = 0.25;
override use_clear_coat: bool = true;

const PI: f32 = 3.14159265;

@group(0) @binding(0) var<uniform> scene: Scene;
@group(1) @binding(0) var scratch_map: texture_2d<f32>;
@group(1) @binding(1) var linear_sampler: sampler;

fn d_ggx_aniso(n_h: f32, t_h: f32, b_h: f32, at: f32, ab: f32) -> f32 {
    let a2 = at * ab;
    let v = vec3<f32>(ab * t_h, at * b_h, a2 * n_h);
    let w2 = a2 / dot(v, v);
    return a2 * w2 * w2 / PI;
}

fn v_smith_aniso(at: f32, ab: f32, t_v: f32, b_v: f32, t_l: f32, b_l: f32, n_v: f32, n_l: f32) -> f32 {
    let lambda_v = n_l * length(vec3<f32>(at * t_v, ab * b_v, n_v));
    let lambda_l = n_v * length(vec3<f32>(at * t_l, ab * b_l, n_l));
    return 0.5 / max(lambda_v + lambda_l, 1e-4);
}

fn fresnel_schlick(f0: vec3<f32>, v_h: f32) -> vec3<f32> {
    let f = pow(1.0 - v_h, 5.0);
    return f0 + (vec3<f32>(1.0) - f0) * f;
}

@fragment
fn fs_main(in: FragmentInput) -> @location(0) vec4<f32> {
    let uv = in.uv * scene.uv_scale;
    // Scratches: the texture's red bends the brushing direction, green darkens the grooves.
    let scratch = textureSample(scratch_map, linear_sampler, uv * vec2<f32>(8.0, 0.5));
    let n = normalize(in.normal);
    let t0 = normalize(in.tangent.xyz - n * dot(n, in.tangent.xyz));
    let b0 = cross(n, t0) * in.tangent.w;
    let bend = (scratch.r - 0.5) * brush_strength;
    let t = normalize(t0 + b0 * bend);
    let b = cross(n, t);

    let v = normalize(scene.camera_pos - in.world_pos);
    let to_light = scene.light_pos - in.world_pos;
    let dist = length(to_light);
    let l = to_light / dist;
    let h = normalize(v + l);

    let n_l = max(dot(n, l), 0.0);
    let n_v = max(dot(n, v), 1e-4);
    let n_h = max(dot(n, h), 0.0);
    let v_h = max(dot(v, h), 0.0);

    let rough = scene.material.roughness;
    let a = rough * rough;
    let aniso = scene.material.anisotropy;
    let at = max(a * (1.0 + aniso), 0.002);
    let ab = max(a * (1.0 - aniso), 0.002);

    let d = d_ggx_aniso(n_h, dot(t, h), dot(b, h), at, ab);
    let vis = v_smith_aniso(at, ab, dot(t, v), dot(b, v), dot(t, l), dot(b, l), n_v, n_l);
    let albedo = mix(scene.material.base_color, scene.material.scratch_color, scratch.g * 0.5);
    let f = fresnel_schlick(albedo, v_h);

    let falloff = clamp(1.0 - pow(dist / scene.light.range, 4.0), 0.0, 1.0);
    let radiance = scene.light.color * scene.light.intensity * falloff * falloff / (dist * dist + 1.0);
    var color = d * vis * f * radiance * n_l;

    // Ambient: metals have no diffuse, so a rough environment term tinted by F0.
    color += scene.ambient * albedo * (0.6 + 0.4 * n.y);

    if (use_clear_coat) {
        let fc = 0.04 + 0.96 * pow(1.0 - v_h, 5.0);
        let dc = d_ggx_aniso(n_h, dot(t, h), dot(b, h), 0.05, 0.05);
        let coat = clear_coat * fc * dc * 0.25 * n_l;
        color = color * (1.0 - clear_coat * fc) + vec3<f32>(coat) * radiance;
    }

    let mapped = vec3<f32>(1.0) - exp(-color * scene.exposure);
    return vec4<f32>(mapped, 1.0);
}
