// ambient_occlusion.wgsl: disc-based ambient occlusion (Bunnell 2005) with a diffuse
// texture and Blinn–Phong (the paper's "Ambient Occlusion" shader).
//
// What it models
//   A receiver surface (a ground plane or board around the origin) shaded with ambient
//   occlusion from nearby objects. Each object is approximated by oriented discs, and
//   each disc occludes the shaded point by Bunnell's disc-to-point form factor:
//     occ = (1 - 1/sqrt(1 + area / (pi d^2))) * sat(0.5 + 0.5 dot(n_e, -v)) * sat(4 dot(n_r, v))
//   (v = unit vector from the point to the disc center, d = its distance; the emitter
//   term is half-wrapped so that discs seen edge-on still occlude).
//   Static scene: four columns standing on y = 0, eight discs each, in a const array of
//   objects (outer loop over objects, inner loop over discs, into `static_ao`).
//   Moving occluder: a sphere (the paper's moving king) of six discs around
//   scene.occluder_pos, summed in its own loop into `moving_ao`.
//   After the loops, the occlusion is applied to a diffuse texture lit by Blinn–Phong:
//   the ambient term and the diffuse term are both scaled by the AO.
//
// Inputs
//   @location(0) world_pos   world-space position (scene units: the columns stand within
//                            |x|, |z| < 2 on the plane y = 0)
//   @location(1) normal      world-space normal
//   @location(2) uv          albedo texture coordinates
//   Scene uniforms beyond the common three:
//     shininess:       f32        Blinn–Phong exponent (about 40)
//     occluder_pos:    vec3<f32>  moving sphere center, world space (keyframed, e.g. a
//                                 circle of radius 1 at height 0.5 around the origin)
//     occluder_radius: f32        moving sphere radius (about 0.4)
//     light_color:     vec3<f32>  point light color times intensity (about (1.0, 0.95, 0.9))
//     ao_strength:     f32        occlusion multiplier (about 1.0)
//     ambient_color:   vec3<f32>  sky/ambient light (about (0.35, 0.38, 0.45))
//     uv_scale:        f32        albedo tiling (about 4.0)
//   Textures (@group(1)):
//     albedo_map:     diffuse color, linear RGB (e.g. a checkerboard or tiles, board-like).
//                     Read with textureSample at uv * uv_scale.
//     linear_sampler: linear filtering, repeat addressing.
//
// Notes
//   * The occluders are virtual: the shader only needs the receiver mesh (a plane from
//     about -3 to 3 in x and z works well). The moving sphere's occlusion changes every
//     frame; the static sum does not depend on camera, light or time.
//   * `ao_static` is read after its loops as a plain value, so the optimizer can cache
//     the whole static sum apart from the moving part.
//   * Loop trip counts are constants (4 x 8 static discs, 6 moving discs).

struct FragmentInput {
    @location(0) world_pos: vec3<f32>,
    @location(1) normal: vec3<f32>,
    @location(2) uv: vec2<f32>,
};

struct Scene {
    camera_pos: vec3<f32>,
    time: f32,
    light_pos: vec3<f32>,
    shininess: f32,
    occluder_pos: vec3<f32>,
    occluder_radius: f32,
    light_color: vec3<f32>,
    ao_strength: f32,
    ambient_color: vec3<f32>,
    uv_scale: f32,
};
@group(0) @binding(0) var<uniform> scene: Scene;

@group(1) @binding(0) var albedo_map: texture_2d<f32>;
@group(1) @binding(1) var linear_sampler: sampler;

const PI: f32 = 3.14159265;
const SPECULAR: f32 = 0.3;

struct Disc {
    center: vec3<f32>,
    normal: vec3<f32>,
    area: f32,
};

struct Occluder {
    discs: array<Disc, 8>,
};

const NUM_OBJECTS: u32 = 4u;
const DISCS_PER_OBJECT: u32 = 8u;

// Static occluders: columns with two rings of four outward-facing discs each.
const STATIC_OBJECTS: array<Occluder, 4> = array<Occluder, 4>(
    // object 0: column at x = -1.4, z = -0.9, radius 0.35, height 1.2
    Occluder(array<Disc, 8>(
        Disc(vec3<f32>(-1.050, 0.300, -0.900), vec3<f32>(1.000, 0.0, 0.0), 0.3299),
        Disc(vec3<f32>(-1.400, 0.300, -0.550), vec3<f32>(0.0, 0.0, 1.000), 0.3299),
        Disc(vec3<f32>(-1.750, 0.300, -0.900), vec3<f32>(-1.000, 0.0, 0.0), 0.3299),
        Disc(vec3<f32>(-1.400, 0.300, -1.250), vec3<f32>(0.0, 0.0, -1.000), 0.3299),
        Disc(vec3<f32>(-1.153, 0.840, -0.653), vec3<f32>(0.707, 0.0, 0.707), 0.3299),
        Disc(vec3<f32>(-1.647, 0.840, -0.653), vec3<f32>(-0.707, 0.0, 0.707), 0.3299),
        Disc(vec3<f32>(-1.647, 0.840, -1.147), vec3<f32>(-0.707, 0.0, -0.707), 0.3299),
        Disc(vec3<f32>(-1.153, 0.840, -1.147), vec3<f32>(0.707, 0.0, -0.707), 0.3299),
    )),
    // object 1: column at x = 1.3, z = -1.2, radius 0.3, height 0.9
    Occluder(array<Disc, 8>(
        Disc(vec3<f32>(1.600, 0.225, -1.200), vec3<f32>(1.000, 0.0, 0.0), 0.2121),
        Disc(vec3<f32>(1.300, 0.225, -0.900), vec3<f32>(0.0, 0.0, 1.000), 0.2121),
        Disc(vec3<f32>(1.000, 0.225, -1.200), vec3<f32>(-1.000, 0.0, 0.0), 0.2121),
        Disc(vec3<f32>(1.300, 0.225, -1.500), vec3<f32>(0.0, 0.0, -1.000), 0.2121),
        Disc(vec3<f32>(1.512, 0.630, -0.988), vec3<f32>(0.707, 0.0, 0.707), 0.2121),
        Disc(vec3<f32>(1.088, 0.630, -0.988), vec3<f32>(-0.707, 0.0, 0.707), 0.2121),
        Disc(vec3<f32>(1.088, 0.630, -1.412), vec3<f32>(-0.707, 0.0, -0.707), 0.2121),
        Disc(vec3<f32>(1.512, 0.630, -1.412), vec3<f32>(0.707, 0.0, -0.707), 0.2121),
    )),
    // object 2: column at x = -0.9, z = 1.3, radius 0.4, height 1.4
    Occluder(array<Disc, 8>(
        Disc(vec3<f32>(-0.500, 0.350, 1.300), vec3<f32>(1.000, 0.0, 0.0), 0.4398),
        Disc(vec3<f32>(-0.900, 0.350, 1.700), vec3<f32>(0.0, 0.0, 1.000), 0.4398),
        Disc(vec3<f32>(-1.300, 0.350, 1.300), vec3<f32>(-1.000, 0.0, 0.0), 0.4398),
        Disc(vec3<f32>(-0.900, 0.350, 0.900), vec3<f32>(0.0, 0.0, -1.000), 0.4398),
        Disc(vec3<f32>(-0.617, 0.980, 1.583), vec3<f32>(0.707, 0.0, 0.707), 0.4398),
        Disc(vec3<f32>(-1.183, 0.980, 1.583), vec3<f32>(-0.707, 0.0, 0.707), 0.4398),
        Disc(vec3<f32>(-1.183, 0.980, 1.017), vec3<f32>(-0.707, 0.0, -0.707), 0.4398),
        Disc(vec3<f32>(-0.617, 0.980, 1.017), vec3<f32>(0.707, 0.0, -0.707), 0.4398),
    )),
    // object 3: column at x = 1.5, z = 1.0, radius 0.3, height 1.0
    Occluder(array<Disc, 8>(
        Disc(vec3<f32>(1.800, 0.250, 1.000), vec3<f32>(1.000, 0.0, 0.0), 0.2356),
        Disc(vec3<f32>(1.500, 0.250, 1.300), vec3<f32>(0.0, 0.0, 1.000), 0.2356),
        Disc(vec3<f32>(1.200, 0.250, 1.000), vec3<f32>(-1.000, 0.0, 0.0), 0.2356),
        Disc(vec3<f32>(1.500, 0.250, 0.700), vec3<f32>(0.0, 0.0, -1.000), 0.2356),
        Disc(vec3<f32>(1.712, 0.700, 1.212), vec3<f32>(0.707, 0.0, 0.707), 0.2356),
        Disc(vec3<f32>(1.288, 0.700, 1.212), vec3<f32>(-0.707, 0.0, 0.707), 0.2356),
        Disc(vec3<f32>(1.288, 0.700, 0.788), vec3<f32>(-0.707, 0.0, -0.707), 0.2356),
        Disc(vec3<f32>(1.712, 0.700, 0.788), vec3<f32>(0.707, 0.0, -0.707), 0.2356),
    )),
);

// Moving sphere: six discs at the sphere's surface, one per axis direction.
const SPHERE_DISCS: u32 = 6u;
const SPHERE_DIRS: array<vec3<f32>, 6> = array<vec3<f32>, 6>(
    vec3<f32>(1.0, 0.0, 0.0),
    vec3<f32>(-1.0, 0.0, 0.0),
    vec3<f32>(0.0, 1.0, 0.0),
    vec3<f32>(0.0, -1.0, 0.0),
    vec3<f32>(0.0, 0.0, 1.0),
    vec3<f32>(0.0, 0.0, -1.0),
);

// Bunnell's disc-to-point occlusion of receiver (p, n) by disc (center, normal, area).
fn disc_occlusion(p: vec3<f32>, n: vec3<f32>, center: vec3<f32>, normal: vec3<f32>, area: f32) -> f32 {
    let d = center - p;
    let d2 = dot(d, d) + 1e-4;
    let v = d * inverseSqrt(d2);
    let solid = 1.0 - inverseSqrt(1.0 + area / (PI * d2));
    let emitter = clamp(0.5 + 0.5 * dot(normal, -v), 0.0, 1.0);
    let receiver = clamp(4.0 * dot(n, v), 0.0, 1.0);
    return solid * emitter * receiver;
}

@fragment
fn fs_main(in: FragmentInput) -> @location(0) vec4<f32> {
    let p = in.world_pos;
    let n = normalize(in.normal);

    // Local copies of the const tables: indexing a const array with a loop counter makes
    // naga's SPIR-V backend copy the whole array at every access (25x slower on lavapipe).
    var objects = STATIC_OBJECTS;
    var sphere_dirs = SPHERE_DIRS;

    // Static occluders: objects, then each object's discs.
    var static_ao: f32 = 0.0;
    for (var o: u32 = 0u; o < NUM_OBJECTS; o = o + 1u) {
        for (var k: u32 = 0u; k < DISCS_PER_OBJECT; k = k + 1u) {
            let disc = objects[o].discs[k];
            static_ao = static_ao + disc_occlusion(p, n, disc.center, disc.normal, disc.area);
        }
    }
    let ao_static = static_ao;

    // Moving occluder, summed apart.
    let r = scene.occluder_radius;
    let sphere_disc_area = (4.0 * PI / 6.0) * r * r;
    var moving_ao: f32 = 0.0;
    for (var i: u32 = 0u; i < SPHERE_DISCS; i = i + 1u) {
        let dir = sphere_dirs[i];
        moving_ao = moving_ao + disc_occlusion(p, n, scene.occluder_pos + dir * r, dir, sphere_disc_area);
    }
    let ao_moving = moving_ao;

    // Combine.
    let occlusion = (ao_static + ao_moving) * scene.ao_strength;
    let ao = clamp(1.0 - occlusion, 0.0, 1.0);

    // Diffuse texture lit by Blinn–Phong.
    let albedo = textureSample(albedo_map, linear_sampler, in.uv * scene.uv_scale).rgb;
    let l = normalize(scene.light_pos - p);
    let v = normalize(scene.camera_pos - p);
    let h = normalize(l + v);
    let n_dot_l = max(dot(n, l), 0.0);
    let ao_diffuse = ao * n_dot_l;
    let ambient = albedo * scene.ambient_color * ao;
    let diffuse = albedo * scene.light_color * ao_diffuse;
    let spec_mask = select(0.0, 1.0, n_dot_l > 0.0);
    let specular = scene.light_color * (SPECULAR * pow(max(dot(n, h), 0.0), scene.shininess) * spec_mask);

    let color = clamp(ambient + diffuse + specular, vec3<f32>(0.0), vec3<f32>(1.0));
    return vec4<f32>(color, 1.0);
}
