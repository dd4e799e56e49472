//! The temporal upsampler (`Renderer::render_upsampled`), rendered on the machine's adapter
//! (lavapipe in CI):
//!
//! - on a still session at scale 1 it converges toward the supersampled image: its last frame is
//!   closer to a 16-sample reference than the one-sample original is, and within 1 dB of a
//!   4-sample supersampled image's own score;
//! - on marble in motion at half the resolution per axis its frames beat the same low-resolution
//!   frames upsampled bilinearly, both against an 8-sample supersampled reference: the history,
//!   reprojected with the motion pass, adds detail (and the motion damping keeps its resampling
//!   blur from taking it back);
//! - a jittered render moves the image by the offset, and a zero offset changes nothing;
//! - a variant composed with it (`render_upsampled_variant`, its cache at the render resolution)
//!   gives the upsampler's own frames at Δn 1, and at Δn 8 the variant's own error.

use std::path::PathBuf;

use reproj_front::{Shader, enumerate, load_file, normalize};
use reproj_instance::{InstanceOptions, NodeSelector, instance};
use reproj_metrics::l2;
use reproj_replay::jitter::halton_offset;
use reproj_replay::{
    Jitter, Reference, RenderOptions, Renderer, RendererOptions, UpsampleSpec, VariantInput,
};
use reproj_scene::Session;

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../..")
}

fn opts(frames: u32) -> RenderOptions {
    RenderOptions {
        max_frames: Some(frames),
        classify: false,
        ..Default::default()
    }
}

fn renderer() -> Renderer {
    Renderer::new(&RendererOptions::default()).expect("a Vulkan adapter (lavapipe in CI)")
}

fn marble() -> Shader {
    load_file(&root().join("shaders/marble.wgsl")).unwrap()
}

/// The mean of `n` renders of `frames` frames, each with its own fixed Halton offset.
fn supersampled(
    r: &Renderer,
    shader: &Shader,
    session: &Session,
    frames: u32,
    n: u32,
) -> Vec<Vec<f32>> {
    let mut sum: Option<Vec<Vec<f32>>> = None;
    for i in 0..n {
        let jitter = Jitter::Fixed(halton_offset(i));
        let one = r
            .render_original_jittered(shader, 0, session, &opts(frames), jitter)
            .unwrap();
        match &mut sum {
            None => sum = Some(one.frames),
            Some(s) => {
                for (acc, f) in s.iter_mut().zip(&one.frames) {
                    for (a, v) in acc.iter_mut().zip(f) {
                        *a += v;
                    }
                }
            }
        }
    }
    let mut s = sum.unwrap();
    for f in &mut s {
        for v in f.iter_mut() {
            *v /= n as f32;
        }
    }
    s
}

fn psnr(frame: &[f32], reference: &[f32], depth: &[f32]) -> f64 {
    l2::compare(frame, reference, depth).psnr()
}

fn original(r: &Renderer, shader: &Shader, session: &Session, frames: u32) -> Reference {
    r.render_original(shader, 0, session, &opts(frames))
        .unwrap()
}

#[test]
fn on_a_still_session_it_converges_to_the_supersampled_image() {
    let r = renderer();
    let shader = marble();
    let mut session = Session::load(root().join("sessions/test_static.json")).unwrap();
    let frames = 32;
    session.frames = frames;
    let one = original(&r, &shader, &session, frames);
    let ss16 = supersampled(&r, &shader, &session, frames, 16);
    let ss4 = supersampled(&r, &shader, &session, frames, 4);
    let up = r
        .render_upsampled(
            &shader,
            0,
            &session,
            &UpsampleSpec::at(session.resolution),
            &opts(frames),
        )
        .unwrap();
    let last = (frames - 1) as usize;
    let depth = &one.depth[last];
    let taa = psnr(&up.frames[last], &ss16[last], depth);
    let single = psnr(&one.frames[last], &ss16[last], depth);
    let four = psnr(&ss4[last], &ss16[last], depth);
    eprintln!(
        "against 16 samples: upsampler {taa:.2} dB, one sample {single:.2} dB, 4 samples {four:.2} dB"
    );
    assert!(taa > single, "{taa} vs one sample {single}");
    assert!(taa > four - 1.0, "{taa} vs 4 samples {four}");
    assert_eq!(up.report.frames.len(), frames as usize);
    assert!(up.report.frames.iter().all(|f| f.frame_ms > 0.0));
}

/// Bilinear upsampling, pixel centers aligned and edges clamped.
fn bilinear(src: &[f32], [sw, sh]: [u32; 2], [dw, dh]: [u32; 2]) -> Vec<f32> {
    let axis = |d: u32, dn: u32, sn: u32| {
        let x = ((d as f64 + 0.5) * sn as f64 / dn as f64 - 0.5).clamp(0.0, (sn - 1) as f64);
        let i = x.floor() as u32;
        (i, (i + 1).min(sn - 1), (x - i as f64) as f32)
    };
    let px = |x: u32, y: u32, c: u32| src[((y * sw + x) * 4 + c) as usize];
    let mut out = Vec::with_capacity((dw * dh * 4) as usize);
    for y in 0..dh {
        let (y0, y1, fy) = axis(y, dh, sh);
        for x in 0..dw {
            let (x0, x1, fx) = axis(x, dw, sw);
            for c in 0..4 {
                let top = px(x0, y0, c) * (1.0 - fx) + px(x1, y0, c) * fx;
                let bottom = px(x0, y1, c) * (1.0 - fx) + px(x1, y1, c) * fx;
                out.push(top * (1.0 - fy) + bottom * fy);
            }
        }
    }
    out
}

#[test]
fn in_motion_at_half_resolution_it_beats_bilinear_upsampling() {
    let r = renderer();
    let shader = marble();
    let session = Session::load(root().join("sessions/marble.json")).unwrap();
    let frames = 32;
    let full = session.resolution;
    let half = full.map(|v| v / 2);
    let one = original(&r, &shader, &session, frames);
    let ss = supersampled(&r, &shader, &session, frames, 8);
    let mut small = session.clone();
    small.resolution = half;
    let low = original(&r, &shader, &small, frames);
    let up = r
        .render_upsampled(&shader, 0, &session, &UpsampleSpec::at(half), &opts(frames))
        .unwrap();
    let (mut taa, mut bil) = (0.0, 0.0);
    for (((low, up), ss), depth) in low
        .frames
        .iter()
        .zip(&up.frames)
        .zip(&ss)
        .zip(&one.depth)
        .skip(8)
    {
        taa += psnr(up, ss, depth);
        bil += psnr(&bilinear(low, half, full), ss, depth);
    }
    let n = (frames - 8) as f64;
    let (taa, bil) = (taa / n, bil / n);
    eprintln!(
        "marble at half resolution, frames 8..{frames}: upsampler {taa:.2} dB, bilinear {bil:.2} dB"
    );
    assert!(taa > bil + 0.3, "upsampler {taa} dB vs bilinear {bil} dB");
}

#[test]
fn a_jittered_render_moves_the_image_and_a_zero_offset_changes_nothing() {
    let r = renderer();
    let shader = marble();
    let session = Session::load(root().join("sessions/test_static.json")).unwrap();
    let plain = original(&r, &shader, &session, 1);
    let zero = r
        .render_original_jittered(&shader, 0, &session, &opts(1), Jitter::Fixed([0.0, 0.0]))
        .unwrap();
    assert_eq!(plain.frames[0], zero.frames[0]);
    let moved = r
        .render_original_jittered(&shader, 0, &session, &opts(1), Jitter::Fixed([0.49, 0.0]))
        .unwrap();
    assert_ne!(plain.frames[0], moved.frames[0]);
    // The silhouette moves right: the first covered column of the middle row moves by 0 or 1.
    let w = session.resolution[0] as usize;
    let row = session.resolution[1] as usize / 2;
    let first = |d: &[f32]| (0..w).find(|&x| d[row * w + x] < 1.0).unwrap();
    let (a, b) = (first(&plain.depth[0]), first(&moved.depth[0]));
    assert!(b == a || b == a + 1, "{a} → {b}");
}

/// reproj composed with temporal upsampling: marble's root cached inside the upsampler. At Δn 1
/// every pixel is recomputed each frame, so at half the resolution the frames are the upsampler's
/// own (the variant reproduces the original, and the resolve is the same). At Δn 8 and scale 1
/// the composition loses nothing to the cache's reuse beyond what the variant alone loses:
/// against 8 samples it stays within 1 dB of the variant drawn plainly (the history's reuse
/// inside the upsampler is reproj's own, and each frame's jitter does not blur it further).
#[test]
#[allow(clippy::needless_range_loop)]
fn a_variant_inside_the_upsampler_gives_its_frames_at_delta_n_1_and_its_own_error_at_8() {
    let r = renderer();
    let shader = marble();
    let session = Session::load(root().join("sessions/marble.json")).unwrap();
    let frames = 24;
    let full = session.resolution;
    let half = full.map(|v| v / 2);
    let norm = normalize(&shader, &Default::default()).unwrap();
    let table = enumerate(&shader, &norm);
    let v = instance(
        &shader,
        &norm,
        &table,
        NodeSelector::Root,
        &InstanceOptions::default(),
    )
    .unwrap();
    let input = |dn| {
        VariantInput::new(
            v.passes.iter().map(|p| p.wgsl.clone()).collect(),
            v.manifest.clone(),
            dn,
        )
    };
    let spec = UpsampleSpec::at(half);
    let up = r
        .render_upsampled(&shader, 0, &session, &spec, &opts(frames))
        .unwrap();
    let at1 = r
        .render_upsampled_variant(&shader, &session, &input(1), &spec, &opts(frames))
        .unwrap();
    assert_eq!(at1.frames.len(), frames as usize);
    let worst = up
        .frames
        .iter()
        .zip(&at1.frames)
        .flat_map(|(a, b)| a.iter().zip(b).map(|(x, y)| (x - y).abs()))
        .fold(0.0f32, f32::max);
    assert!(worst < 1e-3, "Δn 1: frames differ by up to {worst}");

    let one = original(&r, &shader, &session, frames);
    let ss = supersampled(&r, &shader, &session, frames, 8);
    let dir = tempfile::tempdir().unwrap();
    let plain = RenderOptions {
        png_dir: Some(dir.path().to_path_buf()),
        raw_frames: true,
        ..opts(frames)
    };
    r.render_variant(&shader, &session, &input(8), &one, &plain)
        .unwrap();
    let composed = r
        .render_upsampled_variant(
            &shader,
            &session,
            &input(8),
            &UpsampleSpec::at(full),
            &opts(frames),
        )
        .unwrap();
    assert!(composed.report.frames.iter().all(|f| f.frame_ms > 0.0));
    let (mut alone, mut both) = (0.0, 0.0);
    for f in 8..frames as usize {
        let raw = std::fs::read(dir.path().join(format!("frame_{f:03}.f32"))).unwrap();
        let pixels: Vec<f32> = bytemuck::pod_collect_to_vec(&raw);
        alone += psnr(&pixels, &ss[f], &one.depth[f]);
        both += psnr(&composed.frames[f], &ss[f], &one.depth[f]);
    }
    let n = (frames - 8) as f64;
    let (alone, both) = (alone / n, both / n);
    eprintln!(
        "marble root at Δn 8 against 8 samples: the variant {alone:.2} dB, inside the upsampler at scale 1 {both:.2} dB; Δn 1 at half resolution: max |difference| {worst:e}"
    );
    assert!(
        both > alone - 1.0,
        "{both} dB inside the upsampler vs {alone} alone"
    );
}
