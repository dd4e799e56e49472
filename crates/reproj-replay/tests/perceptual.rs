//! The perceptual metrics on a real replay (marble, its recorded session): a variant at Δn = 1 is
//! the original (ꟻLIP ≈ 0, SSIM ≈ 1), a long refresh period scores worse, and the frames sampled
//! on a stride are the ones reported. Needs a Vulkan adapter (lavapipe in CI).

use std::path::PathBuf;

use reproj_front::{enumerate, load_file, normalize};
use reproj_instance::{InstanceOptions, NodeSelector, instance};
use reproj_replay::{PerceptualOn, RenderOptions, Renderer, RendererOptions, VariantInput};
use reproj_scene::Session;

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../..")
}

#[test]
fn flip_and_ssim_grow_with_the_refresh_period_on_marble() {
    // Scored on the device (the CPU's path through the variant loop is every analysis's on
    // lavapipe).
    let renderer = Renderer::new(&RendererOptions {
        perceptual_on: PerceptualOn::Device,
        ..Default::default()
    })
    .expect("a Vulkan adapter (lavapipe in CI)");
    let shader = load_file(&root().join("shaders/marble.wgsl")).unwrap();
    let session = Session::load(root().join("sessions/marble.json")).unwrap();
    let norm = normalize(&shader, &Default::default()).unwrap();
    let table = enumerate(&shader, &norm);
    let opts = RenderOptions {
        max_frames: Some(24),
        classify: false,
        perceptual_stride: Some(3),
        ..Default::default()
    };
    let entry = shader.fragment_entry(None).unwrap();
    let reference = renderer
        .render_original(&shader, entry, &session, &opts)
        .unwrap();
    let v = instance(
        &shader,
        &norm,
        &table,
        NodeSelector::Root,
        &InstanceOptions::default(),
    )
    .unwrap();
    let replay = |delta_n: u32| {
        let input = VariantInput::new(
            v.passes.iter().map(|p| p.wgsl.clone()).collect(),
            v.manifest.clone(),
            delta_n,
        );
        renderer
            .render_variant(&shader, &session, &input, &reference, &opts)
            .unwrap()
    };
    let exact = replay(1);
    let stale = replay(20);
    for r in [&exact, &stale] {
        // Frames 0, 3, ..., 21: eight of the 24, and only those carry the metrics.
        let (flip, ssim) = (r.flip.unwrap(), r.ssim.unwrap());
        assert_eq!((flip.frames, ssim.frames), (8, 8));
        for f in &r.frames {
            assert_eq!(f.flip.is_some(), f.frame % 3 == 0, "frame {}", f.frame);
            assert_eq!(f.ssim.is_some(), f.frame % 3 == 0, "frame {}", f.frame);
        }
        assert_eq!(flip.worst.frame % 3, 0);
        let worst = r.frames[flip.worst.frame as usize].flip.unwrap();
        assert_eq!(worst, flip.worst.value);
        assert!(r.frames.iter().filter_map(|f| f.flip).all(|v| v <= worst));
        // L2 is untouched: every frame, all pixels.
        let l2 = r.error_worst.unwrap();
        assert!(r.frames.iter().all(|f| f.error <= l2.value));
    }
    let (f1, s1) = (exact.flip.unwrap(), exact.ssim.unwrap());
    assert!(f1.worst.value < 1e-3, "Δn = 1: ꟻLIP {f1:?}");
    assert!(s1.worst.value > 0.999, "Δn = 1: SSIM {s1:?}");
    let (f20, s20) = (stale.flip.unwrap(), stale.ssim.unwrap());
    assert!(
        f20.mean > f1.mean + 0.005 && f20.worst.value > f20.mean,
        "Δn = 20: ꟻLIP {f20:?}"
    );
    assert!(
        s20.mean < s1.mean - 0.005 && s20.worst.value < s20.mean,
        "Δn = 20: SSIM {s20:?}"
    );
}

/// `render_scored` (the error reduced on the GPU, ꟻLIP and SSIM of the sampled frames on the
/// device or on the CPU, no frame kept) scores a shader as the CPU scores its kept frames (to f32
/// rounding): marble with its turbulence halved, against marble.
#[test]
fn a_scored_render_equals_scoring_the_kept_frames_on_the_device() {
    scored_render_equals_kept_frames(PerceptualOn::Device);
}

#[test]
fn a_scored_render_equals_scoring_the_kept_frames_on_the_cpu() {
    scored_render_equals_kept_frames(PerceptualOn::Cpu);
}

fn scored_render_equals_kept_frames(perceptual_on: PerceptualOn) {
    let renderer = Renderer::new(&RendererOptions {
        perceptual_on,
        ..Default::default()
    })
    .expect("a Vulkan adapter (lavapipe in CI)");
    let path = root().join("shaders/marble.wgsl");
    let shader = load_file(&path).unwrap();
    let session = Session::load(root().join("sessions/marble.json")).unwrap();
    let opts = RenderOptions {
        max_frames: Some(8),
        perceptual_stride: Some(3),
        ..Default::default()
    };
    let entry = shader.fragment_entry(None).unwrap();
    let reference = renderer
        .render_original(&shader, entry, &session, &opts)
        .unwrap();
    // The same shader scores 0 everywhere.
    let same = renderer
        .render_scored(&shader, entry, &session, &reference, &opts)
        .unwrap();
    assert_eq!(same.frames.len(), 8);
    assert!(same.frames.iter().all(|f| f.error == 0.0), "{same:?}");
    assert_eq!(same.flip.unwrap().mean, 0.0);
    // Another shader: the GPU's figures are the CPU's on the kept frames.
    let source = std::fs::read_to_string(&path).unwrap();
    let other_src = source.replace(
        "return vec4<f32>(color, 1.0);",
        "return vec4<f32>(0.5 * color, 1.0);",
    );
    assert_ne!(other_src, source, "the test must change the shader");
    let other = reproj_front::parse_shader(&path, other_src).unwrap();
    let other_entry = other.fragment_entry(None).unwrap();
    let scored = renderer
        .render_scored(&other, other_entry, &session, &reference, &opts)
        .unwrap();
    let kept = renderer
        .render_original(&other, other_entry, &session, &opts)
        .unwrap();
    for (f, rec) in scored.frames.iter().enumerate() {
        let cpu =
            reproj_metrics::l2::compare(&kept.frames[f], &reference.frames[f], &reference.depth[f]);
        let (gpu, cpu) = (rec.error, cpu.error());
        assert!(
            gpu > 0.0 && (gpu - cpu).abs() <= 1e-5 * cpu,
            "frame {f}: {gpu} vs {cpu}"
        );
        assert_eq!(rec.flip.is_some(), f % 3 == 0, "frame {f}");
        if let Some(flip) = rec.flip {
            let (p, _) = reproj_metrics::perceptual::compare_perceptual(
                &kept.frames[f],
                &reference.frames[f],
                &reference.depth[f],
                session.resolution[0],
                session.resolution[1],
            );
            assert!(
                (flip - p.flip).abs() <= 1e-5 + 1e-4 * p.flip,
                "frame {f}: ꟻLIP {flip} vs {}",
                p.flip
            );
            let ssim = rec.ssim.unwrap();
            assert!(
                (ssim - p.ssim).abs() <= 1e-4,
                "frame {f}: SSIM {ssim} vs {}",
                p.ssim
            );
        }
    }
}
