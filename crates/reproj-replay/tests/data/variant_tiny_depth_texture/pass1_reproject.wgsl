struct ReprojParams {
    delta_n: u32,
    clock: u32,
    block: u32,
    depth_epsilon: f32,
}

struct ReprojInput {
    @builtin(position) position: vec4<f32>,
    @location(3) prev_clip: vec4<f32>,
}

struct ReprojLookup {
    payload: vec4<f32>,
    status: u32,
}

@group(2) @binding(0) 
var<uniform> reproj_params: ReprojParams;
@group(2) @binding(1) 
var reproj_prev_payload: texture_2d<f32>;
@group(2) @binding(2) 
var reproj_prev_depth: texture_depth_2d;
@group(2) @binding(4) 
var reproj_point_sampler: sampler;
@group(2) @binding(5) 
var reproj_linear_sampler: sampler;

fn reproj_hash(x: u32, y: u32) -> u32 {
    var h: u32;

    h = (((x * 747796405u) + (y * 2891336453u)) + 2654435769u);
    let _e10 = h;
    let _e11 = h;
    let _e12 = h;
    h = (((_e10 >> ((_e11 >> 28u) + 4u)) ^ _e12) * 277803737u);
    let _e21 = h;
    let _e22 = h;
    return ((_e21 >> 22u) ^ _e22);
}

fn reproj_refreshed(pixel: vec2<f32>) -> bool {
    let _e3 = reproj_params.block;
    let k = f32(max(_e3, 1u));
    let b = vec2<u32>(floor((pixel / vec2(k))));
    let _e13 = reproj_params.delta_n;
    let n_u = max(_e13, 1u);
    let n = f32(n_u);
    let _e19 = reproj_hash(b.x, b.y);
    let _e22 = reproj_params.clock;
    let v = (f32((_e19 & 65535u)) + f32((_e22 % n_u)));
    return ((v - (n * floor((v / n)))) == 0f);
}

fn reproj_lookup(in_2_: ReprojInput) -> ReprojLookup {
    var r: ReprojLookup;
    var local: bool;
    var local_1_: bool;
    var local_2_: bool;

    r.payload = vec4(0f);
    r.status = 1u;
    if (in_2_.prev_clip.w <= 0f) {
        let _e14 = r;
        return _e14;
    }
    let ndc = (in_2_.prev_clip.xyz / vec3(in_2_.prev_clip.w));
    if !((abs(ndc.x) > 1f)) {
        local = (abs(ndc.y) > 1f);
    } else {
        local = true;
    }
    let _e31 = local;
    if !(_e31) {
        local_1_ = (ndc.z < 0f);
    } else {
        local_1_ = true;
    }
    let _e37 = local_1_;
    if !(_e37) {
        local_2_ = (ndc.z > 1f);
    } else {
        local_2_ = true;
    }
    let _e43 = local_2_;
    if _e43 {
        let _e44 = r;
        return _e44;
    }
    let uv = vec2<f32>(((ndc.x * 0.5f) + 0.5f), (0.5f - (ndc.y * 0.5f)));
    let _e57 = textureDimensions(reproj_prev_depth);
    let size = vec2<f32>(_e57);
    let g = textureGather(reproj_prev_depth, reproj_point_sampler, uv);
    let f = fract(((uv * size) - vec2(0.5f)));
    let d = mix(mix(g.w, g.z, f.x), mix(g.x, g.y, f.x), f.y);
    let _e79 = reproj_params.depth_epsilon;
    let tolerance = (_e79 * max((1f - ndc.z), 0.0000001f));
    if (abs((d - ndc.z)) > tolerance) {
        let _e90 = r;
        return _e90;
    }
    let _e94 = textureSampleLevel(reproj_prev_payload, reproj_linear_sampler, uv, 0f);
    r.payload = _e94;
    let _e98 = reproj_refreshed(in_2_.position.xy);
    r.status = select(0u, 2u, _e98);
    let _e103 = r;
    return _e103;
}

@fragment 
fn reproj_classify(in: ReprojInput) -> @location(0) vec4<f32> {
    var c: vec4<f32> = vec4<f32>(1f, 0f, 0f, 1f);

    let _e7 = reproj_lookup(in);
    if (_e7.status == 0u) {
        c = vec4<f32>(0f, 1f, 0f, 1f);
    } else {
        if (_e7.status == 2u) {
            c = vec4<f32>(0f, 0f, 1f, 1f);
        }
    }
    let _e24 = c;
    return _e24;
}

@fragment 
fn fs_main(in_1_: ReprojInput) -> @location(0) vec4<f32> {
    let _e3 = reproj_refreshed(in_1_.position.xy);
    if _e3 {
        discard;
    }
    let _e4 = reproj_lookup(in_1_);
    if (_e4.status != 0u) {
        discard;
    }
    return _e4.payload;
}
