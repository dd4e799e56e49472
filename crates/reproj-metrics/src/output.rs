//! PNG output: frames (sRGB-encoded), hit maps and error heat maps. Files are written to a
//! temporary name in the same directory and renamed, so a reader never sees a partial file.
//!
//! Names: `frame_NNN.png`, `hitmap_NNN.png` (green hit, red miss, blue refresh, black background),
//! `errmap_NNN.png` (per-pixel L2 error through a black → blue → red → yellow → white ramp, full
//! scale at [`ERRMAP_FULL_SCALE`], with a labelled colour bar under the frame: [`errmap_rgba8`]),
//! `ref_NNN.png` (the original's frame beside a variant's: [`write_reference_frame`]),
//! `flipmap_NNN.png` (the ꟻLIP error map in NVIDIA's magma colours, on the frames the perceptual
//! metrics were computed for), and on request `frame_NNN.f32`: the frame's exact linear RGBA
//! values before PNG encoding (see [`write_frame_raw`]), for comparing two renderers to 1e-4.

use std::path::{Path, PathBuf};

use image::ImageEncoder;

use crate::srgb::frame_to_rgba8;

/// An image that could not be written.
#[derive(Debug, thiserror::Error)]
pub enum OutputError {
    #[error("cannot encode {path}: {message}")]
    Image { path: PathBuf, message: String },
    #[error(transparent)]
    Write(#[from] reproj_io::WriteError),
}

/// Error that maps to white in error maps.
pub const ERRMAP_FULL_SCALE: f32 = 0.1;

/// Write RGBA8 pixels as PNG atomically (temp file + rename).
pub fn write_png_rgba8(
    path: &Path,
    width: u32,
    height: u32,
    rgba: &[u8],
) -> Result<(), OutputError> {
    let mut bytes = Vec::new();
    image::codecs::png::PngEncoder::new(&mut bytes)
        .write_image(rgba, width, height, image::ExtendedColorType::Rgba8)
        .map_err(|e| OutputError::Image {
            path: path.to_owned(),
            message: e.to_string(),
        })?;
    Ok(reproj_io::write_file(path, &bytes)?)
}

/// Heat-map color of an error value.
pub fn heat(e: f32) -> [u8; 4] {
    let t = (e / ERRMAP_FULL_SCALE).clamp(0.0, 1.0);
    let stops: [[f32; 3]; 5] = [
        [0.0, 0.0, 0.0],
        [0.0, 0.0, 1.0],
        [1.0, 0.0, 0.0],
        [1.0, 1.0, 0.0],
        [1.0, 1.0, 1.0],
    ];
    let x = t * 4.0;
    let i = (x.floor() as usize).min(3);
    let f = x - i as f32;
    let c: Vec<u8> = (0..3)
        .map(|k| ((stops[i][k] + (stops[i + 1][k] - stops[i][k]) * f) * 255.0 + 0.5) as u8)
        .collect();
    [c[0], c[1], c[2], 255]
}

/// `frame_NNN.png` from an RGBA f32 linear frame.
pub fn write_frame(
    dir: &Path,
    index: u32,
    width: u32,
    height: u32,
    rgba: &[f32],
) -> Result<PathBuf, OutputError> {
    write_srgb_frame(
        &dir.join(format!("frame_{index:03}.png")),
        width,
        height,
        rgba,
    )
}

/// `frame_NNN.f32` from an RGBA f32 linear frame: no header, `width × height × 4` little-endian
/// `f32` values (R, G, B, A per pixel), row-major, top row first — the frame target's texels as
/// rendered, not clamped.
pub fn write_frame_raw(dir: &Path, index: u32, rgba: &[f32]) -> Result<PathBuf, OutputError> {
    let p = dir.join(format!("frame_{index:03}.f32"));
    let bytes: Vec<u8> = rgba.iter().flat_map(|x| x.to_le_bytes()).collect();
    reproj_io::write_file(&p, &bytes)?;
    Ok(p)
}

/// `ref_NNN.png`: the original shader's frame, written beside a variant's `frame_NNN.png`.
pub fn write_reference_frame(
    dir: &Path,
    index: u32,
    width: u32,
    height: u32,
    rgba: &[f32],
) -> Result<PathBuf, OutputError> {
    write_srgb_frame(
        &dir.join(format!("ref_{index:03}.png")),
        width,
        height,
        rgba,
    )
}

/// A linear RGBA f32 frame as an sRGB PNG at `path`.
fn write_srgb_frame(
    path: &Path,
    width: u32,
    height: u32,
    rgba: &[f32],
) -> Result<PathBuf, OutputError> {
    write_png_rgba8(path, width, height, &frame_to_rgba8(rgba))?;
    Ok(path.to_owned())
}

/// `errmap_NNN.png` from per-pixel errors, with its colour bar ([`errmap_rgba8`]).
pub fn write_errmap(
    dir: &Path,
    index: u32,
    width: u32,
    height: u32,
    errors: &[f32],
) -> Result<PathBuf, OutputError> {
    let p = dir.join(format!("errmap_{index:03}.png"));
    let (h, px) = errmap_rgba8(width, height, errors);
    write_png_rgba8(&p, width, h, &px)?;
    Ok(p)
}

/// An error map as RGBA8: the `width × height` heat map of `errors` ([`heat`]), then below it a
/// colour bar of the ramp from 0 to [`ERRMAP_FULL_SCALE`] with its values written under ticks
/// (a built-in 3×5 pixel font, scaled with the width, so no font file is needed). Returns the
/// image's height and its pixels.
pub fn errmap_rgba8(width: u32, height: u32, errors: &[f32]) -> (u32, Vec<u8>) {
    let s = (width / 160).max(1) as usize;
    let w = width as usize;
    let (gap, bar, text) = (2 * s, 6 * s, 5 * s);
    let extra = gap + bar + s + text + gap;
    let mut px: Vec<u8> = errors.iter().flat_map(|e| heat(*e)).collect();
    px.resize(w * (height as usize + extra) * 4, 0);
    for p in px[w * height as usize * 4..].chunks_exact_mut(4) {
        p.copy_from_slice(&[32, 32, 32, 255]);
    }
    let top = height as usize + gap;
    let mut put = |x: usize, y: usize, c: [u8; 4]| {
        if x < w {
            px[((top + y) * w + x) * 4..][..4].copy_from_slice(&c);
        }
    };
    for x in 0..w {
        let c = heat(ERRMAP_FULL_SCALE * x as f32 / (w.max(2) - 1) as f32);
        for y in 0..bar {
            put(x, y, c);
        }
    }
    // Ticks and labels: 0, the middle and the full scale (and the quarters when there is room).
    let labels: &[(f32, &str)] = if w >= 240 {
        &[
            (0.0, "0"),
            (0.25, "0.025"),
            (0.5, "0.05"),
            (0.75, "0.075"),
            (1.0, "0.1+"),
        ]
    } else {
        &[(0.0, "0"), (0.5, "0.05"), (1.0, "0.1+")]
    };
    let white = [255, 255, 255, 255];
    for &(t, label) in labels {
        let x = ((w - 1) as f32 * t) as usize;
        for y in bar..bar + s {
            put(x, y, white);
        }
        let tw = label.len() * 4 * s - s;
        let x0 = x.saturating_sub(tw / 2).min(w.saturating_sub(tw));
        for (i, ch) in label.chars().enumerate() {
            let rows = glyph(ch);
            for (gy, row) in rows.iter().enumerate() {
                for gx in 0..3 {
                    if row & (0b100 >> gx) != 0 {
                        for dy in 0..s {
                            for dx in 0..s {
                                put(x0 + (i * 4 + gx) * s + dx, bar + s + gy * s + dy, white);
                            }
                        }
                    }
                }
            }
        }
    }
    (height + extra as u32, px)
}

/// A 3×5 pixel glyph (rows top to bottom, bit 2 = left column) for the colour-bar labels.
fn glyph(c: char) -> [u8; 5] {
    match c {
        '0' => [0b111, 0b101, 0b101, 0b101, 0b111],
        '1' => [0b010, 0b110, 0b010, 0b010, 0b111],
        '2' => [0b111, 0b001, 0b111, 0b100, 0b111],
        '3' => [0b111, 0b001, 0b011, 0b001, 0b111],
        '4' => [0b101, 0b101, 0b111, 0b001, 0b001],
        '5' => [0b111, 0b100, 0b111, 0b001, 0b111],
        '6' => [0b111, 0b100, 0b111, 0b101, 0b111],
        '7' => [0b111, 0b001, 0b010, 0b010, 0b010],
        '8' => [0b111, 0b101, 0b111, 0b101, 0b111],
        '9' => [0b111, 0b101, 0b111, 0b001, 0b111],
        '.' => [0b000, 0b000, 0b000, 0b000, 0b010],
        '+' => [0b000, 0b010, 0b111, 0b010, 0b000],
        _ => [0; 5],
    }
}

#[cfg(feature = "flip")]
/// `flipmap_NNN.png`: a ꟻLIP error map ([`crate::perceptual::flip_map`]) through NVIDIA's magma
/// colour map (black: no error, pale yellow: 1).
pub fn write_flipmap(
    dir: &Path,
    index: u32,
    width: u32,
    height: u32,
    map: &[f32],
) -> Result<PathBuf, OutputError> {
    let p = dir.join(format!("flipmap_{index:03}.png"));
    write_png_rgba8(
        &p,
        width,
        height,
        &crate::perceptual::flip_colors(map, width, height),
    )?;
    Ok(p)
}

/// `hitmap_NNN.png` from the RGBA8 classification map (already green / red / blue / black).
pub fn write_hitmap(
    dir: &Path,
    index: u32,
    width: u32,
    height: u32,
    classify_rgba8: &[u8],
) -> Result<PathBuf, OutputError> {
    let p = dir.join(format!("hitmap_{index:03}.png"));
    let px: Vec<u8> = classify_rgba8
        .chunks_exact(4)
        .flat_map(|c| [c[0], c[1], c[2], 255])
        .collect();
    write_png_rgba8(&p, width, height, &px)?;
    Ok(p)
}

#[cfg(test)]
mod tests {
    #[test]
    fn error_maps_carry_a_labelled_colour_bar() {
        let (w, h) = (64u32, 40u32);
        let errors = vec![0.0f32; (w * h) as usize];
        let (total, px) = super::errmap_rgba8(w, h, &errors);
        assert!(total > h);
        assert_eq!(px.len(), (w * total * 4) as usize);
        let at = |x: u32, y: u32| -> [u8; 4] {
            let i = ((y * w + x) * 4) as usize;
            [px[i], px[i + 1], px[i + 2], px[i + 3]]
        };
        // The frame is black (no error); the bar runs from the ramp's 0 to its full scale.
        assert_eq!(at(10, 10), [0, 0, 0, 255]);
        assert_eq!(at(0, h + 2), super::heat(0.0));
        assert_eq!(at(w - 1, h + 2), super::heat(super::ERRMAP_FULL_SCALE));
        // The labels are white pixels under the bar.
        let white = (h + 8..total)
            .flat_map(|y| (0..w).map(move |x| (x, y)))
            .filter(|&(x, y)| at(x, y) == [255, 255, 255, 255])
            .count();
        assert!(white > 20, "{white}");
    }

    #[test]
    fn raw_frames_hold_the_exact_values() {
        let dir = tempfile::tempdir().unwrap();
        let px = [0.25f32, -1.5, 7.0e-6, 1.0, 2.5, 0.0, 1.0, 0.5];
        let p = super::write_frame_raw(dir.path(), 4, &px).unwrap();
        assert_eq!(p.file_name().unwrap(), "frame_004.f32");
        let bytes = std::fs::read(&p).unwrap();
        let back: Vec<f32> = bytes
            .chunks_exact(4)
            .map(|b| f32::from_le_bytes([b[0], b[1], b[2], b[3]]))
            .collect();
        assert_eq!(back, px);
    }
}
