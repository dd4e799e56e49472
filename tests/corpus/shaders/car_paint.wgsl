// Metallic car paint, as in automotive configurator and engine "car paint" materials: a two-tone
// base (color shifts with the view angle), procedural metal flakes (3D cell hash on object space
// jitters a flake normal per cell, each sparkling under the light), a clear coat with Schlick
// Fresnel reflecting a cube-map environment, and the base specular under it.

struct FragmentInput {
    @location(0) world_pos: vec3<f32>,
    @location(1) normal: vec3<f32>,
    @location(4) object_pos: vec3<f32>,
};

struct Scene {
    camera_pos: vec3<f32>,
    time: f32,
    light_pos: vec3<f32>,
    flake_scale: f32,
    paint_color: vec3<f32>,
    flake_strength: f32,
    flip_color: vec3<f32>,
    clearcoat: f32,
    light_color: vec3<f32>,
    env_intensity: f32,
};

@group(0) @binding(0) var<uniform> scene: Scene;
@group(1) @binding(0) var env_cube: texture_cube<f32>;
@group(1) @binding(1) var env_sampler: sampler;

fn hash3(p: vec3<f32>) -> vec3<f32> {
    let q = vec3<f32>(dot(p, vec3<f32>(127.1, 311.7, 74.7)), dot(p, vec3<f32>(269.5, 183.3, 246.1)), dot(p, vec3<f32>(113.5, 271.9, 124.6)));
    return fract(sin(q) * 43758.5453) * 2.0 - 1.0;
}

@fragment
fn fs_main(in: FragmentInput) -> @location(0) vec4<f32> {
    let n = normalize(in.normal);
    let v = normalize(scene.camera_pos - in.world_pos);
    let l = normalize(scene.light_pos - in.world_pos);
    let h = normalize(l + v);
    let n_dot_v = max(dot(n, v), 0.0);
    let n_dot_l = max(dot(n, l), 0.0);
    let base = mix(scene.flip_color, scene.paint_color, pow(n_dot_v, 0.7));
    let cell = floor(in.object_pos * scene.flake_scale);
    let jitter = hash3(cell);
    let flake_n = normalize(n + jitter * scene.flake_strength);
    let sparkle = pow(max(dot(flake_n, h), 0.0), 80.0) * step(0.3, jitter.x * 0.5 + 0.5);
    let base_spec = pow(max(dot(n, h), 0.0), 24.0) * 0.25;
    let under = base * (n_dot_l * 0.9 + 0.1) + (vec3<f32>(base_spec + sparkle)) * scene.light_color * n_dot_l;
    let fresnel = 0.04 + 0.96 * pow(1.0 - n_dot_v, 5.0);
    let r = reflect(-v, n);
    let env = textureSample(env_cube, env_sampler, r).rgb * scene.env_intensity;
    let coat_spec = pow(max(dot(n, h), 0.0), 400.0) * 2.0;
    let coat = fresnel * scene.clearcoat;
    let color = under * (1.0 - coat) + (env + scene.light_color * coat_spec) * coat;
    return vec4<f32>(color / (color + vec3<f32>(1.0)), 1.0);
}
