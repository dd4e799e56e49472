// Hand-written seed: loops nested eight deep, with break, continue and a switch inside.
@fragment
fn main(@location(0) p: vec2<f32>) -> @location(0) vec4<f32> {
    var acc = 0.0;
    for (var a = 0; a < 2; a++) {
        for (var b = 0; b < 2; b++) {
            for (var c = 0; c < 2; c++) {
                for (var d = 0; d < 2; d++) {
                    var e = 0;
                    loop {
                        if (e >= 2) { break; }
                        var f = 0u;
                        while (f < 2u) {
                            f += 1u;
                            if (p.x > 0.5) { continue; }
                            for (var g = 0; g < 2; g++) {
                                switch (g) {
                                    case 0: { acc += sin(p.y * f32(a + b + c + d)); }
                                    default: { acc -= 0.1; }
                                }
                            }
                        }
                        continuing {
                            e += 1;
                            break if acc > 100.0;
                        }
                    }
                }
            }
        }
    }
    return vec4<f32>(acc, p, 1.0);
}
