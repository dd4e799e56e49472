// Iridescent thin film (soap bubble, oil slick, anodized metal): a film of varying thickness over a
// base layer. Two-beam interference of the first reflection at the film's top and bottom gives a
// spectral tint, evaluated at three wavelengths; the base is chosen by a uniform `switch` in a
// helper whose cases each return (dielectric, metal, or a black backing). An equirectangular sky
// is reflected through the tinted Fresnel.

struct FragmentInput {
    @location(0) world_pos: vec3<f32>,
    @location(1) normal: vec3<f32>,
    @location(2) uv: vec2<f32>,
};

struct Scene {
    camera_pos: vec3<f32>,
    time: f32,
    light_pos: vec3<f32>,
    film_ior: f32,
    light_color: vec3<f32>,
    thickness_min: f32,
    base_color: vec3<f32>,
    thickness_max: f32,
    base_mode: u32,
    swirl_speed: f32,
    env_intensity: f32,
    shininess: f32,
};

const PI: f32 = 3.14159265;

@group(0) @binding(0) var<uniform> scene: Scene;
@group(1) @binding(0) var thickness_map: texture_2d<f32>;
@group(1) @binding(1) var env_map: texture_2d<f32>;
@group(1) @binding(2) var linear_sampler: sampler;

// Reflectance of what lies under the film at normal incidence.
fn base_f0(mode: u32) -> vec3<f32> {
    switch mode {
        case 1u: {
            // Metal: its color is its reflectance.
            return scene.base_color;
        }
        case 2u: {
            // Black backing (a bubble seen against a dark interior).
            return vec3<f32>(0.0);
        }
        default: {
            // Dielectric, IOR 1.5.
            return vec3<f32>(0.04);
        }
    }
}

// Interference for one wavelength (nm): phase difference of the two beams.
fn interference(thickness_nm: f32, cos_t: f32, lambda_nm: f32, r0: f32, r1: f32) -> f32 {
    let phase = 4.0 * PI * scene.film_ior * thickness_nm * cos_t / lambda_nm;
    let a = r0 * r0 + r1 * r1 + 2.0 * r0 * r1 * cos(phase);
    return clamp(a, 0.0, 1.0);
}

fn equirect_uv(d: vec3<f32>) -> vec2<f32> {
    let u = atan2(d.z, d.x) / (2.0 * PI) + 0.5;
    let v = acos(clamp(d.y, -1.0, 1.0)) / PI;
    return vec2<f32>(u, v);
}

@fragment
fn fs_main(in: FragmentInput) -> @location(0) vec4<f32> {
    let n = normalize(in.normal);
    let v = normalize(scene.camera_pos - in.world_pos);
    let n_v = max(dot(n, v), 1e-3);

    // Film thickness: a texture swirled slowly over time.
    let swirl = vec2<f32>(sin(scene.time * scene.swirl_speed), cos(scene.time * scene.swirl_speed * 0.7)) * 0.05;
    let t_sample = textureSample(thickness_map, linear_sampler, in.uv * 2.0 + swirl).r;
    let thickness = mix(scene.thickness_min, scene.thickness_max, t_sample);

    // Refraction into the film (Snell), cosine inside it.
    let sin_t2 = (1.0 - n_v * n_v) / (scene.film_ior * scene.film_ior);
    let cos_t = sqrt(max(1.0 - sin_t2, 0.0));

    // Amplitude reflectances at the top (air/film) and the bottom (film/base).
    let f0_base = base_f0(scene.base_mode);
    let r_top = (1.0 - scene.film_ior) / (1.0 + scene.film_ior);
    let base_ior = (1.0 + sqrt(f0_base)) / max(vec3<f32>(1.0) - sqrt(f0_base), vec3<f32>(1e-3));
    let r_bot = (scene.film_ior - base_ior) / (scene.film_ior + base_ior);

    let tint = vec3<f32>(
        interference(thickness, cos_t, 650.0, r_top, r_bot.x),
        interference(thickness, cos_t, 532.0, r_top, r_bot.y),
        interference(thickness, cos_t, 450.0, r_top, r_bot.z),
    );
    let schlick = pow(1.0 - n_v, 5.0);
    let fresnel = tint + (vec3<f32>(1.0) - tint) * schlick;

    // Reflected sky and a sharp highlight.
    let r = reflect(-v, n);
    let env = textureSampleLevel(env_map, linear_sampler, equirect_uv(r), 0.0).rgb * scene.env_intensity;
    let l = normalize(scene.light_pos - in.world_pos);
    let h = normalize(l + v);
    let spec = pow(max(dot(n, h), 0.0), scene.shininess) * (scene.shininess + 8.0) / (8.0 * PI);
    let n_l = max(dot(n, l), 0.0);

    let color = fresnel * (env + scene.light_color * spec * n_l);
    return vec4<f32>(color / (color + vec3<f32>(1.0)), 1.0);
}
