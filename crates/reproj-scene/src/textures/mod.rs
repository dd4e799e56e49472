//! Texture data: generated (noise, normal map, environment, checker, solid) or read from image
//! files, 2D arrays assembled from layers of either, with CPU mip chains. Uploading is in `assets.rs`.

use glam::{Vec3, Vec4};

use crate::reflect::TexDim;
use crate::session::{
    GltfTexture, MaterialSlot, Session, TexFormat, TextureKind, TextureParams, TextureSpec,
};

/// Texel data of one texture, f32 RGBA, all mip levels; each level holds `layers` images (6 for a
/// cube, the layer count for a 2D array, 1 otherwise) or, for 3D, `depth` slices.
#[derive(Debug, Clone)]
pub struct TextureData {
    pub dim: TexDim,
    pub width: u32,
    pub height: u32,
    /// Cube: 6; 2D array: its layers; 2D: 1; 3D: depth.
    pub layers: u32,
    pub format: TexFormat,
    /// `levels[m]` = texels of mip m, layer-major then row-major.
    pub levels: Vec<Vec<[f32; 4]>>,
}

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
fn fbm(p: Vec3, period: i32, octaves: u32, seed: u32) -> f32 {
    let (mut sum, mut amp, mut norm, mut freq) = (0.0, 1.0, 0.0, 1.0f32);
    for o in 0..octaves.max(1) {
        sum += amp * value_noise(p * freq, period * freq as i32, seed.wrapping_add(o * 1013));
        norm += amp;
        amp *= 0.5;
        freq *= 2.0;
    }
    sum / norm
}

fn f16_bits(x: f32) -> u16 {
    let b = x.to_bits();
    let sign = ((b >> 16) & 0x8000) as u16;
    let exp = ((b >> 23) & 0xff) as i32;
    let man = b & 0x7f_ffff;
    if exp == 0xff {
        return sign | 0x7c00 | if man != 0 { 0x200 } else { 0 };
    }
    let e = exp - 127 + 15;
    if e >= 0x1f {
        return sign | 0x7c00;
    }
    if e <= 0 {
        if e < -10 {
            return sign;
        }
        let m = (man | 0x80_0000) >> (1 - e);
        let round = (m >> 12) & 1;
        return sign | ((m >> 13) as u16 + round as u16);
    }
    let mut h = sign as u32 | ((e as u32) << 10) | (man >> 13);
    if (man >> 12) & 1 == 1 {
        h += 1; // round half up (carry into the exponent is correct)
    }
    h as u16
}

impl TextureData {
    /// Bytes per texel of the upload format.
    pub fn bytes_per_texel(&self) -> u32 {
        match self.format {
            TexFormat::Rgba16float => 8,
            _ => 4,
        }
    }

    /// Encode mip `level` in the upload format.
    pub fn encode_level(&self, level: usize) -> Vec<u8> {
        let texels = &self.levels[level];
        match self.format {
            TexFormat::Rgba16float => texels
                .iter()
                .flat_map(|t| t.iter().flat_map(|c| f16_bits(*c).to_le_bytes()))
                .collect(),
            _ => texels
                .iter()
                .flat_map(|t| t.iter().map(|c| (c.clamp(0.0, 1.0) * 255.0 + 0.5) as u8))
                .collect(),
        }
    }

    /// Size of mip `level`: (width, height, layers-or-depth).
    pub fn level_size(&self, level: usize) -> (u32, u32, u32) {
        let w = (self.width >> level).max(1);
        let h = (self.height >> level).max(1);
        let l = if self.dim == TexDim::D3 {
            (self.layers >> level).max(1)
        } else {
            self.layers
        };
        (w, h, l)
    }

    fn build_mips(&mut self) {
        if self.dim == TexDim::D3 {
            return; // 3D textures: base level only
        }
        loop {
            let lvl = self.levels.len() - 1;
            let (w, h, layers) = self.level_size(lvl);
            if w == 1 && h == 1 {
                break;
            }
            let (nw, nh) = ((w / 2).max(1), (h / 2).max(1));
            let src = &self.levels[lvl];
            let mut dst = Vec::with_capacity((nw * nh * layers) as usize);
            for l in 0..layers {
                for y in 0..nh {
                    for x in 0..nw {
                        let mut acc = [0.0f32; 4];
                        let mut n = 0.0;
                        for (dx, dy) in [(0, 0), (1, 0), (0, 1), (1, 1)] {
                            let sx = (2 * x + dx).min(w - 1);
                            let sy = (2 * y + dy).min(h - 1);
                            let t = src[(l * w * h + sy * w + sx) as usize];
                            for c in 0..4 {
                                acc[c] += t[c];
                            }
                            n += 1.0;
                        }
                        dst.push(acc.map(|a| a / n));
                    }
                }
            }
            self.levels.push(dst);
        }
    }
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

/// Build the data of `spec` for a shader variable of dimensionality `dim`.
pub fn build(
    session: &Session,
    name: &str,
    spec: &TextureSpec,
    dim: TexDim,
) -> Result<TextureData, String> {
    match (&spec.layers, dim) {
        (Some(layers), TexDim::D2Array) => build_array(session, name, spec, layers),
        (Some(_), _) => Err(format!(
            "texture `{name}` gives `layers`, which fill a texture_2d_array, but the shader's texture is {}",
            dim_text(dim)
        )),
        (None, TexDim::D2Array) => Err(format!(
            "texture `{name}` is a texture_2d_array; give its images in `layers` (a list of texture specs)"
        )),
        (None, _) => build_single(session, name, spec, dim),
    }
}

fn dim_text(dim: TexDim) -> &'static str {
    match dim {
        TexDim::D2 => "a texture_2d",
        TexDim::D2Array => "a texture_2d_array",
        TexDim::D3 => "a texture_3d",
        TexDim::Cube => "a texture_cube",
    }
}

/// A `texture_2d_array` from its layers: each built as a 2D texture without mips, all of one
/// size and format (the array's `format`, when given, applies to every layer), then the array's
/// mip chain.
fn build_array(
    session: &Session,
    name: &str,
    spec: &TextureSpec,
    layers: &[TextureSpec],
) -> Result<TextureData, String> {
    let mut out: Option<TextureData> = None;
    for (i, layer) in layers.iter().enumerate() {
        let mut layer = layer.clone();
        layer.mipmaps = false;
        if spec.format.is_some() {
            layer.format = spec.format;
        }
        let lname = format!("{name}.layers[{i}]");
        let d = build_single(session, &lname, &layer, TexDim::D2)?;
        match &mut out {
            None => out = Some(d),
            Some(o) => {
                if (d.width, d.height) != (o.width, o.height) {
                    return Err(format!(
                        "texture `{lname}` is {}×{}, layer 0 is {}×{}: the layers of an array need one size",
                        d.width, d.height, o.width, o.height
                    ));
                }
                if d.format != o.format {
                    return Err(format!(
                        "texture `{lname}` has format {:?}, layer 0 {:?}: give the array one `format`",
                        d.format, o.format
                    ));
                }
                o.levels[0].extend_from_slice(&d.levels[0]);
                o.layers += 1;
            }
        }
    }
    let mut data = out.ok_or_else(|| format!("texture `{name}` has no layers"))?;
    data.dim = TexDim::D2Array;
    if spec.mipmaps {
        data.build_mips();
    }
    Ok(data)
}

/// Build one texture that is not an array.
fn build_single(
    session: &Session,
    name: &str,
    spec: &TextureSpec,
    dim: TexDim,
) -> Result<TextureData, String> {
    let mut data = if let Some(kind) = spec.kind {
        procedural(name, spec, kind, dim)?
    } else if let Some(g) = &spec.gltf {
        from_gltf(session, name, spec, g, dim)?
    } else {
        from_files(session, name, spec, dim)?
    };
    if spec.mipmaps {
        data.build_mips();
    }
    Ok(data)
}

/// A generated texture (`kind`) of the shader's dimension: an environment as a cube map or an
/// equirectangular 2D map, a 3D noise or solid volume, or a 2D noise, normal map, checker or solid.
fn procedural(
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

/// A glTF material's texture, read from the file (2D only; base colour and emissive are sRGB).
fn from_gltf(
    session: &Session,
    name: &str,
    spec: &TextureSpec,
    g: &GltfTexture,
    dim: TexDim,
) -> Result<TextureData, String> {
    if dim != TexDim::D2 {
        return Err(format!(
            "texture `{name}` is {}; a glTF material's texture is 2D",
            dim_text(dim)
        ));
    }
    let (width, height, texels) =
        crate::gltf::texture(session, g).map_err(|e| format!("texture `{name}`: {e}"))?;
    // Base color and emissive textures hold sRGB values (glTF 2.0 § 3.9.2).
    let srgb = matches!(g.slot, MaterialSlot::BaseColor | MaterialSlot::Emissive);
    Ok(TextureData {
        dim,
        width,
        height,
        layers: 1,
        format: spec.format.unwrap_or(if srgb {
            TexFormat::Rgba8unormSrgb
        } else {
            TexFormat::Rgba8unorm
        }),
        levels: vec![texels],
    })
}

/// A 2D texture from an image file, or a cube map from six (`faces`), read through `image`.
fn from_files(
    session: &Session,
    name: &str,
    spec: &TextureSpec,
    dim: TexDim,
) -> Result<TextureData, String> {
    let format = spec.format.unwrap_or(TexFormat::Rgba8unorm);
    let files: Vec<std::path::PathBuf> = match (&spec.file, &spec.faces) {
        (Some(f), _) => vec![f.clone()],
        (_, Some(fs)) => fs.clone(),
        _ => return Err(format!("texture `{name}` has neither `kind` nor `file`")),
    };
    let expect = if dim == TexDim::Cube { 6 } else { 1 };
    if matches!(dim, TexDim::D3 | TexDim::D2Array) {
        return Err(format!(
            "texture `{name}` is {}; image files make 2D or cube textures",
            dim_text(dim)
        ));
    }
    if files.len() != expect {
        return Err(format!(
            "texture `{name}` needs {expect} image(s) for its shader type, the session gives {}",
            files.len()
        ));
    }
    let mut texels = Vec::new();
    let mut dims = None;
    for f in &files {
        let full = session
            .resolve(f)
            .map_err(|e| format!("texture `{name}`: {e}"))?;
        let (d, pixels) = read_image(&full)
            .map_err(|e| format!("texture `{name}`: cannot read {}: {e}", full.display()))?;
        if dims.is_some_and(|x| x != d) {
            return Err(format!("texture `{name}`: cube faces differ in size"));
        }
        dims = Some(d);
        texels.extend(pixels);
    }
    let (w, h) = dims.unwrap_or((1, 1));
    Ok(TextureData {
        dim,
        width: w,
        height: h,
        layers: expect as u32,
        format,
        levels: vec![texels],
    })
}

/// An image's size and its texels (RGBA, f32 of the stored values, top row first).
type Image = ((u32, u32), Vec<[f32; 4]>);

/// An image file's size and texels.
#[cfg(feature = "images")]
fn read_image(path: &std::path::Path) -> Result<Image, String> {
    // Through the one reader: a regular file within the size limit (a pipe would block).
    let bytes =
        reproj_io::read_input(path, reproj_io::InputKind::Asset).map_err(|e| e.to_string())?;
    let img = image::ImageReader::new(std::io::Cursor::new(bytes))
        .with_guessed_format()
        .map_err(|e| format!("{}: {e}", path.display()))?
        .decode()
        .map_err(|e| e.to_string())?
        .to_rgba32f();
    Ok((img.dimensions(), img.pixels().map(|p| p.0).collect()))
}

/// Without the `images` feature (the light build) no image file is read.
#[cfg(not(feature = "images"))]
fn read_image(_: &std::path::Path) -> Result<Image, String> {
    Err(
        "this reproj was built without image files (the `images` feature of reproj-cli, on by \
         default; the light build leaves it out)"
            .into(),
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn half_floats() {
        assert_eq!(f16_bits(0.0), 0);
        assert_eq!(f16_bits(1.0), 0x3c00);
        assert_eq!(f16_bits(-2.0), 0xc000);
        assert_eq!(f16_bits(0.5), 0x3800);
        assert_eq!(f16_bits(65504.0), 0x7bff);
        assert_eq!(f16_bits(1e6), 0x7c00);
    }

    #[test]
    fn noise_tiles_and_stays_in_range() {
        for i in 0..100 {
            let p = Vec3::new(i as f32 * 0.37, i as f32 * 0.11, 0.0);
            let a = fbm(p, 8, 4, 3);
            assert!((0.0..=1.0).contains(&a));
            let b = fbm(p + Vec3::new(8.0, 0.0, 0.0), 8, 4, 3);
            assert!((a - b).abs() < 1e-5);
        }
    }
}
