// The perceptual metrics of a frame against its reference, where both are: ꟻLIP (LDR; Andersson
// et al. 2020) and SSIM (Wang et al. 2004) per pixel, summed over the covered pixels. Three entry
// points, dispatched in order over one frame:
//
//   `prepare`  what a viewer sees of each image (clamped, sRGB-encoded, 8 bits, as the PNGs), as
//              YCxCz (ꟻLIP's opponent space) and luma (SSIM's);
//   `across`   the separable filters along the rows: ꟻLIP's colour filters (one Gaussian for Y
//              and Cx, two for Cz), its edge and point detectors, SSIM's 11-tap window;
//   `down`     the same filters along the columns, each pixel's ꟻLIP and SSIM, and each
//              thread's 8×8 block summed into one `Partial` (no workgroup memory, no barrier, as
//              `reduce.wgsl`).
//
// Rows and columns are clamped at the edges (as NVIDIA's reference code); SSIM uses only the
// windows inside the frame. The filter weights and the 8-bit sRGB decoding table come from the
// host (`perceptual.rs`, computed as the reference code computes them). Keep `Params` and
// `Partial` in step with the Rust structs of the same names.

struct Params {
    // width, height, colour filter radius, feature filter radius
    dims: vec4<u32>,
    // cmax, p_c · cmax (ꟻLIP's colour-difference remapping)
    remap: vec4<f32>,
    // colour filter (Y, Cx, Cz first Gaussian, Cz second) × (2·dims.z + 1), then the feature
    // filter (Gaussian, first and second derivative, 0) × (2·dims.w + 1), then SSIM's window in x
    weights: array<vec4<f32>, 64>,
    // 8-bit sRGB → linear, four entries per vec4
    decode: array<vec4<f32>, 64>,
}

struct Partial {
    flip: f32,     // sum of ꟻLIP over the covered pixels
    covered: u32,  // pixels where the reference depth < 1
    ssim: f32,     // sum of SSIM over the covered pixels whose window lies inside the frame
    windows: u32,  // those pixels
}

@group(0) @binding(0) var<uniform> p: Params;
@group(0) @binding(1) var frame_color: texture_2d<f32>;
@group(0) @binding(2) var ref_color: texture_2d<f32>;
@group(0) @binding(3) var ref_depth: texture_2d<f32>;
// Per pixel: Y, Cx, Cz, luma.
@group(0) @binding(4) var<storage, read_write> seen_test: array<vec4<f32>>;
@group(0) @binding(5) var<storage, read_write> seen_ref: array<vec4<f32>>;
// Per pixel, filtered along its row: Y, Cx, Cz (first Gaussian), Cz (second).
@group(0) @binding(6) var<storage, read_write> colour_test: array<vec4<f32>>;
@group(0) @binding(7) var<storage, read_write> colour_ref: array<vec4<f32>>;
// Per pixel, normalized Y filtered along its row: first derivative, second derivative,
// Gaussian; the reference's .w holds SSIM's windowed a·b.
@group(0) @binding(8) var<storage, read_write> feature_test: array<vec4<f32>>;
@group(0) @binding(9) var<storage, read_write> feature_ref: array<vec4<f32>>;
// Per pixel, SSIM's window along its row: a, b, a², b² (a: the frame's luma, b: the reference's).
@group(0) @binding(10) var<storage, read_write> window: array<vec4<f32>>;
@group(0) @binding(11) var<storage, read_write> partials: array<Partial>;

const SSIM_RADIUS: u32 = 5u;
const SSIM_C1: f32 = 0.0001;   // (0.01 · 1)²
const SSIM_C2: f32 = 0.0009;   // (0.03 · 1)²
const FLIP_QC: f32 = 0.7;
const FLIP_PT: f32 = 0.95;
const SIDE: u32 = 8u;
const BLOCK: u32 = 8u;

// A linear channel as the PNGs write it: clamped, sRGB-encoded, rounded to 8 bits (NaN: 0).
fn eight_bits(v: f32) -> u32 {
    if (bitcast<u32>(v) & 0x7fffffffu) > 0x7f800000u {
        return 0u;
    }
    let x = clamp(v, 0.0, 1.0);
    var e = 12.92 * x;
    if x > 0.0031308 {
        e = 1.055 * pow(x, 1.0 / 2.4) - 0.055;
    }
    return min(u32(e * 255.0 + 0.5), 255u);
}

fn decoded(i: u32) -> f32 {
    return p.decode[i / 4u][i % 4u];
}

// Linear RGB → CIE XYZ (D65).
fn xyz_of(c: vec3<f32>) -> vec3<f32> {
    return vec3<f32>(
        (10135552.0 / 24577794.0) * c.x + (8788810.0 / 24577794.0) * c.y + (4435075.0 / 24577794.0) * c.z,
        (2613072.0 / 12288897.0) * c.x + (8788810.0 / 12288897.0) * c.y + (887015.0 / 12288897.0) * c.z,
        (1425312.0 / 73733382.0) * c.x + (8788810.0 / 73733382.0) * c.y + (70074185.0 / 73733382.0) * c.z,
    );
}

// CIE XYZ (D65) → linear RGB.
fn rgb_of(c: vec3<f32>) -> vec3<f32> {
    return vec3<f32>(
        3.241003275 * c.x - 1.537398934 * c.y - 0.498615861 * c.z,
        -0.969224334 * c.x + 1.875930071 * c.y + 0.041554224 * c.z,
        0.055639423 * c.x - 0.204011202 * c.y + 1.057148933 * c.z,
    );
}

const WHITE: vec3<f32> = vec3<f32>(0.950428545, 1.0, 1.088900371);
const INV_WHITE: vec3<f32> = vec3<f32>(1.052156925, 1.0, 0.918357670);

fn ycxcz_of(xyz: vec3<f32>) -> vec3<f32> {
    let n = xyz * INV_WHITE;
    return vec3<f32>(116.0 * n.y - 16.0, 500.0 * (n.x - n.y), 200.0 * (n.y - n.z));
}

fn xyz_of_ycxcz(c: vec3<f32>) -> vec3<f32> {
    let y = (c.x + 16.0) / 116.0;
    return vec3<f32>(y + c.y / 500.0, y, y - c.z / 200.0) * WHITE;
}

fn lab_part(t: f32) -> f32 {
    let delta = 6.0 / 29.0;
    if t > delta * delta * delta {
        return pow(t, 1.0 / 3.0);
    }
    return (1.0 / (3.0 * delta * delta)) * t + 4.0 / 29.0;
}

// Filtered YCxCz → clamped to the RGB cube → CIELab, chroma scaled by lightness (Hunt).
fn hunt_lab(ycc: vec3<f32>) -> vec3<f32> {
    let rgb = clamp(rgb_of(xyz_of_ycxcz(ycc)), vec3<f32>(0.0), vec3<f32>(1.0));
    let n = xyz_of(rgb) * INV_WHITE;
    let f = vec3<f32>(lab_part(n.x), lab_part(n.y), lab_part(n.z));
    let l = 116.0 * f.y - 16.0;
    let a = 500.0 * (f.x - f.y);
    let b = 200.0 * (f.y - f.z);
    return vec3<f32>(l, 0.01 * l * a, 0.01 * l * b);
}

// x^e for x ≥ 0 and e > 0, 0 at 0 (SPIR-V leaves pow(0, e) to the driver).
fn power(x: f32, e: f32) -> f32 {
    return select(pow(x, e), 0.0, x <= 0.0);
}

@compute @workgroup_size(8, 8)
fn prepare(@builtin(global_invocation_id) id: vec3<u32>) {
    if id.x >= p.dims.x || id.y >= p.dims.y {
        return;
    }
    let i = id.y * p.dims.x + id.x;
    var images = array<vec4<f32>, 2>(
        textureLoad(frame_color, id.xy, 0),
        textureLoad(ref_color, id.xy, 0),
    );
    var out: array<vec4<f32>, 2>;
    for (var k = 0u; k < 2u; k++) {
        let c = images[k];
        let q = vec3<u32>(eight_bits(c.r), eight_bits(c.g), eight_bits(c.b));
        let lin = vec3<f32>(decoded(q.x), decoded(q.y), decoded(q.z));
        let luma = (0.298936 * f32(q.x) + 0.587043 * f32(q.y) + 0.114021 * f32(q.z)) / 255.0;
        out[k] = vec4<f32>(ycxcz_of(xyz_of(lin)), luma);
    }
    seen_test[i] = out[0];
    seen_ref[i] = out[1];
}

@compute @workgroup_size(8, 8)
fn across(@builtin(global_invocation_id) id: vec3<u32>) {
    let w = p.dims.x;
    if id.x >= w || id.y >= p.dims.y {
        return;
    }
    let row = id.y * w;
    let last = i32(w) - 1;
    // Colour: Y and Cx by one Gaussian each, Cz by two (summed after the columns).
    let rc = i32(p.dims.z);
    var ct = vec4<f32>(0.0);
    var cr = vec4<f32>(0.0);
    for (var d = -rc; d <= rc; d++) {
        let x = row + u32(clamp(i32(id.x) + d, 0, last));
        let k = p.weights[u32(d + rc)];
        let t = seen_test[x];
        let r = seen_ref[x];
        ct += k * t.xyzz;
        cr += k * r.xyzz;
    }
    // Features: the normalized Y by the Gaussian's first and second derivatives and itself.
    let rf = i32(p.dims.w);
    let base = 2u * p.dims.z + 1u;
    var ft = vec3<f32>(0.0);
    var fr = vec3<f32>(0.0);
    for (var d = -rf; d <= rf; d++) {
        let x = row + u32(clamp(i32(id.x) + d, 0, last));
        let k = p.weights[base + u32(d + rf)].xyz;
        let yt = seen_test[x].x * (1.0 / 116.0) + 16.0 / 116.0;
        let yr = seen_ref[x].x * (1.0 / 116.0) + 16.0 / 116.0;
        ft += vec3<f32>(k.y, k.z, k.x) * yt;
        fr += vec3<f32>(k.y, k.z, k.x) * yr;
    }
    // SSIM's window, where it lies inside the row.
    var win = vec4<f32>(0.0);
    var ab = 0.0;
    if id.x >= SSIM_RADIUS && id.x + SSIM_RADIUS < w {
        let sbase = base + 2u * p.dims.w + 1u;
        for (var d = 0u; d <= 2u * SSIM_RADIUS; d++) {
            let x = row + id.x + d - SSIM_RADIUS;
            let g = p.weights[sbase + d].x;
            let a = seen_test[x].w;
            let b = seen_ref[x].w;
            win += g * vec4<f32>(a, b, a * a, b * b);
            ab += g * (a * b);
        }
    }
    let i = row + id.x;
    colour_test[i] = ct;
    colour_ref[i] = cr;
    feature_test[i] = vec4<f32>(ft, 0.0);
    feature_ref[i] = vec4<f32>(fr, ab);
    window[i] = win;
}

// ꟻLIP at pixel (x, y): the colour difference of the filtered images, raised by the feature
// difference.
fn flip_at(x: u32, y: u32) -> f32 {
    let w = p.dims.x;
    let last = i32(p.dims.y) - 1;
    let rc = i32(p.dims.z);
    var ct = vec4<f32>(0.0);
    var cr = vec4<f32>(0.0);
    for (var d = -rc; d <= rc; d++) {
        let i = u32(clamp(i32(y) + d, 0, last)) * w + x;
        let k = p.weights[u32(d + rc)];
        ct += k * colour_test[i];
        cr += k * colour_ref[i];
    }
    let lt = hunt_lab(vec3<f32>(ct.x, ct.y, ct.z + ct.w));
    let lr = hunt_lab(vec3<f32>(cr.x, cr.y, cr.z + cr.w));
    let hyab = abs(lr.x - lt.x) + length(lr.yz - lt.yz);
    var colour = power(hyab, FLIP_QC);
    let cmax = p.remap.x;
    let pccmax = p.remap.y;
    if colour < pccmax {
        colour *= FLIP_PT / pccmax;
    } else {
        colour = FLIP_PT + ((colour - pccmax) / (cmax - pccmax)) * (1.0 - FLIP_PT);
    }
    let rf = i32(p.dims.w);
    let base = 2u * p.dims.z + 1u;
    // (dx, ddx, dy, ddy) of each image.
    var gt = vec4<f32>(0.0);
    var gr = vec4<f32>(0.0);
    for (var d = -rf; d <= rf; d++) {
        let i = u32(clamp(i32(y) + d, 0, last)) * w + x;
        let k = p.weights[base + u32(d + rf)].xyz;
        let t = feature_test[i].xyz;
        let r = feature_ref[i].xyz;
        gt += vec4<f32>(k.x * t.x, k.x * t.y, k.y * t.z, k.z * t.z);
        gr += vec4<f32>(k.x * r.x, k.x * r.y, k.y * r.z, k.z * r.z);
    }
    let edge = abs(length(gr.xz) - length(gt.xz));
    let point = abs(length(gr.yw) - length(gt.yw));
    let feature = sqrt(max(edge, point) * 0.70710678);
    return power(colour, 1.0 - feature);
}

// SSIM of the window centred at (x, y) (inside the frame).
fn ssim_at(x: u32, y: u32) -> f32 {
    let w = p.dims.x;
    let sbase = 2u * p.dims.z + 2u * p.dims.w + 2u;
    var m = vec4<f32>(0.0);
    var ab = 0.0;
    for (var d = 0u; d <= 2u * SSIM_RADIUS; d++) {
        let i = (y + d - SSIM_RADIUS) * w + x;
        let g = p.weights[sbase + d].x;
        m += g * window[i];
        ab += g * feature_ref[i].w;
    }
    let va = m.z - m.x * m.x;
    let vb = m.w - m.y * m.y;
    let cov = ab - m.x * m.y;
    return ((2.0 * m.x * m.y + SSIM_C1) * (2.0 * cov + SSIM_C2))
        / ((m.x * m.x + m.y * m.y + SSIM_C1) * (va + vb + SSIM_C2));
}

@compute @workgroup_size(8, 8)
fn down(
    @builtin(workgroup_id) wg: vec3<u32>,
    @builtin(num_workgroups) groups: vec3<u32>,
    @builtin(local_invocation_id) lid: vec3<u32>,
    @builtin(local_invocation_index) li: u32,
) {
    let size = p.dims.xy;
    let origin = wg.xy * (SIDE * BLOCK) + lid.xy * BLOCK;
    var flip = 0.0;
    var ssim = 0.0;
    var covered = 0u;
    var windows = 0u;
    for (var j = 0u; j < BLOCK; j++) {
        var row_flip = 0.0;
        var row_ssim = 0.0;
        for (var i = 0u; i < BLOCK; i++) {
            let at = origin + vec2<u32>(i, j);
            if at.x < size.x && at.y < size.y && textureLoad(ref_depth, at, 0).r < 1.0 {
                covered += 1u;
                row_flip += flip_at(at.x, at.y);
                if all(at >= vec2<u32>(SSIM_RADIUS)) && all(at + SSIM_RADIUS < size) {
                    windows += 1u;
                    row_ssim += ssim_at(at.x, at.y);
                }
            }
        }
        flip += row_flip;
        ssim += row_ssim;
    }
    partials[(wg.y * groups.x + wg.x) * (SIDE * SIDE) + li] = Partial(flip, covered, ssim, windows);
}
