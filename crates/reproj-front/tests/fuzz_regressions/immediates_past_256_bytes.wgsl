// An immediate (push-constant) block of 512 bytes, read: naga's validator computed the 4-byte
// slots it covers in a u64 mask, and a slot past the 64th overflowed the shift.
struct Big {
    a: array<vec4<f32>, 32>,
}

var<immediate> big: Big;

@fragment
fn main() -> @location(0) vec4<f32> {
    return big.a[31];
}
