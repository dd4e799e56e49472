// envmap.wgsl: glossy, normal-mapped metal lit by an environment map (the paper's "Trashcan").
//
// What it models
//   A shiny metal surface (the Toyshop trash can). The detail comes from a tangent-space
//   normal map. The view vector is reflected about the perturbed normal. The glossy
//   reflection is 25 taps of an equirectangular environment map on a 5x5 grid of small
//   angular offsets around the reflection direction, weighted by a Gaussian kernel
//   (sigma = 1 grid step) and divided by the sum of the weights. A Schlick Fresnel tint
//   and a small Blinn–Phong highlight from the point light follow. Gamma (1/2.2) is the
//   last step.
//
// Inputs
//   @location(0) world_pos   world-space position
//   @location(1) normal      world-space normal
//   @location(2) uv          normal-map coordinates
//   @location(3) tangent     world-space tangent, w = bitangent sign
//   Scene uniforms beyond the common three:
//     sample_spread:   f32        angle between neighbouring env taps, radians (about 0.05)
//     base_color:      vec3<f32>  metal reflectance at normal incidence (about (0.85, 0.87, 0.9))
//     normal_strength: f32        scales the normal map's xy (1.0 = as authored, about 1.0)
//     light_color:     vec3<f32>  point light color times intensity (about (1.0, 0.95, 0.85))
//     env_intensity:   f32        env map radiance multiplier (about 1.0)
//   Textures (@group(1)):
//     normal_map:     tangent-space normal map, RGB = n * 0.5 + 0.5 (e.g. bumps, dents,
//                     ridges; flat = (0.5, 0.5, 1.0)). Read with textureSample at uv.
//     env_map:        equirectangular environment, linear RGB. u = longitude (atan2(z, x)),
//                     v = 0 at +Y (up) and 1 at -Y. E.g. sky gradient, ground, a few bright
//                     windows or blobs. Read with textureSampleLevel (LOD 0).
//     linear_sampler: linear filtering, repeat addressing (u wraps across the seam).
//
// Notes
//   * The 25 taps are 25 separate calls of env_tap (no loop), each scaled by its
//     Gaussian weight. Sums go from the lightest ring to the heaviest, and the center
//     tap is added last, so "all taps but the center" is one expression.
//   * The output is gamma-encoded (pow 1/2.2) and clamped to [0, 1], unlike the linear
//     output of the other shaders.

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
    sample_spread: f32,
    base_color: vec3<f32>,
    normal_strength: f32,
    light_color: vec3<f32>,
    env_intensity: f32,
};
@group(0) @binding(0) var<uniform> scene: Scene;

@group(1) @binding(0) var normal_map: texture_2d<f32>;
@group(1) @binding(1) var env_map: texture_2d<f32>;
@group(1) @binding(2) var linear_sampler: sampler;

const PI: f32 = 3.14159265;
// Gaussian weights exp(-(i^2 + j^2) / 2), indexed by i^2 + j^2.
const W0: f32 = 1.0;
const W1: f32 = 0.606531;
const W2: f32 = 0.367879;
const W4: f32 = 0.135335;
const W5: f32 = 0.082085;
const W8: f32 = 0.018316;
const W_SUM: f32 = W0 + 4.0 * W1 + 4.0 * W2 + 4.0 * W4 + 8.0 * W5 + 4.0 * W8;
const SHININESS: f32 = 120.0;

// Direction -> equirectangular texture coordinates.
fn equirect_uv(d: vec3<f32>) -> vec2<f32> {
    let u = atan2(d.z, d.x) * (0.5 / PI) + 0.5;
    let v = acos(clamp(d.y, -1.0, 1.0)) * (1.0 / PI);
    return vec2<f32>(u, v);
}

// One env map tap at grid offset `o` (in steps of sample_spread) around direction r,
// with t and b spanning the plane perpendicular to r.
fn env_tap(r: vec3<f32>, t: vec3<f32>, b: vec3<f32>, o: vec2<f32>) -> vec3<f32> {
    let d = normalize(r + (t * o.x + b * o.y) * scene.sample_spread);
    return textureSampleLevel(env_map, linear_sampler, equirect_uv(d), 0.0).rgb;
}

@fragment
fn fs_main(in: FragmentInput) -> @location(0) vec4<f32> {
    // Tangent frame and normal mapping.
    let n_geom = normalize(in.normal);
    let t_geom = normalize(in.tangent.xyz - n_geom * dot(n_geom, in.tangent.xyz));
    let b_geom = cross(n_geom, t_geom) * in.tangent.w;
    let n_tex = textureSample(normal_map, linear_sampler, in.uv).xyz * 2.0 - vec3<f32>(1.0);
    let n_ts = vec3<f32>(n_tex.xy * scene.normal_strength, n_tex.z);
    let n = normalize(t_geom * n_ts.x + b_geom * n_ts.y + n_geom * n_ts.z);

    // Reflection vector and a frame around it.
    let v = normalize(scene.camera_pos - in.world_pos);
    let r = reflect(-v, n);
    let up = select(vec3<f32>(0.0, 1.0, 0.0), vec3<f32>(1.0, 0.0, 0.0), abs(r.y) > 0.99);
    let t = normalize(cross(up, r));
    let b = cross(r, t);

    // 25 Gaussian-weighted env taps on a 5x5 grid, eIJ at offset (I - 2, J - 2).
    let e00 = env_tap(r, t, b, vec2<f32>(-2.0, -2.0)) * W8;
    let e01 = env_tap(r, t, b, vec2<f32>(-2.0, -1.0)) * W5;
    let e02 = env_tap(r, t, b, vec2<f32>(-2.0, 0.0)) * W4;
    let e03 = env_tap(r, t, b, vec2<f32>(-2.0, 1.0)) * W5;
    let e04 = env_tap(r, t, b, vec2<f32>(-2.0, 2.0)) * W8;
    let e10 = env_tap(r, t, b, vec2<f32>(-1.0, -2.0)) * W5;
    let e11 = env_tap(r, t, b, vec2<f32>(-1.0, -1.0)) * W2;
    let e12 = env_tap(r, t, b, vec2<f32>(-1.0, 0.0)) * W1;
    let e13 = env_tap(r, t, b, vec2<f32>(-1.0, 1.0)) * W2;
    let e14 = env_tap(r, t, b, vec2<f32>(-1.0, 2.0)) * W5;
    let e20 = env_tap(r, t, b, vec2<f32>(0.0, -2.0)) * W4;
    let e21 = env_tap(r, t, b, vec2<f32>(0.0, -1.0)) * W1;
    let e22 = env_tap(r, t, b, vec2<f32>(0.0, 0.0)) * W0;
    let e23 = env_tap(r, t, b, vec2<f32>(0.0, 1.0)) * W1;
    let e24 = env_tap(r, t, b, vec2<f32>(0.0, 2.0)) * W4;
    let e30 = env_tap(r, t, b, vec2<f32>(1.0, -2.0)) * W5;
    let e31 = env_tap(r, t, b, vec2<f32>(1.0, -1.0)) * W2;
    let e32 = env_tap(r, t, b, vec2<f32>(1.0, 0.0)) * W1;
    let e33 = env_tap(r, t, b, vec2<f32>(1.0, 1.0)) * W2;
    let e34 = env_tap(r, t, b, vec2<f32>(1.0, 2.0)) * W5;
    let e40 = env_tap(r, t, b, vec2<f32>(2.0, -2.0)) * W8;
    let e41 = env_tap(r, t, b, vec2<f32>(2.0, -1.0)) * W5;
    let e42 = env_tap(r, t, b, vec2<f32>(2.0, 0.0)) * W4;
    let e43 = env_tap(r, t, b, vec2<f32>(2.0, 1.0)) * W5;
    let e44 = env_tap(r, t, b, vec2<f32>(2.0, 2.0)) * W8;

    // Rings from the lightest weight to the heaviest; the center tap last.
    let ring8 = e00 + e04 + e40 + e44;
    let ring5 = e01 + e03 + e10 + e14 + e30 + e34 + e41 + e43;
    let ring4 = e02 + e20 + e24 + e42;
    let ring2 = e11 + e13 + e31 + e33;
    let ring1 = e12 + e21 + e23 + e32;
    let outer = ring8 + ring5 + ring4 + ring2 + ring1;
    let total = outer + e22;
    let glossy = total * (scene.env_intensity / W_SUM);

    // Schlick Fresnel on the metal's color.
    let n_dot_v = max(dot(n, v), 0.0);
    let fresnel = scene.base_color + (vec3<f32>(1.0) - scene.base_color) * pow(1.0 - n_dot_v, 5.0);
    let reflection = glossy * fresnel;

    // Small Blinn–Phong highlight from the point light.
    let l = normalize(scene.light_pos - in.world_pos);
    let h = normalize(l + v);
    let n_dot_l = max(dot(n, l), 0.0);
    let highlight = scene.light_color * scene.base_color * (pow(max(dot(n, h), 0.0), SHININESS) * n_dot_l);

    let linear_color = clamp(reflection + highlight, vec3<f32>(0.0), vec3<f32>(1.0));
    let encoded = pow(linear_color, vec3<f32>(1.0 / 2.2));
    return vec4<f32>(encoded, 1.0);
}
