// Hand-written seed: a helper with an early return (reproj refuses to inline it) and one that
// only returns at the end, called from inside a branch.
fn early(x: f32) -> f32 {
    if (x > 0.5) {
        return x * 2.0;
    }
    return x;
}

fn late(x: f32) -> f32 {
    var y = x;
    if (x > 0.5) { y = y * 2.0; }
    return y;
}

@fragment
fn with_early(@location(0) p: vec2<f32>) -> @location(0) vec4<f32> {
    return vec4<f32>(early(p.x), 0.0, 0.0, 1.0);
}

@fragment
fn with_late(@location(0) p: vec2<f32>) -> @location(0) vec4<f32> {
    var c = 0.0;
    if (p.y > 0.0) {
        c = late(p.x);
    }
    return vec4<f32>(c, late(p.y), 0.0, 1.0);
}
