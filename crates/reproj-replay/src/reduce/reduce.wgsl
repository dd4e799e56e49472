// One workgroup covers a 64×64 tile of the frame: 8×8 threads, each sums an 8×8 block and writes
// its own `Partial` (no workgroup memory, no barrier: a CPU adapter such as lavapipe runs
// workgroup barriers as coroutine switches, which cost more than the sums). Keep `Partial` in step
// with the Rust struct of the same name, and `SIDE`/`BLOCK` with `TILE`/`THREADS` there.
struct Partial {
    l2: f32,        // sum of the per-pixel L2 RGB distance, channels clamped to [0, 1]
    sq: f32,        // sum over covered pixels of the squared (clamped) RGB differences
    covered: u32,   // pixels where the reference depth < 1
    max_bits: u32,  // bits of the largest |difference| over RGBA (a non-negative f32: ordered as u32)
    flags: u32,     // 1: a non-finite RGB in the frame where the reference is finite; 2: the same in a covered pixel
    bad: u32,       // pixels whose frame RGB is not finite where the reference's is
    bad_ref: u32,   // pixels whose reference RGB is not finite: left out of every sum
}

@group(0) @binding(0) var frame_color: texture_2d<f32>;
@group(0) @binding(1) var ref_color: texture_2d<f32>;
@group(0) @binding(2) var ref_depth: texture_2d<f32>;
@group(0) @binding(3) var<storage, read_write> partials: array<Partial>;

const SIDE: u32 = 8u;
const BLOCK: u32 = 8u;
const INF_BITS: u32 = 0x7f800000u;

// NaN or ±inf in any of the three channels (by bits: a compiler may fold `x != x` away).
fn nonfinite3(v: vec3<f32>) -> bool {
    let b = bitcast<vec3<u32>>(v) & vec3<u32>(0x7fffffffu);
    return any(b >= vec3<u32>(INF_BITS));
}

// |d| as bits, NaN as +inf.
fn abs_bits(d: f32) -> u32 {
    let b = bitcast<u32>(d) & 0x7fffffffu;
    return select(b, INF_BITS, b > INF_BITS);
}

@compute @workgroup_size(8, 8)
fn reduce(
    @builtin(workgroup_id) wg: vec3<u32>,
    @builtin(num_workgroups) groups: vec3<u32>,
    @builtin(local_invocation_id) lid: vec3<u32>,
    @builtin(local_invocation_index) li: u32,
) {
    let size = textureDimensions(frame_color);
    let origin = wg.xy * (SIDE * BLOCK) + lid.xy * BLOCK;
    var l2 = 0.0;
    var sq = 0.0;
    var cov = 0u;
    var mx = 0u;
    var flags = 0u;
    var bad = 0u;
    var bad_ref = 0u;
    for (var j = 0u; j < BLOCK; j++) {
        // A row's sums first, then the block's: 16 f32 roundings at most on a term, not 64.
        var row_l2 = 0.0;
        var row_sq = 0.0;
        for (var i = 0u; i < BLOCK; i++) {
            let p = origin + vec2<u32>(i, j);
            if p.x < size.x && p.y < size.y {
                let a = textureLoad(frame_color, p, 0);
                let b = textureLoad(ref_color, p, 0);
                let covered = textureLoad(ref_depth, p, 0).r < 1.0;
                if nonfinite3(b.rgb) {
                    bad_ref += 1u;
                    continue;
                }
                mx = max(mx, max(max(abs_bits(a.r - b.r), abs_bits(a.g - b.g)),
                                 max(abs_bits(a.b - b.b), abs_bits(a.a - b.a))));
                if nonfinite3(a.rgb) {
                    bad += 1u;
                    flags |= select(1u, 3u, covered);
                } else {
                    let d = clamp(a.rgb, vec3<f32>(0.0), vec3<f32>(1.0))
                          - clamp(b.rgb, vec3<f32>(0.0), vec3<f32>(1.0));
                    let s = d.r * d.r + d.g * d.g + d.b * d.b;
                    row_l2 += sqrt(s);
                    if covered {
                        row_sq += s;
                    }
                }
                if covered {
                    cov += 1u;
                }
            }
        }
        l2 += row_l2;
        sq += row_sq;
    }
    partials[(wg.y * groups.x + wg.x) * (SIDE * SIDE) + li] =
        Partial(l2, sq, cov, mx, flags, bad, bad_ref);
}
