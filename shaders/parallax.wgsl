// parallax.wgsl: parallax occlusion mapping with self-shadowing and normal-mapped
// Blinn–Phong (stone or brick walls and floors in a game engine).
//
// What it models
//   A flat surface that looks deeply relieved. The view ray is marched through a height
//   field in tangent space: 24 fixed steps of textureSampleLevel on the height map, then
//   one secant refinement between the last two samples. The texture coordinates at the
//   hit point then drive the albedo and normal maps. A second march of 8 steps toward
//   the light gives soft self-shadowing. Lighting is Blinn–Phong from one point light
//   plus a constant ambient term.
//
// Inputs
//   @location(0) world_pos   world-space position
//   @location(1) normal      world-space normal
//   @location(2) uv          texture coordinates (the maps tile; repeat addressing)
//   @location(3) tangent     world-space tangent (direction of +u), w = bitangent sign
//   Scene uniforms beyond the common three:
//     height_scale: f32        relief depth in uv units (about 0.05)
//     light_color:  vec3<f32>  point light color times intensity (about (1.0, 0.95, 0.85))
//     shininess:    f32        Blinn–Phong exponent (about 32)
//   Textures (@group(1)):
//     albedo_map:     diffuse color, linear RGB (e.g. bricks and mortar, or cobblestones).
//                     textureSample at the parallax-shifted uv.
//     normal_map:     tangent-space normal map of the same relief, RGB = n * 0.5 + 0.5.
//                     textureSample at the parallax-shifted uv.
//     height_map:     relief height in R, 1 = top surface, 0 = deepest (e.g. bricks high,
//                     mortar grooves low). textureSampleLevel LOD 0 inside the loops.
//     linear_sampler: linear filtering, repeat addressing.
//
// Notes
//   * Both marches run a constant number of steps. A step past the hit point is frozen
//     with select() instead of a break, so control flow stays uniform.
//   * The view march depends on the camera, the shadow march on the light. Only the
//     albedo at the original uv would stay fixed from frame to frame. Most of this
//     shader is view-dependent, the hard case for reprojection.

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
};
@group(0) @binding(0) var<uniform> scene: Scene;

@group(1) @binding(0) var albedo_map: texture_2d<f32>;
@group(1) @binding(1) var normal_map: texture_2d<f32>;
@group(1) @binding(2) var height_map: texture_2d<f32>;
@group(1) @binding(3) var linear_sampler: sampler;

const VIEW_STEPS: u32 = 24u;
const SHADOW_STEPS: u32 = 8u;
const AMBIENT: f32 = 0.15;
const SPECULAR: f32 = 0.25;

// Depth below the top surface at uv, in [0, 1].
fn depth_at(uv: vec2<f32>) -> f32 {
    return 1.0 - textureSampleLevel(height_map, linear_sampler, uv, 0.0).r;
}

@fragment
fn fs_main(in: FragmentInput) -> @location(0) vec4<f32> {
    // Tangent frame.
    let n_geom = normalize(in.normal);
    let t_geom = normalize(in.tangent.xyz - n_geom * dot(n_geom, in.tangent.xyz));
    let b_geom = cross(n_geom, t_geom) * in.tangent.w;
    let v = normalize(scene.camera_pos - in.world_pos);
    let l = normalize(scene.light_pos - in.world_pos);
    let v_ts = vec3<f32>(dot(v, t_geom), dot(v, b_geom), dot(v, n_geom));
    let l_ts = vec3<f32>(dot(l, t_geom), dot(l, b_geom), dot(l, n_geom));

    // View ray march through the height field.
    let layer_step = 1.0 / f32(VIEW_STEPS);
    let uv_step = -v_ts.xy / max(v_ts.z, 0.2) * (scene.height_scale * layer_step);
    var cur_uv = in.uv;
    var cur_layer: f32 = 0.0;
    var cur_depth = depth_at(in.uv);
    var prev_uv = in.uv;
    var prev_layer: f32 = 0.0;
    var prev_depth = cur_depth;
    for (var i: u32 = 0u; i < VIEW_STEPS; i = i + 1u) {
        let above = cur_layer < cur_depth;
        let next_uv = cur_uv + uv_step;
        let next_layer = cur_layer + layer_step;
        let next_depth = depth_at(next_uv);
        prev_uv = select(prev_uv, cur_uv, above);
        prev_layer = select(prev_layer, cur_layer, above);
        prev_depth = select(prev_depth, cur_depth, above);
        cur_uv = select(cur_uv, next_uv, above);
        cur_layer = select(cur_layer, next_layer, above);
        cur_depth = select(cur_depth, next_depth, above);
    }

    // Secant refinement between the last point above and the first point below.
    let after = cur_depth - cur_layer;
    let before = prev_depth - prev_layer;
    let denom = before - after;
    let w = clamp(select(0.0, -after / denom, abs(denom) > 1e-5), 0.0, 1.0);
    let hit_uv = mix(cur_uv, prev_uv, w);
    let hit_height = 1.0 - mix(cur_layer, prev_layer, w);

    // Soft self-shadow: march from the hit point up toward the light.
    let shadow_dir = l_ts.xy / max(l_ts.z, 0.2) * scene.height_scale;
    var occlusion: f32 = 0.0;
    for (var j: u32 = 1u; j <= SHADOW_STEPS; j = j + 1u) {
        let f = f32(j) / f32(SHADOW_STEPS);
        let ray_height = hit_height + (1.0 - hit_height) * f;
        let sample_height = 1.0 - depth_at(hit_uv + shadow_dir * (ray_height - hit_height));
        occlusion = max(occlusion, (sample_height - ray_height) * (1.0 - f) * 8.0);
    }
    let light_visible = (1.0 - clamp(occlusion, 0.0, 1.0)) * select(0.0, 1.0, l_ts.z > 0.0);

    // Shading at the displaced texture coordinates.
    let albedo = textureSample(albedo_map, linear_sampler, hit_uv).rgb;
    let n_tex = textureSample(normal_map, linear_sampler, hit_uv).xyz * 2.0 - vec3<f32>(1.0);
    let n = normalize(t_geom * n_tex.x + b_geom * n_tex.y + n_geom * n_tex.z);
    let h = normalize(l + v);
    let n_dot_l = max(dot(n, l), 0.0);
    let n_dot_h = max(dot(n, h), 0.0);
    let direct = scene.light_color * (light_visible * n_dot_l);
    let diffuse = albedo * direct;
    let specular = direct * (SPECULAR * pow(n_dot_h, scene.shininess));
    let ambient = albedo * AMBIENT;

    let color = clamp(ambient + diffuse + specular, vec3<f32>(0.0), vec3<f32>(1.0));
    return vec4<f32>(color, 1.0);
}
