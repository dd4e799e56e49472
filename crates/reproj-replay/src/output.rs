//! PNG output: frames (sRGB-encoded), hit maps and error heat maps. Files are written to a
//! temporary name in the same directory and renamed, so a reader never sees a partial file.
//!
//! Names: `frame_NNN.png`, `hitmap_NNN.png` (green hit, red miss, blue refresh, black background),
//! `errmap_NNN.png` (per-pixel L2 error through a black → blue → red → yellow → white ramp, full
//! scale at [`ERRMAP_FULL_SCALE`]), `flipmap_NNN.png` (the ꟻLIP error map in NVIDIA's magma
//! colours, on the frames the perceptual metrics were computed for), and on request
//! `frame_NNN.f32`: the frame's exact linear RGBA values before PNG encoding (see
//! [`write_frame_raw`]), for comparing two renderers to 1e-4.

use std::io::Write;
use std::path::{Path, PathBuf};

use image::ImageEncoder;

use crate::ReplayError;

/// Error that maps to white in error maps.
pub const ERRMAP_FULL_SCALE: f32 = 0.1;

/// Linear → sRGB transfer function.
pub fn srgb_encode(x: f32) -> f32 {
    let x = x.clamp(0.0, 1.0);
    if x <= 0.003_130_8 {
        12.92 * x
    } else {
        1.055 * x.powf(1.0 / 2.4) - 0.055
    }
}

/// Write RGBA8 pixels as PNG atomically (temp file + rename).
pub fn write_png_rgba8(
    path: &Path,
    width: u32,
    height: u32,
    rgba: &[u8],
) -> Result<(), ReplayError> {
    let mut bytes = Vec::new();
    image::codecs::png::PngEncoder::new(&mut bytes)
        .write_image(rgba, width, height, image::ExtendedColorType::Rgba8)
        .map_err(|e| ReplayError::Image {
            path: path.to_owned(),
            message: e.to_string(),
        })?;
    write_atomic(path, &bytes)
}

/// Write `bytes` to `path` atomically (temp file in the same directory + rename), creating the
/// directory.
fn write_atomic(path: &Path, bytes: &[u8]) -> Result<(), ReplayError> {
    let io = |source| ReplayError::Io {
        path: path.to_owned(),
        source,
    };
    let dir = path
        .parent()
        .filter(|p| !p.as_os_str().is_empty())
        .unwrap_or(Path::new("."));
    std::fs::create_dir_all(dir).map_err(io)?;
    let file_name = path
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default();
    let tmp: PathBuf = dir.join(format!(".{file_name}.tmp{}", std::process::id()));
    let mut f = std::fs::File::create(&tmp).map_err(io)?;
    f.write_all(bytes).map_err(io)?;
    f.sync_all().ok();
    drop(f);
    std::fs::rename(&tmp, path).map_err(|e| {
        let _ = std::fs::remove_file(&tmp);
        io(e)
    })
}

/// RGBA f32 linear frame → sRGB-encoded RGBA8 (clamped, alpha forced to 255).
pub fn frame_to_rgba8(rgba: &[f32]) -> Vec<u8> {
    rgba.chunks_exact(4)
        .flat_map(|p| {
            [
                (srgb_encode(p[0]) * 255.0 + 0.5) as u8,
                (srgb_encode(p[1]) * 255.0 + 0.5) as u8,
                (srgb_encode(p[2]) * 255.0 + 0.5) as u8,
                255,
            ]
        })
        .collect()
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
) -> Result<PathBuf, ReplayError> {
    let p = dir.join(format!("frame_{index:03}.png"));
    write_png_rgba8(&p, width, height, &frame_to_rgba8(rgba))?;
    Ok(p)
}

/// `frame_NNN.f32` from an RGBA f32 linear frame: no header, `width × height × 4` little-endian
/// `f32` values (R, G, B, A per pixel), row-major, top row first — the frame target's texels as
/// rendered, not clamped.
pub fn write_frame_raw(dir: &Path, index: u32, rgba: &[f32]) -> Result<PathBuf, ReplayError> {
    let p = dir.join(format!("frame_{index:03}.f32"));
    let bytes: Vec<u8> = rgba.iter().flat_map(|x| x.to_le_bytes()).collect();
    write_atomic(&p, &bytes)?;
    Ok(p)
}

/// `errmap_NNN.png` from per-pixel errors.
pub fn write_errmap(
    dir: &Path,
    index: u32,
    width: u32,
    height: u32,
    errors: &[f32],
) -> Result<PathBuf, ReplayError> {
    let p = dir.join(format!("errmap_{index:03}.png"));
    let px: Vec<u8> = errors.iter().flat_map(|e| heat(*e)).collect();
    write_png_rgba8(&p, width, height, &px)?;
    Ok(p)
}

/// `flipmap_NNN.png`: a ꟻLIP error map ([`crate::perceptual::flip_map`]) through NVIDIA's magma
/// colour map (black: no error, pale yellow: 1).
pub fn write_flipmap(
    dir: &Path,
    index: u32,
    width: u32,
    height: u32,
    map: &[f32],
) -> Result<PathBuf, ReplayError> {
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
) -> Result<PathBuf, ReplayError> {
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
