@fragment
fn fs_main(@location(0) p: vec3<f32>) -> @location(0) vec4<f32> {
    return vec4<f32>(q);
}
