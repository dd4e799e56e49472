@group(0) @binding(0) var ext: texture_external;
@group(0) @binding(1) var smp: sampler;
@fragment
fn fs_main(@location(0) p: vec3<f32>, @location(2) uv: vec2<f32>) -> @location(0) vec4<f32> {
    let c = textureSampleBaseClampToEdge(ext, smp, uv).rgb;
    return vec4<f32>(c * (sin(p * 7.0) * 0.5 + 0.5), 1.0);
}
