//! Generated texture content: periodic fBm value noise, an analytic environment (sky with
//! clouds and a sun over the ground, as a cube map or an equirectangular map), 3D volumes and
//! the flat 2D kinds (noise, normal map, checker, solid).

use glam::{Vec3, Vec4};

use super::TextureData;
use crate::reflect::TexDim;
use crate::session::{TexFormat, TextureKind, TextureParams, TextureSpec};

fn hash3(x: i32, y: i32, z: i32, seed: u32) -> f32 {
    let mut h = (x as u32).wrapping_mul(0x8da6_b343)
        ^ (y as u32).wrapping_mul(0xd816_3841)
        ^ (z as u32).wrapping_mul(0xcb1a_b31f)
        ^ seed.wrapping_mul(0x9e37_79b9);
    h ^= h >> 16;
    h = h.wrapping_mul(0x7feb_352d);
    h ^= h >> 15;
    h = h.wrapping_mul(0x846c_a68b);
    h ^= h >> 16;
    (h >> 8) as f32 / (1u32 << 24) as f32
}

fn fade(t: f32) -> f32 {
    t * t * t * (t * (t * 6.0 - 15.0) + 10.0)
}

/// Value noise in [0, 1] at `p`, tiling with integer `period` per axis (0 = no tiling).
fn value_noise(p: Vec3, period: i32, seed: u32) -> f32 {
    let i = p.floor();
    let f = p - i;
    let (ix, iy, iz) = (i.x as i32, i.y as i32, i.z as i32);
    let wrap = |a: i32| if period > 0 { a.rem_euclid(period) } else { a };
    let c = |dx: i32, dy: i32, dz: i32| hash3(wrap(ix + dx), wrap(iy + dy), wrap(iz + dz), seed);
    let (u, v, w) = (fade(f.x), fade(f.y), fade(f.z));
    let lerp = |a: f32, b: f32, t: f32| a + (b - a) * t;
    let x00 = lerp(c(0, 0, 0), c(1, 0, 0), u);
    let x10 = lerp(c(0, 1, 0), c(1, 1, 0), u);
    let x01 = lerp(c(0, 0, 1), c(1, 0, 1), u);
    let x11 = lerp(c(0, 1, 1), c(1, 1, 1), u);
    lerp(lerp(x00, x10, v), lerp(x01, x11, v), w)
}

/// Fractal value noise in [0, 1]; `p` in cells of the base octave.
pub(super) fn fbm(p: Vec3, period: i32, octaves: u32, seed: u32) -> f32 {
    let (mut sum, mut amp, mut norm, mut freq) = (0.0, 1.0, 0.0, 1.0f32);
    for o in 0..octaves.max(1) {
        sum += amp * value_noise(p * freq, period * freq as i32, seed.wrapping_add(o * 1013));
        norm += amp;
        amp *= 0.5;
        freq *= 2.0;
    }
    sum / norm
}

fn cube_dir(face: u32, s: f32, t: f32) -> Vec3 {
    match face {
        0 => Vec3::new(1.0, -t, -s),
        1 => Vec3::new(-1.0, -t, s),
        2 => Vec3::new(s, 1.0, t),
        3 => Vec3::new(s, -1.0, -t),
        4 => Vec3::new(s, -t, 1.0),
        _ => Vec3::new(-s, -t, -1.0),
    }
    .normalize()
}

fn environment(d: Vec3, p: &TextureParams) -> [f32; 4] {
    let sun = Vec3::from(p.sun_direction).normalize_or_zero();
    let sky = Vec3::from(p.sky_color);
    let hor = Vec3::from(p.horizon_color);
    let gnd = Vec3::from(p.ground_color);
    let c = if d.y >= 0.0 {
        let clouds = fbm(d * 4.0 + Vec3::splat(10.0), 0, 4, p.seed);
        let base = hor.lerp(sky, d.y.sqrt());
        let cloud = ((clouds - 0.45) * 3.0).clamp(0.0, 1.0) * d.y.sqrt();
        base.lerp(Vec3::splat(0.9), cloud * 0.6)
    } else {
        let n = fbm(d * 8.0, 0, 3, p.seed.wrapping_add(7));
        gnd.lerp(hor * 0.5, (1.0 + d.y).powi(8)) * (0.8 + 0.4 * n)
    };
    let cosang = d.dot(sun).max(0.0);
    let c = c + Vec3::splat(p.sun_intensity * (cosang.powf(512.0) + 0.02 * cosang.powf(16.0)));
    let c: Vec4 = c.extend(1.0);
    c.into()
}

/// A generated texture (`kind`) of the shader's dimension: an environment as a cube map or an
/// equirectangular 2D map, a 3D noise or solid volume, or a 2D noise, normal map, checker or solid.
pub(super) fn procedural(
    name: &str,
    spec: &TextureSpec,
    kind: TextureKind,
    dim: TexDim,
) -> Result<TextureData, String> {
    let p = &spec.params;
    let size = spec.size;
    let format = spec.format.unwrap_or(if kind == TextureKind::Environment {
        TexFormat::Rgba16float
    } else {
        TexFormat::Rgba8unorm
    });
    Ok(match (kind, dim) {
        (TextureKind::Environment, TexDim::Cube) => environment_cube(p, size, dim, format),
        (TextureKind::Environment, TexDim::D2) => environment_equirect(p, size, dim, format),
        (_, TexDim::D2Array) => {
            return Err(format!(
                "texture `{name}` is a texture_2d_array; give its images in `layers`"
            ));
        }
        (_, TexDim::Cube) => {
            return Err(format!(
                "texture `{name}` is a texture_cube; only kind \"environment\" or `faces` can fill it"
            ));
        }
        (TextureKind::Environment, TexDim::D3) => {
            return Err(format!(
                "texture `{name}` is a texture_3d; kind \"environment\" makes 2D or cube maps"
            ));
        }
        (kind, TexDim::D3) => volume(name, kind, p, size, dim, format)?,
        (kind, TexDim::D2) => flat(kind, p, size, dim, format),
    })
}

/// The six faces of a cube map of the procedural environment, `size`² texels each.
fn environment_cube(p: &TextureParams, size: u32, dim: TexDim, format: TexFormat) -> TextureData {
    let mut texels = Vec::with_capacity((size * size * 6) as usize);
    for face in 0..6 {
        for y in 0..size {
            for x in 0..size {
                let s = 2.0 * (x as f32 + 0.5) / size as f32 - 1.0;
                let t = 2.0 * (y as f32 + 0.5) / size as f32 - 1.0;
                texels.push(environment(cube_dir(face, s, t), p));
            }
        }
    }
    TextureData {
        dim,
        width: size,
        height: size,
        layers: 6,
        format,
        levels: vec![texels],
    }
}

/// The procedural environment as an equirectangular 2D map, `2·size`×`size`.
fn environment_equirect(
    p: &TextureParams,
    size: u32,
    dim: TexDim,
    format: TexFormat,
) -> TextureData {
    // Equirectangular: u = atan2(d.z, d.x) / 2π + 0.5, v = acos(d.y) / π.
    let (w, h) = (size * 2, size);
    let mut texels = Vec::with_capacity((w * h) as usize);
    for y in 0..h {
        for x in 0..w {
            let lon = ((x as f32 + 0.5) / w as f32 - 0.5) * std::f32::consts::TAU;
            let th = (y as f32 + 0.5) / h as f32 * std::f32::consts::PI;
            let d = Vec3::new(th.sin() * lon.cos(), th.cos(), th.sin() * lon.sin());
            texels.push(environment(d, p));
        }
    }
    TextureData {
        dim,
        width: w,
        height: h,
        layers: 1,
        format,
        levels: vec![texels],
    }
}

/// A 3D texture: fBm noise between two colours, or a solid colour (at most 256³).
fn volume(
    name: &str,
    kind: TextureKind,
    p: &TextureParams,
    size: u32,
    dim: TexDim,
    format: TexFormat,
) -> Result<TextureData, String> {
    if kind != TextureKind::Noise && kind != TextureKind::Solid {
        return Err(format!(
            "texture `{name}` is a texture_3d; only kinds \"noise\" and \"solid\" make 3D textures"
        ));
    }
    let n = size.min(256);
    let period = p.scale.round().max(1.0) as i32;
    let mut texels = Vec::with_capacity((n * n * n) as usize);
    for z in 0..n {
        for y in 0..n {
            for x in 0..n {
                if kind == TextureKind::Solid {
                    texels.push(p.color);
                } else {
                    let q = Vec3::new(x as f32, y as f32, z as f32) / n as f32 * period as f32;
                    let v = fbm(q, period, p.octaves, p.seed);
                    texels.push(std::array::from_fn(|c| {
                        p.color_low[c] + (p.color_high[c] - p.color_low[c]) * v
                    }));
                }
            }
        }
    }
    Ok(TextureData {
        dim,
        width: n,
        height: n,
        layers: n,
        format,
        levels: vec![texels],
    })
}

/// A 2D texture of `kind` (not the environment): noise, a normal map of the noise, a checker, or
/// a solid colour.
fn flat(
    kind: TextureKind,
    p: &TextureParams,
    size: u32,
    dim: TexDim,
    format: TexFormat,
) -> TextureData {
    let period = p.scale.round().max(1.0) as i32;
    let height = |x: u32, y: u32| {
        let q = Vec3::new(x as f32 / size as f32, y as f32 / size as f32, 0.0) * period as f32;
        fbm(q, period, p.octaves, p.seed)
    };
    let mut texels = Vec::with_capacity((size * size) as usize);
    match kind {
        TextureKind::Noise => {
            for y in 0..size {
                for x in 0..size {
                    let v = height(x, y);
                    texels.push(std::array::from_fn(|c| {
                        p.color_low[c] + (p.color_high[c] - p.color_low[c]) * v
                    }));
                }
            }
        }
        TextureKind::NormalMap => {
            let hs: Vec<f32> = (0..size * size)
                .map(|i| height(i % size, i / size))
                .collect();
            let at = |x: i64, y: i64| {
                let s = size as i64;
                hs[(y.rem_euclid(s) * s + x.rem_euclid(s)) as usize]
            };
            let k = p.strength * size as f32 / period as f32;
            for y in 0..size as i64 {
                for x in 0..size as i64 {
                    let dx = (at(x + 1, y) - at(x - 1, y)) * 0.5 * k;
                    let dy = (at(x, y + 1) - at(x, y - 1)) * 0.5 * k;
                    let n = Vec3::new(-dx, -dy, 1.0).normalize();
                    let e = n * 0.5 + Vec3::splat(0.5);
                    texels.push([e.x, e.y, e.z, 1.0]);
                }
            }
        }
        TextureKind::Checker => {
            let sq = p.squares.max(1);
            for y in 0..size {
                for x in 0..size {
                    let cx = x * sq / size;
                    let cy = y * sq / size;
                    texels.push(if (cx + cy).is_multiple_of(2) {
                        p.color_a
                    } else {
                        p.color_b
                    });
                }
            }
        }
        TextureKind::Solid => texels.resize((size * size) as usize, p.color),
        TextureKind::Environment => unreachable!(),
    }
    TextureData {
        dim,
        width: size,
        height: size,
        layers: 1,
        format,
        levels: vec![texels],
    }
}
