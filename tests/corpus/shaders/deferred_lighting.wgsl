// Deferred lighting pass, as in the WebGPU samples' "deferredRendering": reads the G-buffer
// (normal and albedo targets with `textureLoad` at the fragment's pixel, the depth buffer as a
// `texture_depth_2d`), reconstructs the world position with the inverse view-projection, and
// accumulates the point lights of a storage buffer (runtime-sized array) with a smooth radius
// falloff.

struct FragmentInput {
    @builtin(position) frag_coord: vec4<f32>,
};

struct Scene {
    camera_pos: vec3<f32>,
    time: f32,
    light_pos: vec3<f32>,
    ambient: f32,
    inv_view_proj: mat4x4<f32>,
    resolution: vec2<f32>,
};

struct PointLight {
    position: vec3<f32>,
    radius: f32,
    color: vec3<f32>,
    intensity: f32,
};

struct LightsBuffer {
    count: u32,
    lights: array<PointLight>,
};

@group(0) @binding(0) var<uniform> scene: Scene;
@group(1) @binding(0) var gbuffer_normal: texture_2d<f32>;
@group(1) @binding(1) var gbuffer_albedo: texture_2d<f32>;
@group(1) @binding(2) var gbuffer_depth: texture_depth_2d;
@group(1) @binding(3) var<storage, read> lights_buffer: LightsBuffer;

fn world_from_depth(coord: vec2<f32>, depth: f32) -> vec3<f32> {
    let ndc = vec2<f32>(coord.x / scene.resolution.x * 2.0 - 1.0, 1.0 - coord.y / scene.resolution.y * 2.0);
    let world = scene.inv_view_proj * vec4<f32>(ndc, depth, 1.0);
    return world.xyz / world.w;
}

@fragment
fn fs_main(in: FragmentInput) -> @location(0) vec4<f32> {
    let pixel = vec2<i32>(floor(in.frag_coord.xy));
    let depth = textureLoad(gbuffer_depth, pixel, 0);
    let n = normalize(textureLoad(gbuffer_normal, pixel, 0).xyz * 2.0 - 1.0);
    let albedo = textureLoad(gbuffer_albedo, pixel, 0).rgb;
    let position = world_from_depth(in.frag_coord.xy, depth);
    let v = normalize(scene.camera_pos - position);
    var result = albedo * scene.ambient;
    for (var i = 0u; i < lights_buffer.count; i++) {
        let light = lights_buffer.lights[i];
        let to_light = light.position - position;
        let dist = length(to_light);
        let l = to_light / dist;
        let falloff = clamp(1.0 - pow(dist / light.radius, 4.0), 0.0, 1.0);
        let attenuation = falloff * falloff / (dist * dist + 1.0);
        let h = normalize(l + v);
        let spec = pow(max(dot(n, h), 0.0), 32.0) * 0.25;
        result += (albedo * max(dot(n, l), 0.0) + vec3<f32>(spec)) * light.color * (light.intensity * attenuation);
    }
    return vec4<f32>(result, 1.0);
}
