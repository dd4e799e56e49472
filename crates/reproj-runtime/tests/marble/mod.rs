//! A small wgpu app that uses `reproj-runtime` (`app.rs`): it draws the marble variant `reproj
//! instance` writes into its own frame, with its own depth target, its own vertex stage and its
//! own bind group for the shader's `scene` uniform, and its frames must equal `reproj render
//! --variant`'s (every channel of every pixel of every frame within [`TOLERANCE`]; on lavapipe
//! they are identical, and the test prints the figure). Needs a Vulkan device (lavapipe without a
//! GPU: `scripts/ensure-vulkan.sh`).

mod app;
mod counts;

use std::path::Path;

use reproj_runtime::{FrameInputs, FrameTargets, RuntimeError, Setup, Variant};

use crate::common::{instance_marble, reproj, s};
use app::{App, COLOR, FRAMES, OBJECT_GROUP};

/// Largest allowed difference of any channel of any pixel between the app's frames and
/// `reproj render`'s.
const TOLERANCE: f32 = 1e-4;
/// `reproj render` of the marble session with the variant in `dir`; its raw frames.
fn render_reference(dir: &Path, out: &Path) -> Vec<Vec<f32>> {
    let max = FRAMES.to_string();
    reproj(&[
        "render",
        "shaders/marble.wgsl",
        "--session",
        "sessions/marble.json",
        "--variant",
        s(dir),
        "--frames",
        s(out),
        "--raw-frames",
        "--max-frames",
        &max,
    ]);
    (0..FRAMES)
        .map(|f| {
            let bytes = std::fs::read(out.join(format!("frame_{f:03}.f32"))).unwrap();
            bytemuck::pod_collect_to_vec::<u8, f32>(&bytes)
        })
        .collect()
}

/// The app's frames equal `reproj render --variant`'s, for the default 3pass variant and a 2pass
/// variant written with `--frame-load load` (the app draws the background first); running them
/// again after a restart or a resize gives the same frames; and the app's depth target holds the
/// scene's depth afterwards: short of the far plane exactly where the variant drew something other
/// than the background.
#[test]
fn an_app_using_the_runtime_renders_the_frames_reproj_render_does() {
    let tmp = tempfile::tempdir().unwrap();
    let cases: [(&str, &[&str]); 4] = [
        ("3pass", &[]),
        // The variant's bindings join marble's group 0, as for a shader that uses all four.
        (
            "fused-shared-group",
            &["--strategy", "fused", "--group", "0"],
        ),
        (
            "2pass-frame-load",
            &["--strategy", "2pass", "--frame-load", "load"],
        ),
        (
            "fused-depth-load",
            &["--strategy", "fused", "--depth-load", "load"],
        ),
    ];
    for (name, flags) in cases {
        let dir = tmp.path().join(name);
        instance_marble(&dir, flags);
        let variant = Variant::load(&dir).unwrap();
        assert_eq!(
            variant.delta_n(),
            Some(8),
            "{name}: the instancer's default Δn"
        );
        assert_eq!(variant.loads_frame_first(), name.ends_with("frame-load"));
        assert_eq!(variant.loads_depth_first(), name.ends_with("depth-load"));
        assert!(!variant.reads_motion_vectors());
        assert_eq!(variant.shares_group(), name.ends_with("shared-group"));
        if variant.shares_group() {
            assert_eq!((variant.group(), variant.binding_base()), (0, 1));
        }
        let app = App::new(variant.required_features());
        let vs = app.vertex_module(&variant);
        let stages = app.stages(&vs);
        let mut gpu = app.create(&variant, &stages);
        let (frames, depth) = app.run(&variant, &mut gpu, false);
        // Starting over, by a restart or a resize (there and back), gives the same frames: the
        // clock, the ping-pong and the textures' contents start again from frame 0.
        let (restarted, _) = app.run(&variant, &mut gpu, true);
        let [w, h] = app.size;
        gpu.resize(&app.device, [w / 2, h / 3]).unwrap();
        assert_eq!(gpu.size(), [w / 2, h / 3]);
        gpu.resize(&app.device, app.size).unwrap();
        let (resized, _) = app.run(&variant, &mut gpu, false);
        for (again, how) in [(&restarted, "restart"), (&resized, "resize")] {
            let same = frames
                .iter()
                .zip(again)
                .all(|(a, b)| a.iter().zip(b).all(|(x, y)| x.to_bits() == y.to_bits()));
            assert!(same, "{name}: the frames after a {how} differ");
        }
        let reference = render_reference(&dir, &tmp.path().join(format!("{name}-render")));
        let mut worst = 0.0f32;
        for (f, (a, b)) in frames.iter().zip(&reference).enumerate() {
            assert_eq!(a.len(), b.len(), "{name} frame {f}: sizes differ");
            for (x, y) in a.iter().zip(b) {
                assert!(
                    x.is_finite() && y.is_finite(),
                    "{name} frame {f}: not finite"
                );
                worst = worst.max((x - y).abs());
            }
        }
        println!(
            "{name} Δn 8: runtime app vs reproj render: max |difference| over {FRAMES} frames = {worst:e}"
        );
        assert!(worst <= TOLERANCE, "{name}: frames differ by up to {worst}");

        let last = frames.last().unwrap();
        let bg = app.session.background;
        let mut drawn = 0;
        for (px, z) in last.chunks_exact(4).zip(&depth) {
            let background = px.iter().zip(&bg).all(|(a, b)| a == b);
            assert_eq!(
                *z < 1.0,
                !background,
                "{name}: the depth target is the scene's depth"
            );
            drawn += usize::from(*z < 1.0);
        }
        assert!(
            drawn > last.len() / 4 / 10,
            "{name}: the torus covers the frame"
        );
    }
}

/// A variant written with `--depth-load load` is depth-tested against the app's own depth: behind
/// an occluder that covers the frame (the depth cleared to 0, the near plane) nothing of it is
/// drawn, nor does it write depth, frame after frame.
#[test]
fn a_variant_that_loads_the_engines_depth_hides_behind_it() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path().join("v");
    instance_marble(&dir, &["--strategy", "2pass", "--depth-load", "load"]);
    let variant = Variant::load(&dir).unwrap();
    assert!(variant.loads_depth_first());
    let app = App::new(variant.required_features());
    let vs = app.vertex_module(&variant);
    let stages = app.stages(&vs);
    let mut gpu = app.create(&variant, &stages);
    let (frames, depth) = app.run_over(&variant, &mut gpu, false, 0.0);
    let bg = app.session.background;
    for (f, frame) in frames.iter().enumerate() {
        assert!(
            frame
                .chunks_exact(4)
                .all(|px| px.iter().zip(&bg).all(|(a, b)| a == b)),
            "frame {f}: the variant drew in front of the engine's depth"
        );
    }
    assert!(
        depth.iter().all(|&z| z == 0.0),
        "the engine's depth was overwritten"
    );
    // With nothing in front, the same variant draws the torus.
    let (frames, _) = app.run_over(&variant, &mut gpu, true, 1.0);
    let last = frames.last().unwrap();
    assert!(
        last.chunks_exact(4)
            .any(|px| px.iter().zip(&bg).any(|(a, b)| a != b))
    );
    let errors = std::mem::take(&mut *app.errors.lock().unwrap());
    assert!(errors.is_empty(), "wgpu errors: {errors:#?}");
}

/// What the application gets wrong is an error naming the argument, never a panic or a wgpu
/// validation error: a missing layout for the shader's own group, a layout in the variant's group,
/// a shared group's bindings missing or given where the group is the variant's own,
/// targets of another format or size, a frame size without pixels.
#[test]
fn misuse_is_an_error_naming_the_argument() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path().join("v");
    instance_marble(&dir, &[]);
    let variant = Variant::load(&dir).unwrap();
    let app = App::new(variant.required_features());
    let vs = app.vertex_module(&variant);
    let stages = app.stages(&vs);
    let setup = |layouts: &[(u32, &wgpu::BindGroupLayout)]| {
        variant.create(
            &app.device,
            &Setup {
                size: app.size,
                color_format: COLOR,
                vertex: &stages,
                bind_group_layouts: layouts,
                classification: None,
                motion: None,
                shared: None,
            },
        )
    };
    usage(
        setup(&[(OBJECT_GROUP, &app.object_layout)]),
        "Setup::bind_group_layouts",
        "`scene` in group 0",
    );
    usage(
        setup(&[
            (0, &app.scene_layout),
            (variant.group(), &app.object_layout),
        ]),
        "Setup::bind_group_layouts",
        "the variant's own group",
    );
    let mut gpu = setup(&[(0, &app.scene_layout), (OBJECT_GROUP, &app.object_layout)]).unwrap();
    usage(gpu.resize(&app.device, [0, 5]), "size", "no pixel");
    // Motion vectors for a variant that reads none.
    usage(
        variant.create(
            &app.device,
            &Setup {
                size: app.size,
                color_format: COLOR,
                vertex: &stages,
                bind_group_layouts: &[(0, &app.scene_layout), (OBJECT_GROUP, &app.object_layout)],
                classification: None,
                motion: Some(&app.frame_view),
                shared: None,
            },
        ),
        "Setup::motion",
        "reads no motion vectors",
    );
    usage(
        gpu.set_motion(&app.device, &app.frame_view),
        "set_motion",
        "reads no motion vectors",
    );
    // No motion vectors for a variant that reads them.
    let motion_dir = tmp.path().join("motion");
    instance_marble(&motion_dir, &["--reproject", "motion-vectors"]);
    let motion = Variant::load(&motion_dir).unwrap();
    assert!(motion.reads_motion_vectors());
    assert_eq!(motion.vertex().prev_clip_location, None);
    usage(
        motion.create(
            &app.device,
            &Setup {
                size: app.size,
                color_format: COLOR,
                vertex: &stages,
                bind_group_layouts: &[(0, &app.scene_layout), (OBJECT_GROUP, &app.object_layout)],
                classification: None,
                motion: None,
                shared: None,
            },
        ),
        "Setup::motion",
        "give their texture",
    );
    // A shared group's bindings not given for a variant that shares marble's group 0, and given
    // for one that does not.
    let shared_dir = tmp.path().join("shared");
    instance_marble(&shared_dir, &["--group", "0"]);
    let shared = Variant::load(&shared_dir).unwrap();
    assert!(shared.shares_group());
    usage(
        shared.create(
            &app.device,
            &Setup {
                size: app.size,
                color_format: COLOR,
                vertex: &stages,
                bind_group_layouts: &[(OBJECT_GROUP, &app.object_layout)],
                classification: None,
                motion: None,
                shared: None,
            },
        ),
        "Setup::shared",
        "`scene` at binding 0",
    );
    usage(
        variant.create(
            &app.device,
            &Setup {
                size: app.size,
                color_format: COLOR,
                vertex: &stages,
                bind_group_layouts: &[(0, &app.scene_layout), (OBJECT_GROUP, &app.object_layout)],
                classification: None,
                motion: None,
                shared: Some(reproj_runtime::SharedGroup {
                    layout: &[],
                    resources: &[],
                }),
            },
        ),
        "Setup::shared",
        "is its own",
    );
    // The color target as the depth target: the wrong format.
    let mut enc = app.device.create_command_encoder(&Default::default());
    let wrong = FrameTargets {
        color: &app.frame_view,
        depth: &app.frame_view,
        clear_color: wgpu::Color::BLACK,
    };
    usage(
        gpu.record(
            &app.queue,
            &mut enc,
            &wrong,
            &FrameInputs::default(),
            no_draw,
        ),
        "FrameTargets::depth",
        "Depth32Float",
    );
    // Targets of the old size after a resize.
    gpu.resize(&app.device, [app.size[0] / 2, app.size[1]])
        .unwrap();
    let targets = FrameTargets {
        color: &app.frame_view,
        depth: &app.depth_view,
        clear_color: wgpu::Color::BLACK,
    };
    usage(
        gpu.record(
            &app.queue,
            &mut enc,
            &targets,
            &FrameInputs::default(),
            no_draw,
        ),
        "FrameTargets::color",
        "resize",
    );
    assert_eq!(gpu.frame(), 0, "nothing was recorded");
    drop(enc);
    let errors = std::mem::take(&mut *app.errors.lock().unwrap());
    assert!(errors.is_empty(), "wgpu errors: {errors:#?}");
}

/// `r` is a [`RuntimeError::Usage`] whose message starts with `what` and says `says`.
fn usage<T>(r: Result<T, RuntimeError>, what: &str, says: &str) {
    match r {
        Err(e @ RuntimeError::Usage { .. }) => {
            let text = e.to_string();
            assert!(text.starts_with(what) && text.contains(says), "`{text}`");
        }
        Err(e) => panic!("{what}: {e}"),
        Ok(_) => panic!("{what}: accepted"),
    }
}

fn no_draw(_: &mut wgpu::RenderPass<'_>, _: &[wgpu::RenderPipeline]) {}
