// The upsamplers' resolve: one full-screen pass at the output resolution over the frame drawn at
// the render resolution (docs/UPSAMPLING.md): reproj's temporal upsampler.
//
// Render pixel i shows the scene point at (i + 1/2 - jitter) render pixels: the projection was
// moved by `jitter` this frame. Each output pixel gathers the 3x3 render samples around it:
//   spatial   a Gaussian of render-pixel width `sigma_low` over them (the frame alone: the
//             first frame, and wherever the history is off screen);
//   sharp     a Gaussian of output-pixel width `sigma_out` (what the samples say of this very
//             pixel), with its weight sum as the sample's confidence;
//   temporal  the history (last frame's output, reprojected with the motion at the nearest
//             sample and read with a 5-tap Catmull-Rom filter) clipped in YCoCg to the
//             samples' mean +- gamma standard deviations (`clip_still` for a still pixel,
//             `clip_moving` from a quarter output pixel of motion on), then the sharp estimate
//             accumulated into it by weight; the history's weight rides in alpha, capped at
//             `max_weight / (1 + motion_damping * |motion in output pixels|)`: each frame the
//             history is resampled at a sub-pixel offset, which blurs it a little, so a moving
//             pixel keeps a shorter memory (a still one the whole `max_weight`).

struct Params {
    full: vec2<f32>,
    low: vec2<f32>,
    jitter: vec2<f32>,
    max_weight: f32,
    reset: u32,
    sigma_out: f32,
    sigma_low: f32,
    clip_still: f32,
    motion_damping: f32,
    clip_moving: f32,
    pad: f32,
    prev_jitter: vec2<f32>,
}

@group(0) @binding(0) var color_low: texture_2d<f32>;
@group(0) @binding(1) var history_sampler: sampler;
@group(0) @binding(2) var motion_low: texture_2d<f32>;
@group(0) @binding(3) var history: texture_2d<f32>;
@group(0) @binding(4) var<uniform> params: Params;

@vertex
fn upsample_vs(@builtin(vertex_index) i: u32) -> @builtin(position) vec4<f32> {
    let corner = vec2<f32>(f32((i << 1u) & 2u), f32(i & 2u));
    return vec4<f32>(corner * 2.0 - 1.0, 0.0, 1.0);
}

fn to_ycocg(c: vec3<f32>) -> vec3<f32> {
    return vec3<f32>(
        0.25 * c.r + 0.5 * c.g + 0.25 * c.b,
        0.5 * c.r - 0.5 * c.b,
        -0.25 * c.r + 0.5 * c.g - 0.25 * c.b,
    );
}

fn from_ycocg(c: vec3<f32>) -> vec3<f32> {
    return vec3<f32>(c.x + c.y - c.z, c.x + c.z, c.x - c.y - c.z);
}

// `c` moved toward `center` until it is inside the box of half-size `extent` around it.
fn clip_to_box(c: vec3<f32>, center: vec3<f32>, extent: vec3<f32>) -> vec3<f32> {
    let off = c - center;
    let unit = abs(off / max(extent, vec3<f32>(1e-5)));
    let m = max(unit.x, max(unit.y, unit.z));
    if m > 1.0 {
        return center + off / m;
    }
    return c;
}

// The history at `uv`, Catmull-Rom filtered with 5 bilinear taps (the 16-tap filter less its
// four corners, whose weights are the smallest; renormalized).
fn sample_history(uv: vec2<f32>) -> vec4<f32> {
    let at = uv * params.full;
    let center = floor(at - 0.5) + 0.5;
    let f = at - center;
    let w0 = f * (-0.5 + f * (1.0 - 0.5 * f));
    let w1 = 1.0 + f * f * (-2.5 + 1.5 * f);
    let w2 = f * (0.5 + f * (2.0 - 1.5 * f));
    let w3 = f * f * (-0.5 + 0.5 * f);
    let w12 = w1 + w2;
    let p0 = (center - 1.0) / params.full;
    let p3 = (center + 2.0) / params.full;
    let p12 = (center + w2 / w12) / params.full;
    var sum = textureSampleLevel(history, history_sampler, vec2<f32>(p12.x, p0.y), 0.0) * (w12.x * w0.y);
    sum += textureSampleLevel(history, history_sampler, vec2<f32>(p0.x, p12.y), 0.0) * (w0.x * w12.y);
    sum += textureSampleLevel(history, history_sampler, p12, 0.0) * (w12.x * w12.y);
    sum += textureSampleLevel(history, history_sampler, vec2<f32>(p3.x, p12.y), 0.0) * (w3.x * w12.y);
    sum += textureSampleLevel(history, history_sampler, vec2<f32>(p12.x, p3.y), 0.0) * (w12.x * w3.y);
    let w = w12.x * w0.y + w0.x * w12.y + w12.x * w12.y + w3.x * w12.y + w12.x * w3.y;
    return sum / w;
}

@fragment
fn upsample_fs(@builtin(position) frag: vec4<f32>) -> @location(0) vec4<f32> {
    let uv = frag.xy / params.full;
    let here = uv * params.low;
    let last = vec2<i32>(params.low) - 1;
    let nearest = clamp(vec2<i32>(round(here - 0.5 + params.jitter)), vec2<i32>(0), last);
    let out_per_low = params.full / params.low;
    var sharp_sum = vec3<f32>(0.0);
    var sharp_w = 0.0;
    var soft_sum = vec3<f32>(0.0);
    var soft_w = 0.0;
    var m1 = vec3<f32>(0.0);
    var m2 = vec3<f32>(0.0);
    for (var dy = -1; dy <= 1; dy++) {
        for (var dx = -1; dx <= 1; dx++) {
            let p = clamp(nearest + vec2<i32>(dx, dy), vec2<i32>(0), last);
            let c = textureLoad(color_low, p, 0).rgb;
            let d_low = vec2<f32>(p) + 0.5 - params.jitter - here;
            let d_out = d_low * out_per_low;
            let g_out = exp(-dot(d_out, d_out) / (2.0 * params.sigma_out * params.sigma_out));
            let g_low = exp(-dot(d_low, d_low) / (2.0 * params.sigma_low * params.sigma_low));
            sharp_sum += c * g_out;
            sharp_w += g_out;
            soft_sum += c * g_low;
            soft_w += g_low;
            let y = to_ycocg(c);
            m1 += y;
            m2 += y * y;
        }
    }
    let spatial = soft_sum / max(soft_w, 1e-6);
    let w_new = min(sharp_w, 1.0);
    if params.reset == 1u {
        return vec4<f32>(spatial, w_new);
    }
    // The motion pass wrote uv_now - uv_before at the jittered pixel: the surface's own motion
    // plus this frame's offset less the previous frame's (each frame's matrix carries its own).
    let motion = textureLoad(motion_low, nearest, 0).xy - (params.jitter - params.prev_jitter) / params.low;
    let before = uv - motion;
    if any(before < vec2<f32>(0.0)) || any(before > vec2<f32>(1.0)) {
        return vec4<f32>(spatial, w_new);
    }
    let sharp = select(spatial, sharp_sum / max(sharp_w, 1e-6), sharp_w > 1e-4);
    let mean = m1 / 9.0;
    let sigma = sqrt(max(m2 / 9.0 - mean * mean, vec3<f32>(0.0)));
    let moved = length(motion * params.full);
    let gamma = mix(params.clip_still, params.clip_moving, clamp(moved * 4.0, 0.0, 1.0));
    let h = sample_history(before);
    let kept = from_ycocg(clip_to_box(to_ycocg(h.rgb), mean, gamma * sigma));
    let hw = clamp(h.a, 0.0, params.max_weight / (1.0 + params.motion_damping * moved));
    if hw + w_new < 1e-4 {
        return vec4<f32>(spatial, w_new);
    }
    let color = (max(kept, vec3<f32>(0.0)) * hw + sharp * w_new) / (hw + w_new);
    return vec4<f32>(color, min(hw + w_new, params.max_weight));
}
