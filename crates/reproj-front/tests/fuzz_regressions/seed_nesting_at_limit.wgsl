// Hand-written seed: nesting just under the walker's limit of 64 (60 inlined helpers, then loops
// and branches 3 deep, and an entry point with 60 nested blocks): must work, without overflowing
// a 2 MiB test thread in a debug build.
fn g0(x: f32) -> f32 {
    var acc = x;
    for (var i = 0; i < 2; i++) {
        if (acc > 0.5) {
            { acc = acc * 0.5; }
        }
    }
    return acc;
}
fn g1(x: f32) -> f32 { return g0(x) + 1.0; }
fn g2(x: f32) -> f32 { return g1(x) + 1.0; }
fn g3(x: f32) -> f32 { return g2(x) + 1.0; }
fn g4(x: f32) -> f32 { return g3(x) + 1.0; }
fn g5(x: f32) -> f32 { return g4(x) + 1.0; }
fn g6(x: f32) -> f32 { return g5(x) + 1.0; }
fn g7(x: f32) -> f32 { return g6(x) + 1.0; }
fn g8(x: f32) -> f32 { return g7(x) + 1.0; }
fn g9(x: f32) -> f32 { return g8(x) + 1.0; }
fn g10(x: f32) -> f32 { return g9(x) + 1.0; }
fn g11(x: f32) -> f32 { return g10(x) + 1.0; }
fn g12(x: f32) -> f32 { return g11(x) + 1.0; }
fn g13(x: f32) -> f32 { return g12(x) + 1.0; }
fn g14(x: f32) -> f32 { return g13(x) + 1.0; }
fn g15(x: f32) -> f32 { return g14(x) + 1.0; }
fn g16(x: f32) -> f32 { return g15(x) + 1.0; }
fn g17(x: f32) -> f32 { return g16(x) + 1.0; }
fn g18(x: f32) -> f32 { return g17(x) + 1.0; }
fn g19(x: f32) -> f32 { return g18(x) + 1.0; }
fn g20(x: f32) -> f32 { return g19(x) + 1.0; }
fn g21(x: f32) -> f32 { return g20(x) + 1.0; }
fn g22(x: f32) -> f32 { return g21(x) + 1.0; }
fn g23(x: f32) -> f32 { return g22(x) + 1.0; }
fn g24(x: f32) -> f32 { return g23(x) + 1.0; }
fn g25(x: f32) -> f32 { return g24(x) + 1.0; }
fn g26(x: f32) -> f32 { return g25(x) + 1.0; }
fn g27(x: f32) -> f32 { return g26(x) + 1.0; }
fn g28(x: f32) -> f32 { return g27(x) + 1.0; }
fn g29(x: f32) -> f32 { return g28(x) + 1.0; }
fn g30(x: f32) -> f32 { return g29(x) + 1.0; }
fn g31(x: f32) -> f32 { return g30(x) + 1.0; }
fn g32(x: f32) -> f32 { return g31(x) + 1.0; }
fn g33(x: f32) -> f32 { return g32(x) + 1.0; }
fn g34(x: f32) -> f32 { return g33(x) + 1.0; }
fn g35(x: f32) -> f32 { return g34(x) + 1.0; }
fn g36(x: f32) -> f32 { return g35(x) + 1.0; }
fn g37(x: f32) -> f32 { return g36(x) + 1.0; }
fn g38(x: f32) -> f32 { return g37(x) + 1.0; }
fn g39(x: f32) -> f32 { return g38(x) + 1.0; }
fn g40(x: f32) -> f32 { return g39(x) + 1.0; }
fn g41(x: f32) -> f32 { return g40(x) + 1.0; }
fn g42(x: f32) -> f32 { return g41(x) + 1.0; }
fn g43(x: f32) -> f32 { return g42(x) + 1.0; }
fn g44(x: f32) -> f32 { return g43(x) + 1.0; }
fn g45(x: f32) -> f32 { return g44(x) + 1.0; }
fn g46(x: f32) -> f32 { return g45(x) + 1.0; }
fn g47(x: f32) -> f32 { return g46(x) + 1.0; }
fn g48(x: f32) -> f32 { return g47(x) + 1.0; }
fn g49(x: f32) -> f32 { return g48(x) + 1.0; }
fn g50(x: f32) -> f32 { return g49(x) + 1.0; }
fn g51(x: f32) -> f32 { return g50(x) + 1.0; }
fn g52(x: f32) -> f32 { return g51(x) + 1.0; }
fn g53(x: f32) -> f32 { return g52(x) + 1.0; }
fn g54(x: f32) -> f32 { return g53(x) + 1.0; }
fn g55(x: f32) -> f32 { return g54(x) + 1.0; }
fn g56(x: f32) -> f32 { return g55(x) + 1.0; }
fn g57(x: f32) -> f32 { return g56(x) + 1.0; }
fn g58(x: f32) -> f32 { return g57(x) + 1.0; }
fn g59(x: f32) -> f32 { return g58(x) + 1.0; }
@fragment
fn chain(@location(0) p: vec2<f32>) -> @location(0) vec4<f32> {
    return vec4<f32>(g59(p.x));
}
@fragment
fn blocks(@location(0) p: vec2<f32>) -> @location(0) vec4<f32> {
    var acc = p.x;
    { { { { { { { { { { { { { { { { { { { { { { { { { { { { { { { { { { { { { { { { { { { { { { { { { { { { { { { { { { { { if (p.y > 0.5) { acc = sin(acc); } } } } } } } } } } } } } } } } } } } } } } } } } } } } } } } } } } } } } } } } } } } } } } } } } } } } } } } } } } } } }
    return vec4<f32>(acc);
}
