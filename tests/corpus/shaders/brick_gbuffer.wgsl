// Procedural brick wall in a G-buffer-style pass: the entry point fills an output struct field by
// field and returns it (the shape of deferred engines' material passes), here with the one color
// target a forward pass keeps. Bricks are laid in running bond from the uv; each brick gets its own
// hashed tint and a value-noise grit, the mortar is inset and darker. The helpers return early
// (inside the mortar, a light behind the surface).

struct FragmentInput {
    @location(0) world_pos: vec3<f32>,
    @location(1) normal: vec3<f32>,
    @location(2) uv: vec2<f32>,
};

struct GBufferOutput {
    @location(0) color: vec4<f32>,
};

struct Scene {
    camera_pos: vec3<f32>,
    time: f32,
    light_pos: vec3<f32>,
    mortar_width: f32,
    brick_color: vec3<f32>,
    bricks_per_unit: f32,
    mortar_color: vec3<f32>,
    brick_aspect: f32,
    light_color: vec3<f32>,
    tint_variation: f32,
    ambient: vec3<f32>,
    bump_strength: f32,
};

@group(0) @binding(0) var<uniform> scene: Scene;

fn hash21(p: vec2<f32>) -> f32 {
    var q = fract(p * vec2<f32>(123.34, 456.21));
    q += dot(q, q + 45.32);
    return fract(q.x * q.y);
}

fn value_noise(p: vec2<f32>) -> f32 {
    let i = floor(p);
    let f = fract(p);
    let u = f * f * (3.0 - 2.0 * f);
    let a = hash21(i);
    let b = hash21(i + vec2<f32>(1.0, 0.0));
    let c = hash21(i + vec2<f32>(0.0, 1.0));
    let d = hash21(i + vec2<f32>(1.0, 1.0));
    return mix(mix(a, b, u.x), mix(c, d, u.x), u.y);
}

// Distance-like mask from the mortar: 0 in the joint, rising to 1 inside the brick.
fn brick_mask(local: vec2<f32>, mortar: vec2<f32>) -> f32 {
    let edge = min(local, vec2<f32>(1.0) - local);
    if (edge.x < mortar.x || edge.y < mortar.y) {
        return 0.0;
    }
    let inner = (edge - mortar) / max(mortar, vec2<f32>(1e-4));
    return clamp(min(inner.x, inner.y), 0.0, 1.0);
}

fn lambert_wrap(n: vec3<f32>, l: vec3<f32>, wrap: f32) -> f32 {
    let d = dot(n, l);
    if (d <= -wrap) {
        return 0.0;
    }
    return (d + wrap) / (1.0 + wrap);
}

@fragment
fn fs_main(in: FragmentInput) -> GBufferOutput {
    var out: GBufferOutput;

    // Running bond: every other row is shifted by half a brick.
    let grid = in.uv * vec2<f32>(scene.bricks_per_unit, scene.bricks_per_unit * scene.brick_aspect);
    let row = floor(grid.y);
    let shifted = vec2<f32>(grid.x + 0.5 * (row - 2.0 * floor(row * 0.5)), grid.y);
    let cell = floor(shifted);
    let local = fract(shifted);
    let mortar = vec2<f32>(scene.mortar_width, scene.mortar_width * scene.brick_aspect);
    let mask = brick_mask(local, mortar);

    // Per-brick tint and grit.
    let tint = 1.0 + (hash21(cell) - 0.5) * scene.tint_variation;
    let grit = value_noise(shifted * 9.0) * 0.6 + value_noise(shifted * 23.0) * 0.4;
    let brick = scene.brick_color * tint * (0.8 + 0.35 * grit);
    let sand = scene.mortar_color * (0.85 + 0.3 * value_noise(in.uv * 80.0));
    let albedo = mix(sand, brick, smoothstep(0.0, 0.15, mask));

    // Bevel: the bricks stand out of the mortar; bend the normal by the mask's gradient.
    let n0 = normalize(in.normal);
    let slope = vec2<f32>(dpdx(mask), dpdy(mask)) * scene.bump_strength;
    let n = normalize(n0 - vec3<f32>(slope.x, 0.0, slope.y) * (1.0 - abs(n0.y)));

    let l = normalize(scene.light_pos - in.world_pos);
    let v = normalize(scene.camera_pos - in.world_pos);
    let h = normalize(l + v);
    let diffuse = lambert_wrap(n, l, 0.2);
    let gloss = mix(8.0, 24.0, mask);
    let spec = pow(max(dot(n, h), 0.0), gloss) * 0.08 * mask;
    let cavity = mix(0.55, 1.0, smoothstep(0.0, 0.3, mask));

    out.color = vec4<f32>(albedo * (scene.ambient * cavity + scene.light_color * diffuse), 1.0);
    out.color = vec4<f32>(out.color.rgb + scene.light_color * spec, out.color.a);
    out.color = vec4<f32>(clamp(out.color.rgb, vec3<f32>(0.0), vec3<f32>(1.0)), 1.0);
    return out;
}
