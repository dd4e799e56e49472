// Found by hand while fuzzing (caught by the fuzz target's REPROJ_FUZZ_STRICT=1 round trip): a
// store inside a bare `{ }` block was forwarded past the block, so the normalized module used an
// expression out of its scope (naga's validator accepts that; the WGSL it writes does not parse).
// Also: a switch with a multi-value case, a discard, a fragment entry with no result.
@fragment
fn blocks(@location(0) p: vec2<f32>) -> @location(0) vec4<f32> {
    var x = p.x;
    {
        x = sin(x) + p.y;
    }
    var y = 0.0;
    switch (i32(p.y)) {
        case 0, 1: { y = x; }
        default: { y = cos(x); }
    }
    if (y < 0.0) { discard; }
    return vec4<f32>(x, y, 0.0, 1.0);
}

@fragment
fn no_result(@location(0) p: vec2<f32>) {
    if (p.x > 0.5) { discard; }
}
