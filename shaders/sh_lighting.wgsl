// sh_lighting.wgsl: spherical-harmonics ambient plus a translucent (subsurface) point light.
//
// What it models
//   The usual engine split for skin, wax, jade or leaves:
//   * Diffuse ambient from an environment's irradiance, stored as 9 spherical-harmonics
//     coefficients (bands 0-2) in uniforms. It is evaluated per pixel with the closed
//     form of Ramamoorthi & Hanrahan 2001.
//   * Wrap-lighting diffuse from the point light.
//   * Translucency: the fast back-lit approximation of Barré-Brisebois & Bouchard
//     (GDC 2011). The light vector is distorted by the normal, the view is raised to a
//     power against it, and the result is scaled by (1 - local thickness) from a texture.
//   * A weak Blinn–Phong sheen.
//
// Inputs
//   @location(0) world_pos   world-space position
//   @location(1) normal      world-space normal
//   @location(2) uv          texture coordinates
//   Scene uniforms beyond the common three:
//     sh_intensity:            f32        multiplier on the SH irradiance (about 1.0)
//     light_color:             vec3<f32>  point light color times intensity (about (1.0, 0.9, 0.8))
//     translucency_distortion: f32        normal distortion of the light vector (about 0.3)
//     subsurface_color:        vec3<f32>  color of light scattered through (about (1.0, 0.35, 0.2))
//     translucency_power:      f32        view falloff exponent (about 4.0)
//     sh0:                     vec3<f32>  L00     (Grace Cathedral: (0.79, 0.44, 0.54))
//     translucency_scale:      f32        back-light strength (about 1.5)
//     sh1:                     vec3<f32>  L1,-1 (y) (( 0.39,  0.35,  0.60))
//     shininess:               f32        sheen exponent (about 24)
//     sh2:                     vec3<f32>  L1,0  (z) ((-0.34, -0.18, -0.27))
//     sh3:                     vec3<f32>  L1,1  (x) ((-0.29, -0.06,  0.01))
//     sh4:                     vec3<f32>  L2,-2 (xy) ((-0.11, -0.05, -0.12))
//     sh5:                     vec3<f32>  L2,-1 (yz) ((-0.26, -0.22, -0.47))
//     sh6:                     vec3<f32>  L2,0  (3z^2 - 1) ((-0.16, -0.09, -0.15))
//     sh7:                     vec3<f32>  L2,1  (xz) (( 0.56,  0.21,  0.14))
//     sh8:                     vec3<f32>  L2,2  (x^2 - y^2) (( 0.21, -0.05, -0.30))
//     (The SH basis is evaluated on the world-space normal's x, y, z as written.)
//   Textures (@group(1)):
//     albedo_map:     diffuse color, linear RGB (e.g. pale skin or wax with mottling).
//                     textureSample at uv.
//     thickness_map:  local thickness in R, 0 = thin (glows when back-lit), 1 = thick
//                     (e.g. smooth blobs or the inverse of an AO bake). textureSample at uv.
//     linear_sampler: linear filtering, repeat addressing.
//
// Notes
//   * The uniform block has no explicit padding fields. Each vec3 sits on a 16-byte
//     boundary; where no scalar follows it, WGSL pads the gap implicitly.
//   * The SH ambient depends only on the normal and uniforms; translucency and sheen
//     depend on camera and light.

struct FragmentInput {
    @location(0) world_pos: vec3<f32>,
    @location(1) normal: vec3<f32>,
    @location(2) uv: vec2<f32>,
};

struct Scene {
    camera_pos: vec3<f32>,
    time: f32,
    light_pos: vec3<f32>,
    sh_intensity: f32,
    light_color: vec3<f32>,
    translucency_distortion: f32,
    subsurface_color: vec3<f32>,
    translucency_power: f32,
    sh0: vec3<f32>,
    translucency_scale: f32,
    sh1: vec3<f32>,
    shininess: f32,
    sh2: vec3<f32>,
    sh3: vec3<f32>,
    sh4: vec3<f32>,
    sh5: vec3<f32>,
    sh6: vec3<f32>,
    sh7: vec3<f32>,
    sh8: vec3<f32>,
};
@group(0) @binding(0) var<uniform> scene: Scene;

@group(1) @binding(0) var albedo_map: texture_2d<f32>;
@group(1) @binding(1) var thickness_map: texture_2d<f32>;
@group(1) @binding(2) var linear_sampler: sampler;

// Ramamoorthi & Hanrahan irradiance constants.
const C1: f32 = 0.429043;
const C2: f32 = 0.511664;
const C3: f32 = 0.743125;
const C4: f32 = 0.886227;
const C5: f32 = 0.247708;
const WRAP: f32 = 0.4;
const SHEEN: f32 = 0.12;
const TRANSLUCENCY_AMBIENT: f32 = 0.05;

// Irradiance at normal n from the 9 SH coefficients in the uniforms.
fn sh_irradiance(n: vec3<f32>) -> vec3<f32> {
    let x = n.x;
    let y = n.y;
    let z = n.z;
    let band0 = C4 * scene.sh0 - C5 * scene.sh6;
    let band1 = 2.0 * C2 * (scene.sh3 * x + scene.sh1 * y + scene.sh2 * z);
    let band2 = C1 * scene.sh8 * (x * x - y * y) + C3 * scene.sh6 * (z * z)
        + 2.0 * C1 * (scene.sh4 * (x * y) + scene.sh7 * (x * z) + scene.sh5 * (y * z));
    return max(band0 + band1 + band2, vec3<f32>(0.0));
}

@fragment
fn fs_main(in: FragmentInput) -> @location(0) vec4<f32> {
    let n = normalize(in.normal);
    let l = normalize(scene.light_pos - in.world_pos);
    let v = normalize(scene.camera_pos - in.world_pos);
    let albedo = textureSample(albedo_map, linear_sampler, in.uv).rgb;
    let thickness = textureSample(thickness_map, linear_sampler, in.uv).r;

    // Ambient from the spherical-harmonics environment.
    let irradiance = sh_irradiance(n) * scene.sh_intensity;
    let ambient = albedo * irradiance;

    // Wrap diffuse from the point light.
    let wrap = max((dot(n, l) + WRAP) / (1.0 + WRAP), 0.0);
    let diffuse = albedo * scene.light_color * wrap;

    // Translucency: light through the thin parts toward the viewer.
    let l_t = normalize(l + n * scene.translucency_distortion);
    let back = pow(clamp(dot(v, -l_t), 0.0, 1.0), scene.translucency_power) * scene.translucency_scale;
    let transmitted = (back + TRANSLUCENCY_AMBIENT) * (1.0 - thickness);
    let translucency = scene.subsurface_color * scene.light_color * (albedo * transmitted);

    // Weak sheen.
    let h = normalize(l + v);
    let n_dot_l = max(dot(n, l), 0.0);
    let sheen = scene.light_color * (SHEEN * pow(max(dot(n, h), 0.0), scene.shininess) * n_dot_l);

    let color = clamp(ambient + diffuse + translucency + sheen, vec3<f32>(0.0), vec3<f32>(1.0));
    return vec4<f32>(color, 1.0);
}
