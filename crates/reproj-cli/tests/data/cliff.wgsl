// Non-finite fixture (`crates/reproj-cli/tests/nonfinite.rs`): the two-term shader whose albedo
// sum `a` sits 1e-5 above 1 and is read through log(a - 1). The original is finite everywhere;
// a variant caching `a` resamples it, and where the bilinear fetch mixes texels the difference
// can fall to 0 or below: log gives -inf or NaN. Such a node must be set aside, never scored.
struct FragmentInput {
    @builtin(position) frag_coord: vec4<f32>,
    @location(0) world_pos: vec3<f32>,
    @location(1) normal: vec3<f32>,
    @location(2) uv: vec2<f32>,
};

struct Scene {
    camera_pos: vec3<f32>,
    time: f32,
    light_pos: vec3<f32>,
    gain: f32,
    tint: vec3<f32>,
};

@group(0) @binding(0) var<uniform> scene: Scene;

@fragment
fn fs_main(in: FragmentInput) -> @location(0) vec4<f32> {
    let p = in.world_pos;
    var a = 1.0;
    for (var i = 0; i < 192; i++) {
        let f = 1.0 + f32(i) * 0.02;
        a += 1.0e-7 * (1.5 + sin(p.x * f * 3.1 + cos(p.y * f * 2.3)) * exp(-0.01 * f32(i)));
    }
    var b = 0.0;
    for (var j = 0; j < 144; j++) {
        let g = 1.0 + f32(j) * 0.03;
        b += cos(p.z * g * 2.7 + sin(p.x * g * 1.9)) * exp(-0.01 * f32(j)) / g;
    }
    // a - 1 is about 1e-5: fine in f32, zero in a half float.
    let albedo = 0.5 + 0.05 * (log(a - 1.0) + 10.5);
    let gloss = clamp(0.5 + 0.2 * b, 0.0, 1.0);
    let n = normalize(in.normal);
    let l = normalize(scene.light_pos - p);
    let v = normalize(scene.camera_pos - p);
    let h = normalize(l + v);
    let diffuse = max(dot(n, l), 0.0);
    let spec = pow(max(dot(n, h), 0.0), 8.0 + 24.0 * gloss) * gloss;
    let c = albedo * diffuse * scene.tint * scene.gain + vec3<f32>(spec * 0.5);
    return vec4<f32>(c, 1.0);
}
