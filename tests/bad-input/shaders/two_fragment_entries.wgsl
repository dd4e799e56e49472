@fragment fn a() -> @location(0) vec4<f32> { return vec4<f32>(1.0); }
@fragment fn b() -> @location(0) vec4<f32> { return vec4<f32>(0.5); }
