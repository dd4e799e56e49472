// Hand-written seed: struct outputs, with @location(0) not first, built in the return, through a
// variable, and with no @location(0) member at all.
struct Out {
    @location(1) extra: vec4<f32>,
    @location(0) color: vec4<f32>,
    @builtin(frag_depth) depth: f32,
};

struct NoColor {
    @location(1) extra: vec4<f32>,
};

@fragment
fn direct(@location(0) uv: vec2<f32>) -> Out {
    let c = vec4<f32>(sin(uv.x), cos(uv.y), 0.0, 1.0);
    return Out(c * 0.5, c, 0.5);
}

@fragment
fn via_var(@location(0) uv: vec2<f32>) -> Out {
    var o: Out;
    o.color = vec4<f32>(uv, 0.0, 1.0);
    o.extra = o.color * 2.0;
    o.depth = 0.25;
    return o;
}

@fragment
fn zero() -> Out {
    return Out();
}

@fragment
fn no_color(@location(0) uv: vec2<f32>) -> NoColor {
    return NoColor(vec4<f32>(uv, 0.0, 1.0));
}
