// Volume ray-marching of a density field in a 3D texture (smoke/cloud in a unit box), as in the
// WebGPU samples' "volumeRenderingTexture3D" and engine fog volumes: the ray enters at the front
// face of the box, slab-intersects it for the exit distance, takes 24 fixed steps with
// Beer–Lambert absorption, and a 4-step shadow march toward the light at every sample.

struct FragmentInput {
    @location(0) world_pos: vec3<f32>,
};

struct Scene {
    camera_pos: vec3<f32>,
    time: f32,
    light_pos: vec3<f32>,
    density_scale: f32,
    light_color: vec3<f32>,
    absorption: f32,
    scatter_color: vec3<f32>,
    wind_speed: f32,
};

@group(0) @binding(0) var<uniform> scene: Scene;
@group(1) @binding(0) var density_volume: texture_3d<f32>;
@group(1) @binding(1) var volume_sampler: sampler;

const STEPS: i32 = 24;
const SHADOW_STEPS: i32 = 4;

fn density_at(p: vec3<f32>) -> f32 {
    let uvw = p + vec3<f32>(0.5) + vec3<f32>(scene.time * scene.wind_speed, 0.0, 0.0);
    let d = textureSampleLevel(density_volume, volume_sampler, uvw, 0.0).r;
    return max(d - 0.35, 0.0) * scene.density_scale;
}

@fragment
fn fs_main(in: FragmentInput) -> @location(0) vec4<f32> {
    let dir = normalize(in.world_pos - scene.camera_pos);
    let inv = 1.0 / dir;
    let t0 = (vec3<f32>(-0.5) - in.world_pos) * inv;
    let t1 = (vec3<f32>(0.5) - in.world_pos) * inv;
    let t_far = max(t0, t1);
    let t_exit = max(min(min(t_far.x, t_far.y), t_far.z), 0.0);
    let step_len = t_exit / f32(STEPS);
    var transmittance = 1.0;
    var radiance = vec3<f32>(0.0);
    for (var i = 0; i < STEPS; i++) {
        let p = in.world_pos + dir * (step_len * (f32(i) + 0.5));
        let d = density_at(p);
        let to_light = normalize(scene.light_pos - p);
        var shadow_depth = 0.0;
        for (var j = 1; j <= SHADOW_STEPS; j++) {
            shadow_depth += density_at(p + to_light * (0.1 * f32(j)));
        }
        let light_t = exp(-shadow_depth * 0.1 * scene.absorption);
        let sample_t = exp(-d * step_len * scene.absorption);
        radiance += transmittance * (1.0 - sample_t) * scene.scatter_color * scene.light_color * light_t;
        transmittance *= sample_t;
    }
    let background = vec3<f32>(0.1, 0.12, 0.16);
    return vec4<f32>(radiance + background * transmittance, 1.0);
}
