// Hand-written seed: helpers that store through pointer arguments (to a local, a struct member, an
// array element inside a loop), a matrix column store, an early top-level return, derivatives.
struct S { a: vec4<f32>, b: f32 };
fn bump(p: ptr<function, f32>, k: f32) { *p = *p * k + 1.0; }
fn setv(s: ptr<function, S>, v: vec4<f32>) { (*s).a = v; (*s).b = v.x; }
fn mk(x: f32) -> S { var s: S; setv(&s, vec4<f32>(x)); return s; }
@fragment
fn main(@location(0) p: vec2<f32>) -> @location(0) vec4<f32> {
    var s = mk(p.x);
    var arr: array<f32, 4>;
    for (var i = 0; i < 4; i++) { arr[i] = p.y * f32(i); bump(&arr[i], 2.0); }
    bump(&s.b, p.y);
    var m = mat2x2<f32>(p, p);
    m[1] = vec2<f32>(s.b);
    if (arr[2] > 0.5) { return vec4<f32>(0.0); }
    return s.a + vec4<f32>(arr[1], m[1].x, dpdx(p.x), fwidth(s.b));
}
