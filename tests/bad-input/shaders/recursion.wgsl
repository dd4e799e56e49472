fn f(x: f32) -> f32 { return f(x); }
@fragment fn fs() -> @location(0) vec4<f32> { return vec4<f32>(f(1.0)); }
