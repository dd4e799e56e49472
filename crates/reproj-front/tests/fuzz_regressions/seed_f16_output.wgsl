// Hand-written seed: an f16 output color (the root is a node but not a payload).
enable f16;
@fragment
fn main(@location(0) p: vec2<f32>) -> @location(0) vec4<f16> {
    return vec4<f16>(f16(sin(p.x)), 0.0h, 0.0h, 1.0h);
}
