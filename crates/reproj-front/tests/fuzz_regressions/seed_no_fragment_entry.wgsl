// Hand-written seed: no fragment entry point at all.
@group(0) @binding(0) var<storage, read_write> data: array<f32>;

fn helper(x: f32) -> f32 {
    return x * x;
}

@compute @workgroup_size(64)
fn cs_main(@builtin(global_invocation_id) id: vec3<u32>) {
    data[id.x] = helper(data[id.x]);
}

@vertex
fn vs_main(@builtin(vertex_index) i: u32) -> @builtin(position) vec4<f32> {
    return vec4<f32>(f32(i), 0.0, 0.0, 1.0);
}
