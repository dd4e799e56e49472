// Cloth (velvet, satin-like fabric): the "Charlie" sheen distribution (Estevez & Kulla) with
// Neubelt's visibility term, a wrapped diffuse lobe, and a woven-thread pattern from the uv.
// The per-draw uniforms nest structs two deep (`Scene.fabric.sheen`), as an engine's material
// system lays them out. The light helpers return early: past the light's range, and behind the
// surface.

struct FragmentInput {
    @location(0) world_pos: vec3<f32>,
    @location(1) normal: vec3<f32>,
    @location(2) uv: vec2<f32>,
};

struct SheenParams {
    color: vec3<f32>,
    roughness: f32,
};

struct Fabric {
    base_color: vec3<f32>,
    weave_scale: f32,
    sheen: SheenParams,
    thread_color: vec3<f32>,
    diffuse_wrap: f32,
};

struct Scene {
    camera_pos: vec3<f32>,
    time: f32,
    light_pos: vec3<f32>,
    light_range: f32,
    light_color: vec3<f32>,
    light_intensity: f32,
    fabric: Fabric,
    sky_color: vec3<f32>,
    _pad: f32,
};

const PI: f32 = 3.14159265;

@group(0) @binding(0) var<uniform> scene: Scene;
@group(1) @binding(0) var fiber_map: texture_2d<f32>;
@group(1) @binding(1) var linear_sampler: sampler;

fn d_charlie(roughness: f32, n_h: f32) -> f32 {
    let inv_alpha = 1.0 / max(roughness * roughness, 1e-3);
    let cos2 = n_h * n_h;
    let sin2 = max(1.0 - cos2, 0.0078125);
    return (2.0 + inv_alpha) * pow(sin2, inv_alpha * 0.5) / (2.0 * PI);
}

fn v_neubelt(n_v: f32, n_l: f32) -> f32 {
    return clamp(1.0 / (4.0 * (n_l + n_v - n_l * n_v)), 0.0, 1.0);
}

// Smooth inverse-square falloff to zero at the range; zero early when out of range.
fn attenuation(dist: f32, range: f32) -> f32 {
    if (dist >= range) {
        return 0.0;
    }
    let x = dist / range;
    let w = clamp(1.0 - x * x * x * x, 0.0, 1.0);
    return w * w / (dist * dist + 1.0);
}

// Sheen and diffuse from one light; nothing when the light is behind the cloth.
fn cloth_light(n: vec3<f32>, v: vec3<f32>, l: vec3<f32>, albedo: vec3<f32>) -> vec3<f32> {
    let wrap = scene.fabric.diffuse_wrap;
    let n_l_raw = dot(n, l);
    if (n_l_raw <= -wrap) {
        return vec3<f32>(0.0);
    }
    let h = normalize(v + l);
    let n_l = max(n_l_raw, 0.0);
    let n_v = max(dot(n, v), 1e-4);
    let n_h = max(dot(n, h), 0.0);
    let diffuse = albedo * max((n_l_raw + wrap) / (1.0 + wrap), 0.0) / PI;
    let sheen = scene.fabric.sheen.color * d_charlie(scene.fabric.sheen.roughness, n_h) * v_neubelt(n_v, n_l) * n_l;
    return diffuse + sheen;
}

// Plain weave: warp and weft threads alternate over and under.
fn weave(uv: vec2<f32>) -> vec2<f32> {
    let p = uv * scene.fabric.weave_scale;
    let cell = floor(p);
    let f = fract(p) - 0.5;
    let over = (cell.x + cell.y) - 2.0 * floor((cell.x + cell.y) * 0.5);
    let warp = 1.0 - smoothstep(0.25, 0.5, abs(f.x));
    let weft = 1.0 - smoothstep(0.25, 0.5, abs(f.y));
    let height = mix(warp * (0.6 + 0.4 * cos(f.y * PI)), weft * (0.6 + 0.4 * cos(f.x * PI)), over);
    return vec2<f32>(height, over);
}

@fragment
fn fs_main(in: FragmentInput) -> @location(0) vec4<f32> {
    let w = weave(in.uv);
    let fiber = textureSample(fiber_map, linear_sampler, in.uv * scene.fabric.weave_scale * 0.25).r;
    let albedo = mix(scene.fabric.base_color, scene.fabric.thread_color, w.y * 0.35) * (0.55 + 0.45 * w.x) * (0.8 + 0.4 * fiber);

    let n = normalize(in.normal);
    let v = normalize(scene.camera_pos - in.world_pos);
    let to_light = scene.light_pos - in.world_pos;
    let dist = length(to_light);
    let l = to_light / dist;

    let radiance = scene.light_color * scene.light_intensity * attenuation(dist, scene.light_range);
    let direct = cloth_light(n, v, l, albedo) * radiance;
    let ambient = albedo * scene.sky_color * (0.5 + 0.5 * n.y) * (0.7 + 0.3 * w.x);
    let color = direct + ambient;
    return vec4<f32>(pow(color / (color + vec3<f32>(0.6)), vec3<f32>(0.9)), 1.0);
}
