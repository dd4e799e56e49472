// marble.wgsl: procedural marble with a Blinn–Phong specular layer.
//
// What it models
//   The paper's "Marble" shader. The albedo is a solid texture: five octaves of 3D
//   gradient (Perlin-style) noise on the object-space position, summed as turbulence,
//   bend the stripes of sin(x * frequency + turbulence) into veins: a smoothstep of the
//   stripe value's magnitude draws thin dark veins on a light, cloudy base (the cloud is
//   the turbulence itself). On top go Lambert diffuse plus a Blinn–Phong highlight from
//   one point light.
//
// Inputs
//   @location(0) world_pos   world-space position (lighting)
//   @location(1) normal      world-space normal
//   @location(4) object_pos  object-space position (solid texture: the veins stick to
//                            the object while it moves)
//   Scene uniforms beyond the common three:
//     shininess:   f32        Blinn–Phong exponent (about 60)
//     light_color: vec3<f32>  light color times intensity (about (1.0, 0.97, 0.9))
//     noise_scale: f32        object-space to noise-space scale (about 2.0 for a unit-sized mesh)
//   Textures: none.
//
// Notes
//   * The octaves are written out one by one (n0..n4, partial sums s1..s4), with no
//     loop, so each octave and each partial sum is its own expression. The optimizer
//     can then cache the low-frequency octaves, a partial sum, or the whole noise term.
//   * gradient_noise is straight-line too: 8 hashed corner gradients, quintic fade,
//     trilinear mix. Each corner's gradient comes from the classic GPU sine hash
//     (fract(sin(dot(c, k)) * 43758.5453), three per corner) and is normalized, as in
//     most real-time procedural shaders; that makes the noise the bulk of the cost.
//   * The noise does not depend on camera, light or time. Lighting does.

struct FragmentInput {
    @location(0) world_pos: vec3<f32>,
    @location(1) normal: vec3<f32>,
    @location(4) object_pos: vec3<f32>,
};

struct Scene {
    camera_pos: vec3<f32>,
    time: f32,
    light_pos: vec3<f32>,
    shininess: f32,
    light_color: vec3<f32>,
    noise_scale: f32,
};
@group(0) @binding(0) var<uniform> scene: Scene;

const VEIN_COLOR: vec3<f32> = vec3<f32>(0.20, 0.17, 0.22);
const BASE_COLOR: vec3<f32> = vec3<f32>(0.88, 0.86, 0.82);
const CLOUD_COLOR: vec3<f32> = vec3<f32>(0.66, 0.66, 0.68);
const VEIN_FREQUENCY: f32 = 6.0;
const TURBULENCE_GAIN: f32 = 4.0;
const AMBIENT: f32 = 0.12;
const SPECULAR: f32 = 0.45;

// Pseudo-random unit gradient at lattice point `c` (the classic sine hash), dotted with the offset
// `d` from that corner.
fn corner_grad(c: vec3<f32>, d: vec3<f32>) -> f32 {
    let q = vec3<f32>(
        dot(c, vec3<f32>(127.1, 311.7, 74.7)),
        dot(c, vec3<f32>(269.5, 183.3, 246.1)),
        dot(c, vec3<f32>(113.5, 271.9, 124.6)),
    );
    let g = normalize(fract(sin(q) * 43758.5453) * 2.0 - vec3<f32>(1.0));
    return dot(g, d);
}

// 3D gradient noise, roughly in [-1, 1]; straight-line code (no loops).
fn gradient_noise(p: vec3<f32>) -> f32 {
    let pf = floor(p);
    let c = pf;
    let f = p - pf;
    // quintic fade 6t^5 - 15t^4 + 10t^3
    let w = f * f * f * (f * (f * 6.0 - vec3<f32>(15.0)) + vec3<f32>(10.0));
    let g000 = corner_grad(c, f);
    let g100 = corner_grad(c + vec3<f32>(1.0, 0.0, 0.0), f - vec3<f32>(1.0, 0.0, 0.0));
    let g010 = corner_grad(c + vec3<f32>(0.0, 1.0, 0.0), f - vec3<f32>(0.0, 1.0, 0.0));
    let g110 = corner_grad(c + vec3<f32>(1.0, 1.0, 0.0), f - vec3<f32>(1.0, 1.0, 0.0));
    let g001 = corner_grad(c + vec3<f32>(0.0, 0.0, 1.0), f - vec3<f32>(0.0, 0.0, 1.0));
    let g101 = corner_grad(c + vec3<f32>(1.0, 0.0, 1.0), f - vec3<f32>(1.0, 0.0, 1.0));
    let g011 = corner_grad(c + vec3<f32>(0.0, 1.0, 1.0), f - vec3<f32>(0.0, 1.0, 1.0));
    let g111 = corner_grad(c + vec3<f32>(1.0, 1.0, 1.0), f - vec3<f32>(1.0, 1.0, 1.0));
    let x00 = mix(g000, g100, w.x);
    let x10 = mix(g010, g110, w.x);
    let x01 = mix(g001, g101, w.x);
    let x11 = mix(g011, g111, w.x);
    let y0 = mix(x00, x10, w.y);
    let y1 = mix(x01, x11, w.y);
    return mix(y0, y1, w.z);
}

@fragment
fn fs_main(in: FragmentInput) -> @location(0) vec4<f32> {
    // Solid-texture coordinates.
    let p = in.object_pos * scene.noise_scale;

    // Turbulence: five octaves of |noise|, each its own expression.
    let n0 = abs(gradient_noise(p));
    let n1 = abs(gradient_noise(p * 2.0 + vec3<f32>(17.3, 5.1, 9.7))) * 0.5;
    let n2 = abs(gradient_noise(p * 4.0 + vec3<f32>(3.7, 31.9, 11.3))) * 0.25;
    let n3 = abs(gradient_noise(p * 8.0 + vec3<f32>(23.1, 7.7, 41.5))) * 0.125;
    let n4 = abs(gradient_noise(p * 16.0 + vec3<f32>(5.9, 13.3, 29.1))) * 0.0625;
    let s1 = n0 + n1;
    let s2 = s1 + n2;
    let s3 = s2 + n3;
    let s4 = s3 + n4;
    let turbulence = s4;

    // Marble veins: stripes along x, bent by the turbulence.
    let stripes = sin(p.x * VEIN_FREQUENCY + turbulence * TURBULENCE_GAIN);
    let vein = smoothstep(0.0, 0.5, abs(stripes));
    let cloudy = mix(BASE_COLOR, CLOUD_COLOR, clamp(turbulence * 0.8, 0.0, 1.0));
    let albedo = mix(VEIN_COLOR, cloudy, vein);

    // Blinn–Phong with one point light.
    let n = normalize(in.normal);
    let l = normalize(scene.light_pos - in.world_pos);
    let v = normalize(scene.camera_pos - in.world_pos);
    let h = normalize(l + v);
    let n_dot_l = max(dot(n, l), 0.0);
    let n_dot_h = max(dot(n, h), 0.0);
    let diffuse = albedo * (n_dot_l * scene.light_color);
    let ambient = albedo * AMBIENT;
    let spec_mask = select(0.0, 1.0, n_dot_l > 0.0);
    let specular = scene.light_color * (SPECULAR * pow(n_dot_h, scene.shininess) * spec_mask);

    let color = clamp(ambient + diffuse + specular, vec3<f32>(0.0), vec3<f32>(1.0));
    return vec4<f32>(color, 1.0);
}
