// Procedural terrain shading, in the style of Inigo Quilez's terrain articles and engine landscape
// materials: 6-octave hashed value-noise fBm over world xz (with rotation between octaves) gives a
// detail height; its finite-difference gradient (two more fBm evaluations) perturbs the normal;
// grass / rock / snow blend by slope and height; sun Lambert with sky fill; exponential distance fog.

struct FragmentInput {
    @location(0) world_pos: vec3<f32>,
    @location(1) normal: vec3<f32>,
};

struct Scene {
    camera_pos: vec3<f32>,
    time: f32,
    light_pos: vec3<f32>,
    detail_scale: f32,
    grass_color: vec3<f32>,
    detail_strength: f32,
    rock_color: vec3<f32>,
    snow_height: f32,
    snow_color: vec3<f32>,
    fog_density: f32,
    fog_color: vec3<f32>,
};

@group(0) @binding(0) var<uniform> scene: Scene;

fn hash2(p: vec2<f32>) -> f32 {
    let q = fract(p * vec2<f32>(123.34, 456.21));
    let r = q + dot(q, q + 45.32);
    return fract(r.x * r.y);
}

fn value_noise(p: vec2<f32>) -> f32 {
    let i = floor(p);
    let f = fract(p);
    let u = f * f * (3.0 - 2.0 * f);
    let a = hash2(i);
    let b = hash2(i + vec2<f32>(1.0, 0.0));
    let c = hash2(i + vec2<f32>(0.0, 1.0));
    let d = hash2(i + vec2<f32>(1.0, 1.0));
    return mix(mix(a, b, u.x), mix(c, d, u.x), u.y);
}

fn fbm(p_in: vec2<f32>) -> f32 {
    let rot = mat2x2<f32>(0.8, -0.6, 0.6, 0.8);
    var p = p_in;
    var amplitude = 0.5;
    var sum = 0.0;
    for (var i = 0; i < 6; i++) {
        sum += amplitude * value_noise(p);
        p = rot * p * 2.03;
        amplitude *= 0.5;
    }
    return sum;
}

@fragment
fn fs_main(in: FragmentInput) -> @location(0) vec4<f32> {
    let p = in.world_pos.xz * scene.detail_scale;
    let eps = 0.05;
    let h = fbm(p);
    let hx = fbm(p + vec2<f32>(eps, 0.0));
    let hz = fbm(p + vec2<f32>(0.0, eps));
    let grad = vec2<f32>(hx - h, hz - h) / eps * scene.detail_strength;
    let n = normalize(normalize(in.normal) + vec3<f32>(-grad.x, 0.0, -grad.y));
    let height = in.world_pos.y + h * 0.5;
    let slope = 1.0 - n.y;
    let rock_w = smoothstep(0.15, 0.35, slope);
    let snow_w = smoothstep(scene.snow_height - 0.1, scene.snow_height + 0.1, height + h * 0.3) * (1.0 - rock_w);
    let ground = mix(mix(scene.grass_color, scene.rock_color, rock_w), scene.snow_color, snow_w);
    let albedo = ground * (0.75 + 0.5 * h);
    let sun = normalize(scene.light_pos);
    let diffuse = max(dot(n, sun), 0.0);
    let sky = 0.25 * (0.5 + 0.5 * n.y);
    let lit = albedo * (diffuse * vec3<f32>(1.0, 0.95, 0.85) + sky * vec3<f32>(0.5, 0.65, 0.9));
    let dist = length(in.world_pos - scene.camera_pos);
    let fog = 1.0 - exp(-dist * scene.fog_density);
    return vec4<f32>(mix(lit, scene.fog_color, fog), 1.0);
}
