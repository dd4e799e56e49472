// Parallax occlusion mapping written the way tutorials and engines usually do it (LearnOpenGL,
// many engine material graphs): the layer count depends on the view angle and the linear search
// stops with `break` as soon as the ray goes below the height field, then interpolates between the
// last two layers. Textured Blinn–Phong at the shifted uv with the normal map.

struct FragmentInput {
    @location(0) world_pos: vec3<f32>,
    @location(1) normal: vec3<f32>,
    @location(2) uv: vec2<f32>,
    @location(3) tangent: vec4<f32>,
};

struct Scene {
    camera_pos: vec3<f32>,
    time: f32,
    light_pos: vec3<f32>,
    height_scale: f32,
    light_color: vec3<f32>,
    shininess: f32,
    min_layers: f32,
    max_layers: f32,
};

@group(0) @binding(0) var<uniform> scene: Scene;
@group(1) @binding(0) var albedo_map: texture_2d<f32>;
@group(1) @binding(1) var normal_map: texture_2d<f32>;
@group(1) @binding(2) var depth_map: texture_2d<f32>;
@group(1) @binding(3) var linear_sampler: sampler;

fn depth_at(uv: vec2<f32>) -> f32 {
    return 1.0 - textureSampleLevel(depth_map, linear_sampler, uv, 0.0).r;
}

@fragment
fn fs_main(in: FragmentInput) -> @location(0) vec4<f32> {
    let n = normalize(in.normal);
    let t = normalize(in.tangent.xyz - n * dot(n, in.tangent.xyz));
    let b = cross(n, t) * in.tangent.w;
    let v_world = normalize(scene.camera_pos - in.world_pos);
    let v = vec3<f32>(dot(v_world, t), dot(v_world, b), dot(v_world, n));
    let num_layers = mix(scene.max_layers, scene.min_layers, abs(v.z));
    let layer_depth = 1.0 / num_layers;
    let delta_uv = v.xy / max(v.z, 0.05) * scene.height_scale / num_layers;
    var cur_uv = in.uv;
    var cur_layer = 0.0;
    var cur_depth = depth_at(cur_uv);
    loop {
        if cur_layer >= cur_depth {
            break;
        }
        cur_uv -= delta_uv;
        cur_depth = depth_at(cur_uv);
        cur_layer += layer_depth;
    }
    let prev_uv = cur_uv + delta_uv;
    let after = cur_depth - cur_layer;
    let before = depth_at(prev_uv) - cur_layer + layer_depth;
    let weight = after / (after - before);
    let uv = mix(cur_uv, prev_uv, weight);

    let tn = textureSample(normal_map, linear_sampler, uv).xyz * 2.0 - 1.0;
    let pn = normalize(t * tn.x + b * tn.y + n * tn.z);
    let albedo = textureSample(albedo_map, linear_sampler, uv).rgb;
    let l = normalize(scene.light_pos - in.world_pos);
    let h = normalize(l + v_world);
    let diffuse = albedo * max(dot(pn, l), 0.0);
    let spec = pow(max(dot(pn, h), 0.0), scene.shininess) * 0.2;
    let color = albedo * 0.1 + (diffuse + vec3<f32>(spec)) * scene.light_color;
    return vec4<f32>(clamp(color, vec3<f32>(0.0), vec3<f32>(1.0)), 1.0);
}
