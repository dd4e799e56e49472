// wood.wgsl: procedural varnished wood (solid texture) with a clear-coat layer.
//
// What it models
//   Growth rings are bands of the distance from the trunk axis (the object's y axis).
//   Two octaves of 3D value noise bend that distance so the rings wobble. Fine grain is
//   a third value-noise octave, stretched along the axis so it reads as fibers. Another
//   octave adds pores. The wood gets Lambert diffuse and a weak, broad base specular.
//   A clear coat on top adds a Schlick-Fresnel-weighted sharp highlight and darkens the
//   base by the energy the coat reflects.
//
// Inputs
//   @location(0) world_pos   world-space position (lighting)
//   @location(1) normal      world-space normal
//   @location(4) object_pos  object-space position (the trunk axis is the object's y axis)
//   Scene uniforms beyond the common three:
//     wood_scale:     f32        object-space to wood-space scale (about 1.5 for a unit mesh)
//     light_color:    vec3<f32>  point light color times intensity (about (1.0, 0.95, 0.88))
//     ring_frequency: f32        rings per wood-space unit of radius (about 6.0)
//   Textures: none.
//
// Notes
//   * The noise calls are written out one by one (no loops), and the hash is integer-only.
//   * The whole albedo (rings, grain, pores) depends only on object_pos and constant
//     uniforms. The coat highlight depends on camera and light.

struct FragmentInput {
    @location(0) world_pos: vec3<f32>,
    @location(1) normal: vec3<f32>,
    @location(4) object_pos: vec3<f32>,
};

struct Scene {
    camera_pos: vec3<f32>,
    time: f32,
    light_pos: vec3<f32>,
    wood_scale: f32,
    light_color: vec3<f32>,
    ring_frequency: f32,
};
@group(0) @binding(0) var<uniform> scene: Scene;

const EARLY_WOOD: vec3<f32> = vec3<f32>(0.62, 0.40, 0.20);
const LATE_WOOD: vec3<f32> = vec3<f32>(0.36, 0.19, 0.08);
const PORE_COLOR: vec3<f32> = vec3<f32>(0.22, 0.12, 0.05);
const AMBIENT: f32 = 0.15;
const BASE_SPECULAR: f32 = 0.06;
const BASE_SHININESS: f32 = 12.0;
const COAT_SHININESS: f32 = 180.0;
const COAT_F0: f32 = 0.04;

// Integer hash of a lattice cell to [0, 1].
fn hash01(c: vec3<i32>) -> f32 {
    let u = bitcast<vec3<u32>>(c);
    let h0 = (u.x * 73856093u) ^ (u.y * 19349663u) ^ (u.z * 83492791u);
    let h1 = (h0 ^ (h0 >> 15u)) * 0x2c1b3c6du;
    let h2 = (h1 ^ (h1 >> 12u)) * 0x297a2d39u;
    return f32((h2 ^ (h2 >> 15u)) & 0xffffu) * (1.0 / 65535.0);
}

// 3D value noise in [0, 1]: 8 hashed corners, smoothstep fade, trilinear mix.
fn value_noise(p: vec3<f32>) -> f32 {
    let pf = floor(p);
    let c = vec3<i32>(pf);
    let f = p - pf;
    let w = f * f * (vec3<f32>(3.0) - 2.0 * f);
    let v000 = hash01(c);
    let v100 = hash01(c + vec3<i32>(1, 0, 0));
    let v010 = hash01(c + vec3<i32>(0, 1, 0));
    let v110 = hash01(c + vec3<i32>(1, 1, 0));
    let v001 = hash01(c + vec3<i32>(0, 0, 1));
    let v101 = hash01(c + vec3<i32>(1, 0, 1));
    let v011 = hash01(c + vec3<i32>(0, 1, 1));
    let v111 = hash01(c + vec3<i32>(1, 1, 1));
    let x00 = mix(v000, v100, w.x);
    let x10 = mix(v010, v110, w.x);
    let x01 = mix(v001, v101, w.x);
    let x11 = mix(v011, v111, w.x);
    return mix(mix(x00, x10, w.y), mix(x01, x11, w.y), w.z);
}

@fragment
fn fs_main(in: FragmentInput) -> @location(0) vec4<f32> {
    let q = in.object_pos * scene.wood_scale;

    // Ring distortion: two octaves, low frequency along the axis.
    let d0 = value_noise(q * vec3<f32>(1.2, 0.35, 1.2)) - 0.5;
    let d1 = (value_noise(q * vec3<f32>(2.6, 0.7, 2.6) + vec3<f32>(7.1, 3.3, 1.9)) - 0.5) * 0.5;
    let distortion = d0 + d1;

    // Growth rings: distance from the y axis, bent by the distortion.
    let radius = length(q.xz + vec2<f32>(distortion * 0.35, distortion * 0.2));
    let ring = fract(radius * scene.ring_frequency + distortion * 1.5);
    let late = smoothstep(0.55, 0.8, ring) * (1.0 - smoothstep(0.9, 1.0, ring));
    let ring_color = mix(EARLY_WOOD, LATE_WOOD, late);

    // Fibers (stretched along the axis) and pores.
    let grain = value_noise(q * vec3<f32>(48.0, 2.0, 48.0) + vec3<f32>(11.0, 0.0, 5.0));
    let pores = smoothstep(0.72, 0.9, value_noise(q * vec3<f32>(90.0, 9.0, 90.0)));
    let fibered = ring_color * (0.82 + 0.3 * grain);
    let albedo = mix(fibered, PORE_COLOR, pores * 0.6);

    // Base layer: Lambert plus a weak broad specular.
    let n = normalize(in.normal);
    let l = normalize(scene.light_pos - in.world_pos);
    let v = normalize(scene.camera_pos - in.world_pos);
    let h = normalize(l + v);
    let n_dot_l = max(dot(n, l), 0.0);
    let n_dot_h = max(dot(n, h), 0.0);
    let n_dot_v = max(dot(n, v), 0.0);
    let base_diffuse = albedo * (scene.light_color * n_dot_l) + albedo * AMBIENT;
    let base_specular = scene.light_color * (BASE_SPECULAR * pow(n_dot_h, BASE_SHININESS) * n_dot_l);

    // Clear coat: Schlick Fresnel, sharp highlight, energy taken from the base.
    let fresnel = COAT_F0 + (1.0 - COAT_F0) * pow(1.0 - n_dot_v, 5.0);
    let coat = scene.light_color * (fresnel * pow(n_dot_h, COAT_SHININESS) * n_dot_l * 4.0);
    let base = (base_diffuse + base_specular) * (1.0 - fresnel);

    let color = clamp(base + coat, vec3<f32>(0.0), vec3<f32>(1.0));
    return vec4<f32>(color, 1.0);
}
