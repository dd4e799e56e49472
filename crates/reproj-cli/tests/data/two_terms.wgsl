// Set-search fixture (`crates/reproj-cli/tests/sets.rs`, docs/notebook/node-sets.md): two independent
// expensive terms of the surface point — an albedo `a` (192 waves) and a gloss `b` (144 waves;
// not as costly as `a`, or `analyze`'s pruning would merge the two as one choice) — lit by a moving
// light. Each term alone is a good node to cache; caching both in one payload
// saves both loops, and any single node that holds both also holds the lighting, which changes
// every frame.
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
    var a = 0.0;
    for (var i = 0; i < 192; i++) {
        let f = 1.0 + f32(i) * 0.02;
        a += sin(p.x * f * 3.1 + cos(p.y * f * 2.3)) * exp(-0.01 * f32(i)) / f;
    }
    var b = 0.0;
    for (var j = 0; j < 144; j++) {
        let g = 1.0 + f32(j) * 0.03;
        b += cos(p.z * g * 2.7 + sin(p.x * g * 1.9)) * exp(-0.01 * f32(j)) / g;
    }
    let albedo = 0.5 + 0.2 * a;
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
