// Toon (cel) shading, as in anime-style engine materials and the three.js MeshToonMaterial: a
// diffuse ramp quantized into bands with a soft antialiased edge (`fwidth`), a hard specular
// highlight, a Fresnel rim light on the lit side, and a dark outline term at grazing angles.

struct FragmentInput {
    @location(0) world_pos: vec3<f32>,
    @location(1) normal: vec3<f32>,
    @location(2) uv: vec2<f32>,
};

struct Scene {
    camera_pos: vec3<f32>,
    time: f32,
    light_pos: vec3<f32>,
    bands: f32,
    base_color: vec3<f32>,
    glossiness: f32,
    shadow_color: vec3<f32>,
    rim_amount: f32,
    rim_color: vec3<f32>,
    outline_width: f32,
};

@group(0) @binding(0) var<uniform> scene: Scene;
@group(1) @binding(0) var albedo_map: texture_2d<f32>;
@group(1) @binding(1) var linear_sampler: sampler;

fn quantize(x: f32, bands: f32) -> f32 {
    let scaled = x * bands;
    let band = floor(scaled);
    let edge = fwidth(scaled);
    let blend = smoothstep(1.0 - edge, 1.0, fract(scaled));
    return (band + blend) / bands;
}

@fragment
fn fs_main(in: FragmentInput) -> @location(0) vec4<f32> {
    let n = normalize(in.normal);
    let l = normalize(scene.light_pos - in.world_pos);
    let v = normalize(scene.camera_pos - in.world_pos);
    let h = normalize(l + v);
    let n_dot_l = dot(n, l);
    let ramp = quantize(clamp(n_dot_l * 0.5 + 0.5, 0.0, 1.0), scene.bands);
    let albedo = textureSample(albedo_map, linear_sampler, in.uv).rgb * scene.base_color;
    let diffuse = mix(scene.shadow_color * albedo, albedo, ramp);
    let spec_raw = pow(max(dot(n, h), 0.0) * step(0.0, n_dot_l), scene.glossiness * scene.glossiness);
    let spec = smoothstep(0.005, 0.01, spec_raw);
    let rim_dot = 1.0 - dot(v, n);
    let rim = smoothstep(scene.rim_amount - 0.01, scene.rim_amount + 0.01, rim_dot * pow(max(n_dot_l, 0.0), 0.1));
    let outline = step(scene.outline_width, dot(v, n));
    let color = (diffuse + vec3<f32>(spec) + scene.rim_color * rim) * outline;
    return vec4<f32>(clamp(color, vec3<f32>(0.0), vec3<f32>(1.0)), 1.0);
}
