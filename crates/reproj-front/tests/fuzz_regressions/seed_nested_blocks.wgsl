// Hand-written seed: a store inside 100 nested bare blocks, read after them (over the walker's
// nesting limit of 64: an Unsupported error).
@fragment
fn main(@location(0) p: vec2<f32>) -> @location(0) vec4<f32> {
 var acc = 0.0;
{{{{{{{{{{{{{{{{{{{{{{{{{{{{{{{{{{{{{{{{{{{{{{{{{{{{{{{{{{{{{{{{{{{{{{{{{{{{{{{{{{{{{{{{{{{{{{{{{{{{acc = acc + p.x;}}}}}}}}}}}}}}}}}}}}}}}}}}}}}}}}}}}}}}}}}}}}}}}}}}}}}}}}}}}}}}}}}}}}}}}}}}}}}}}}}}}}}}}}}}}}}}}}}}}}return vec4<f32>(acc);
}
