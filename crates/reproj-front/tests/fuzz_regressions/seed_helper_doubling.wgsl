// Hand-written seed: helpers that each call the previous one twice (inlining doubles: 2^11 calls).
fn g0(x: f32) -> f32 { return sin(x); }
fn g1(x: f32) -> f32 { var y = g0(x); return y + g0(x * 2.0); }
fn g2(x: f32) -> f32 { var y = g1(x); return y + g1(x * 2.0); }
fn g3(x: f32) -> f32 { var y = g2(x); return y + g2(x * 2.0); }
fn g4(x: f32) -> f32 { var y = g3(x); return y + g3(x * 2.0); }
fn g5(x: f32) -> f32 { var y = g4(x); return y + g4(x * 2.0); }
fn g6(x: f32) -> f32 { var y = g5(x); return y + g5(x * 2.0); }
fn g7(x: f32) -> f32 { var y = g6(x); return y + g6(x * 2.0); }
fn g8(x: f32) -> f32 { var y = g7(x); return y + g7(x * 2.0); }
fn g9(x: f32) -> f32 { var y = g8(x); return y + g8(x * 2.0); }
fn g10(x: f32) -> f32 { var y = g9(x); return y + g9(x * 2.0); }
fn g11(x: f32) -> f32 { var y = g10(x); return y + g10(x * 2.0); }
@fragment fn main(@location(0) p: vec2<f32>) -> @location(0) vec4<f32> { return vec4<f32>(g11(p.x)); }
