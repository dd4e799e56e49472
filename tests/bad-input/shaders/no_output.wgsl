@group(0) @binding(0) var<storage, read_write> o: array<f32>;
@fragment fn fs(@location(0) p: vec3<f32>) { o[0] = p.x; }
