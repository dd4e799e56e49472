// A material with the debug views engines and samples put behind a uniform (the "normalMap"
// sample's shape): `view_mode` picks lit shading or one of its inputs, and every case of the
// `switch` returns its own color. reproj rewrites the returns into one exit (a `result` stored in
// each case), so the work inside the cases is cacheable: the branch is on a uniform.

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
    shininess: f32,
    light_color: vec3<f32>,
    normal_strength: f32,
    sky_color: vec3<f32>,
    uv_scale: f32,
    ground_color: vec3<f32>,
    view_mode: u32,
};

@group(0) @binding(0) var<uniform> scene: Scene;
@group(1) @binding(0) var albedo_map: texture_2d<f32>;
@group(1) @binding(1) var normal_map: texture_2d<f32>;
@group(1) @binding(2) var linear_sampler: sampler;

fn tbn_normal(n: vec3<f32>, t: vec4<f32>, uv: vec2<f32>) -> vec3<f32> {
    let tangent = normalize(t.xyz - n * dot(n, t.xyz));
    let bitangent = cross(n, tangent) * t.w;
    let sampled = textureSample(normal_map, linear_sampler, uv).xyz * 2.0 - 1.0;
    let ts = vec3<f32>(sampled.xy * scene.normal_strength, sampled.z);
    return normalize(tangent * ts.x + bitangent * ts.y + n * ts.z);
}

@fragment
fn fs_main(in: FragmentInput) -> @location(0) vec4<f32> {
    let uv = in.uv * scene.uv_scale;
    let n = tbn_normal(normalize(in.normal), in.tangent, uv);
    let texel = textureSample(albedo_map, linear_sampler, uv);
    switch scene.view_mode {
        // Normals, as colors.
        case 1u: {
            return vec4<f32>(n * 0.5 + 0.5, 1.0);
        }
        // Albedo only.
        case 2u: {
            return vec4<f32>(texel.rgb, 1.0);
        }
        // Texture coordinates, and the tangent's handedness.
        case 3u, 4u: {
            return vec4<f32>(fract(uv), in.tangent.w * 0.5 + 0.5, 1.0);
        }
        // Lit: hemisphere ambient and normalized Blinn–Phong.
        default: {
            let l = normalize(scene.light_pos - in.world_pos);
            let v = normalize(scene.camera_pos - in.world_pos);
            let h = normalize(l + v);
            let hemi = mix(scene.ground_color, scene.sky_color, n.y * 0.5 + 0.5);
            let n_dot_l = max(dot(n, l), 0.0);
            let norm_factor = (scene.shininess + 8.0) / 25.13274;
            let spec = norm_factor * pow(max(dot(n, h), 0.0), scene.shininess) * texel.a * 0.04;
            let color = texel.rgb * hemi * 0.3
                + (texel.rgb * n_dot_l + vec3<f32>(spec * n_dot_l)) * scene.light_color;
            return vec4<f32>(clamp(color, vec3<f32>(0.0), vec3<f32>(1.0)), 1.0);
        }
    }
}
