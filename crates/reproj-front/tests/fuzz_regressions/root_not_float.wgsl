// Found by hand while fuzzing: an entry point whose @location(0) output is not f32/f16 data.
// Its root was not a node, so `NodeTable::root()` panicked ("the root is always a node");
// `normalize` now refuses it with an `Unsupported` error.
struct Out {
    @location(0) id: vec4<u32>,
    @location(1) color: vec4<f32>,
};

@fragment
fn int_output(@location(0) p: vec2<f32>) -> @location(0) vec4<i32> {
    return vec4<i32>(i32(p.x * 2.0), 0, 0, 1);
}

@fragment
fn uint_scalar(@location(0) p: vec2<f32>) -> @location(0) u32 {
    return u32(p.x * 255.0);
}

@fragment
fn struct_uint(@location(0) p: vec2<f32>) -> Out {
    return Out(vec4<u32>(1u), vec4<f32>(p, 0.0, 1.0));
}

@fragment
fn f64_output(@location(0) p: vec2<f32>) -> @location(0) vec4<f64> {
    return vec4<f64>(f64(p.x), 0.0lf, 0.0lf, 1.0lf);
}
