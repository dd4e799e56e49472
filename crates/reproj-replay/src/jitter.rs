//! Sub-pixel jitter of the projection: the camera's view-projection moved by a fraction of a pixel
//! per frame, as temporal antialiasing and upsampling do (a different sample position inside each
//! pixel every frame), or by a fixed offset (one sample of a supersampled reference). Only the
//! vertex stage's transform moves; the previous frame's matrix (motion) stays unjittered, so a
//! motion vector read at a jittered pixel is the surface's motion plus the current offset.

/// Where each frame's samples sit inside their pixels.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub enum Jitter {
    /// Pixel centers.
    #[default]
    None,
    /// The same offset every frame, in pixels (x right, y down), each in (−½, ½).
    Fixed([f32; 2]),
    /// The Halton (2, 3) sequence, `phases` offsets long, repeating: frame `f` takes offset
    /// `f mod phases` (FSR 2's choice: ⌊8·(full / render)²⌋ phases per axis ratio).
    Halton { phases: u32 },
}

impl Jitter {
    /// The offset of frame `frame`, in pixels (x right, y down), each in (−½, ½).
    pub fn offset(&self, frame: u32) -> [f32; 2] {
        match *self {
            Jitter::None => [0.0, 0.0],
            Jitter::Fixed(o) => o,
            Jitter::Halton { phases } => halton_offset(frame % phases.max(1)),
        }
    }

    /// FSR 2's phase count for rendering at `scale` of the output's side: ⌊8 / scale²⌋, at
    /// least 8.
    pub fn phases_for(scale: f64) -> u32 {
        let s = scale.clamp(1e-3, 1.0);
        ((8.0 / (s * s)).floor() as u32).max(8)
    }
}

/// Term `index` (from 0) of the Halton sequence of base `base`, in [0, 1).
pub fn halton(mut index: u32, base: u32) -> f32 {
    let (mut f, mut r) = (1.0f64, 0.0f64);
    while index > 0 {
        f /= f64::from(base);
        r += f * f64::from(index % base);
        index /= base;
    }
    r as f32
}

/// Halton (2, 3) offset `i`, centered: terms 1.. (term 0 is the pixel's corner), minus ½.
pub fn halton_offset(i: u32) -> [f32; 2] {
    [halton(i + 1, 2) - 0.5, halton(i + 1, 3) - 0.5]
}

/// `view_proj` moved so that a point lands `offset` pixels (x right, y down) from where it would
/// on a `size` = `[width, height]` target: the clip position's x and y move by
/// `2·offset/size·w` (y negated: NDC points up).
pub fn jittered(view_proj: glam::Mat4, offset: [f32; 2], size: [u32; 2]) -> glam::Mat4 {
    if offset == [0.0, 0.0] {
        return view_proj;
    }
    let dx = 2.0 * offset[0] / size[0].max(1) as f32;
    let dy = -2.0 * offset[1] / size[1].max(1) as f32;
    let shift = glam::Mat4::from_cols(
        glam::Vec4::X,
        glam::Vec4::Y,
        glam::Vec4::Z,
        glam::Vec4::new(dx, dy, 0.0, 1.0),
    );
    shift * view_proj
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn halton_offsets_are_the_known_sequence_inside_the_pixel() {
        assert_eq!(halton(1, 2), 0.5);
        assert_eq!(halton(2, 2), 0.25);
        assert!((halton(2, 3) - 2.0 / 3.0).abs() < 1e-6);
        let o = halton_offset(0);
        assert!((o[0] - 0.0).abs() < 1e-6 && (o[1] + 1.0 / 6.0).abs() < 1e-6);
        for i in 0..64 {
            let [x, y] = Jitter::Halton { phases: 16 }.offset(i);
            assert!(x.abs() < 0.5 && y.abs() < 0.5);
        }
        assert_eq!(
            Jitter::Halton { phases: 8 }.offset(3),
            Jitter::Halton { phases: 8 }.offset(11)
        );
        assert_eq!(Jitter::phases_for(1.0), 8);
        assert_eq!(Jitter::phases_for(0.5), 32);
    }

    /// A point at the screen's center moves by exactly the offset in pixels, y down.
    #[test]
    fn a_jittered_projection_moves_points_by_the_offset() {
        let vp = glam::Mat4::IDENTITY;
        let size = [200, 100];
        let m = jittered(vp, [0.25, -0.5], size);
        let clip = m * glam::Vec4::new(0.0, 0.0, 0.5, 2.0);
        let ndc = clip.truncate() / clip.w;
        let px = [
            (ndc.x * 0.5 + 0.5) * size[0] as f32,
            (0.5 - ndc.y * 0.5) * size[1] as f32,
        ];
        assert!((px[0] - 100.25).abs() < 1e-4, "{px:?}");
        assert!((px[1] - 49.5).abs() < 1e-4, "{px:?}");
    }
}
