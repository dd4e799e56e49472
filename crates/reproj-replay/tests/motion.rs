//! The engine's motion vectors and depth (`--reproject motion-vectors`, `--depth-load load`),
//! rendered on the machine's adapter (lavapipe in CI): the replay draws the motion vectors in a
//! pass of its own, as an engine's velocity pass would, and clears the depth the first pass loads.
//!
//! - at Δn = 1 a motion-vector variant reproduces the original exactly, in every strategy;
//! - on marble in motion it is as good as the vertex path (within 0.5 dB PSNR at Δn 11), with
//!   about the same hit rate;
//! - a variant that loads the engine's depth renders what one that clears it does when the engine
//!   drew nothing else.

use std::path::PathBuf;

use reproj_front::{Shader, enumerate, load_file, normalize};
use reproj_instance::{DepthLoad, InstanceOptions, NodeSelector, Reprojection, Strategy, instance};
use reproj_metrics::RenderReport;
use reproj_replay::{Reference, RenderOptions, Renderer, RendererOptions, VariantInput};
use reproj_scene::Session;

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../..")
}

fn opts(frames: u32) -> RenderOptions {
    RenderOptions {
        png_dir: None,
        max_frames: Some(frames),
        first_frame: 0,
        timing_only: false,
        classify: false,
        raw_frames: false,
        perceptual_stride: None,
    }
}

/// Marble's turbulence (node 680, the node `emit` picks on it) as a variant with `options`,
/// rendered at Δn `delta_n` over the first `frames` frames.
fn render(
    renderer: &Renderer,
    shader: &Shader,
    session: &Session,
    reference: &Reference,
    options: InstanceOptions,
    delta_n: u32,
    frames: u32,
) -> RenderReport {
    let norm = normalize(shader, &Default::default()).unwrap();
    let table = enumerate(shader, &norm);
    let v = instance(shader, &norm, &table, NodeSelector::Id(680), &options).unwrap();
    let input = VariantInput::new(
        v.passes.iter().map(|p| p.wgsl.clone()).collect(),
        v.manifest.clone(),
        delta_n,
    );
    renderer
        .render_variant(shader, session, &input, reference, &opts(frames))
        .unwrap_or_else(|e| panic!("{options:?}: {e}"))
}

fn marble(renderer: &Renderer, frames: u32) -> (Shader, Session, Reference) {
    let shader = load_file(&root().join("shaders/marble.wgsl")).unwrap();
    let session = Session::load(root().join("sessions/marble.json")).unwrap();
    let reference = renderer
        .render_original(
            &shader,
            shader.fragment_entry(None).unwrap(),
            &session,
            &opts(frames),
        )
        .unwrap();
    (shader, session, reference)
}

#[test]
fn motion_vectors_at_delta_n_1_reproduce_the_original() {
    let renderer =
        Renderer::new(&RendererOptions::default()).expect("a Vulkan adapter (lavapipe in CI)");
    let (shader, session, reference) = marble(&renderer, 4);
    for strategy in Strategy::ALL {
        let options = InstanceOptions {
            strategy,
            reprojection: Reprojection::MotionVectors,
            ..Default::default()
        };
        let report = render(&renderer, &shader, &session, &reference, options, 1, 4);
        for f in &report.frames {
            assert_eq!(f.max_abs_diff, 0.0, "{strategy:?} frame {}", f.frame);
            assert_eq!(f.hits, 0, "{strategy:?}: Δn = 1 refreshes every pixel");
        }
    }
}

#[test]
fn motion_vectors_are_as_good_as_the_vertex_path_on_marble() {
    let renderer =
        Renderer::new(&RendererOptions::default()).expect("a Vulkan adapter (lavapipe in CI)");
    let frames = 48;
    let (shader, session, reference) = marble(&renderer, frames);
    let at = |reprojection| {
        let options = InstanceOptions {
            strategy: Strategy::TwoPass,
            reprojection,
            ..Default::default()
        };
        render(
            &renderer, &shader, &session, &reference, options, 11, frames,
        )
    };
    let vertex = at(Reprojection::Vertex);
    let motion = at(Reprojection::MotionVectors);
    let (pv, pm) = (vertex.psnr, motion.psnr);
    assert!(pv.is_finite() && pm.is_finite(), "{pv} {pm}");
    assert!(
        pm >= pv - 0.5,
        "motion vectors {pm:.2} dB, vertex {pv:.2} dB"
    );
    let (hv, hm) = (vertex.hit_rate, motion.hit_rate);
    assert!(hm > 0.8 && (hm - hv).abs() < 0.05, "hit rate {hm} vs {hv}");
}

#[test]
fn loading_the_engines_depth_changes_nothing_when_it_drew_nothing() {
    let renderer =
        Renderer::new(&RendererOptions::default()).expect("a Vulkan adapter (lavapipe in CI)");
    let (shader, session, reference) = marble(&renderer, 12);
    for strategy in Strategy::ALL {
        let at = |depth_load| {
            let options = InstanceOptions {
                strategy,
                depth_load,
                ..Default::default()
            };
            render(&renderer, &shader, &session, &reference, options, 8, 12)
        };
        let (clear, load) = (at(DepthLoad::Clear), at(DepthLoad::Load));
        for (c, l) in clear.frames.iter().zip(&load.frames) {
            assert_eq!(c.error, l.error, "{strategy:?} frame {}", c.frame);
            assert_eq!(c.hits, l.hits, "{strategy:?} frame {}", c.frame);
        }
    }
}
