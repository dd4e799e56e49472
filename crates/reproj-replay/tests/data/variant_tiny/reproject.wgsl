// Hand-written pass 1 (reproject) of tiny.wgsl caching `albedo`, following docs/PASSES.md.
struct ReprojParams {
    delta_n: u32,
    clock: u32,
    block: u32,
    depth_epsilon: f32,
};

@group(2) @binding(0) var<uniform> reproj_params: ReprojParams;
@group(2) @binding(1) var reproj_prev_payload: texture_2d<f32>;
@group(2) @binding(2) var reproj_prev_depth: texture_depth_2d;

struct ReprojInput {
    @builtin(position) frag_coord: vec4<f32>,
    @location(5) prev_clip: vec4<f32>,
};

// 32-bit integer hash of a refresh block.
fn reproj_hash(x: u32, y: u32) -> u32 {
    var h = (x * 0x8da6b343u) ^ (y * 0xd8163841u);
    h = h ^ (h >> 16u);
    h = h * 0x7feb352du;
    h = h ^ (h >> 15u);
    h = h * 0x846ca68bu;
    h = h ^ (h >> 16u);
    return h;
}

struct ReprojLookup {
    // 0 hit, 1 miss, 2 refresh
    status: u32,
    payload: vec4<f32>,
};

fn reproj_lookup(frag_coord: vec4<f32>, prev_clip: vec4<f32>) -> ReprojLookup {
    var out: ReprojLookup;
    out.status = 1u;
    out.payload = vec4<f32>(0.0);
    if (prev_clip.w > 0.0) {
        let ndc = prev_clip.xyz / prev_clip.w;
        let uv = ndc.xy * vec2<f32>(0.5, -0.5) + vec2<f32>(0.5);
        if (all(uv >= vec2<f32>(0.0)) && all(uv <= vec2<f32>(1.0))) {
            let size = textureDimensions(reproj_prev_depth);
            let p = uv * vec2<f32>(size) - vec2<f32>(0.5);
            let base = floor(p);
            let f = p - base;
            let hi = vec2<i32>(size) - vec2<i32>(1);
            let c00 = clamp(vec2<i32>(base), vec2<i32>(0), hi);
            let c11 = clamp(vec2<i32>(base) + vec2<i32>(1), vec2<i32>(0), hi);
            let c10 = vec2<i32>(c11.x, c00.y);
            let c01 = vec2<i32>(c00.x, c11.y);
            let d00 = textureLoad(reproj_prev_depth, c00, 0);
            let d10 = textureLoad(reproj_prev_depth, c10, 0);
            let d01 = textureLoad(reproj_prev_depth, c01, 0);
            let d11 = textureLoad(reproj_prev_depth, c11, 0);
            let eps = reproj_params.depth_epsilon;
            let z = ndc.z;
            let agree = abs(d00 - z) <= eps && abs(d10 - z) <= eps && abs(d01 - z) <= eps && abs(d11 - z) <= eps;
            if (agree) {
                let p00 = textureLoad(reproj_prev_payload, c00, 0);
                let p10 = textureLoad(reproj_prev_payload, c10, 0);
                let p01 = textureLoad(reproj_prev_payload, c01, 0);
                let p11 = textureLoad(reproj_prev_payload, c11, 0);
                out.payload = mix(mix(p00, p10, f.x), mix(p01, p11, f.x), f.y);
                let k = max(reproj_params.block, 1u);
                let blk = vec2<u32>(frag_coord.xy) / k;
                let dn = max(reproj_params.delta_n, 1u);
                if (((reproj_hash(blk.x, blk.y) + reproj_params.clock) % dn) != 0u) {
                    out.status = 0u;
                } else {
                    out.status = 2u;
                }
            }
        }
    }
    return out;
}

@fragment
fn reproj_main(in: ReprojInput) -> @location(0) vec4<f32> {
    let r = reproj_lookup(in.frag_coord, in.prev_clip);
    if (r.status != 0u) {
        discard;
    }
    return r.payload;
}

@fragment
fn reproj_classify(in: ReprojInput) -> @location(0) vec4<f32> {
    let r = reproj_lookup(in.frag_coord, in.prev_clip);
    var c = vec4<f32>(0.0, 1.0, 0.0, 1.0);
    if (r.status == 1u) {
        c = vec4<f32>(1.0, 0.0, 0.0, 1.0);
    } else if (r.status == 2u) {
        c = vec4<f32>(0.0, 0.0, 1.0, 1.0);
    }
    return c;
}
