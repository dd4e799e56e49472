//! Texture data: generated (noise, normal map, environment, checker, solid) or read from image
//! files, 2D arrays assembled from layers of either, with CPU mip chains. Uploading is in `assets.rs`.

use crate::reflect::TexDim;
use crate::session::{GltfTexture, MaterialSlot, Session, TexFormat, TextureSpec};

mod procedural;

use procedural::procedural;

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
    use glam::Vec3;

    use super::procedural::fbm;
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
