// Cube-map skybox, as in the WebGPU samples' "cubemap" and most engines' sky pass: the view
// direction from the eye through the fragment looks up a cube map; exposure, a horizon haze tint
// and Reinhard tone mapping. Drawn on a box around the camera with culling off.

struct FragmentInput {
    @location(0) world_pos: vec3<f32>,
};

struct Scene {
    camera_pos: vec3<f32>,
    time: f32,
    light_pos: vec3<f32>,
    exposure: f32,
    haze_color: vec3<f32>,
    haze_amount: f32,
};

@group(0) @binding(0) var<uniform> scene: Scene;
@group(1) @binding(0) var sky_cube: texture_cube<f32>;
@group(1) @binding(1) var sky_sampler: sampler;

@fragment
fn fs_main(in: FragmentInput) -> @location(0) vec4<f32> {
    let dir = normalize(in.world_pos - scene.camera_pos);
    let sky = textureSample(sky_cube, sky_sampler, dir).rgb * scene.exposure;
    let sun_dir = normalize(scene.light_pos);
    let sun_glow = pow(max(dot(dir, sun_dir), 0.0), 64.0) * 0.5;
    let haze = pow(1.0 - abs(dir.y), 4.0) * scene.haze_amount;
    let hdr = mix(sky + vec3<f32>(sun_glow), scene.haze_color, haze);
    let ldr = hdr / (hdr + vec3<f32>(1.0));
    return vec4<f32>(ldr, 1.0);
}
