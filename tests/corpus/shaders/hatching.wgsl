// Real-time hatching with tonal art maps (Praun et al. 2001), as in NPR demos and engine sketch
// styles: six hatch tones packed in the RGB channels of two textures (light → dark); the lit
// intensity picks the two nearest tones and blends them with weights that sum to one, over paper
// color. Uses the mesh uvs scaled to a stroke density.

struct FragmentInput {
    @location(0) world_pos: vec3<f32>,
    @location(1) normal: vec3<f32>,
    @location(2) uv: vec2<f32>,
};

struct Scene {
    camera_pos: vec3<f32>,
    time: f32,
    light_pos: vec3<f32>,
    stroke_density: f32,
    paper_color: vec3<f32>,
    ink_strength: f32,
    ink_color: vec3<f32>,
};

@group(0) @binding(0) var<uniform> scene: Scene;
@group(1) @binding(0) var hatch_light: texture_2d<f32>;
@group(1) @binding(1) var hatch_dark: texture_2d<f32>;
@group(1) @binding(2) var linear_sampler: sampler;

fn hatch_weights(intensity: f32) -> array<f32, 6> {
    let s = clamp(1.0 - intensity, 0.0, 1.0) * 6.0;
    var w = array<f32, 6>(0.0, 0.0, 0.0, 0.0, 0.0, 0.0);
    w[0] = clamp(1.0 - abs(s - 1.0), 0.0, 1.0);
    w[1] = clamp(1.0 - abs(s - 2.0), 0.0, 1.0);
    w[2] = clamp(1.0 - abs(s - 3.0), 0.0, 1.0);
    w[3] = clamp(1.0 - abs(s - 4.0), 0.0, 1.0);
    w[4] = clamp(1.0 - abs(s - 5.0), 0.0, 1.0);
    w[5] = clamp(s - 5.0, 0.0, 1.0);
    return w;
}

@fragment
fn fs_main(in: FragmentInput) -> @location(0) vec4<f32> {
    let n = normalize(in.normal);
    let l = normalize(scene.light_pos - in.world_pos);
    let v = normalize(scene.camera_pos - in.world_pos);
    let h = normalize(l + v);
    let intensity = max(dot(n, l), 0.0) * 0.85 + pow(max(dot(n, h), 0.0), 30.0) * 0.3;
    let uv = in.uv * scene.stroke_density;
    let t_light = textureSample(hatch_light, linear_sampler, uv).rgb;
    let t_dark = textureSample(hatch_dark, linear_sampler, uv).rgb;
    let w = hatch_weights(intensity);
    let white = clamp(1.0 - (w[0] + w[1] + w[2] + w[3] + w[4] + w[5]), 0.0, 1.0) * step(0.5, intensity);
    let tone = white + t_light.r * w[0] + t_light.g * w[1] + t_light.b * w[2]
        + t_dark.r * w[3] + t_dark.g * w[4] + t_dark.b * w[5];
    let ink = clamp((1.0 - tone) * scene.ink_strength, 0.0, 1.0);
    return vec4<f32>(mix(scene.paper_color, scene.ink_color, ink), 1.0);
}
