@fragment
fn fs_main(@location(0) p: vec3<f32>) -> @location(0) vec4<f32> {
    let a: vec5<f32> = vec4<f32>(1.0);
    return vec4<f32>(1.0);
}
