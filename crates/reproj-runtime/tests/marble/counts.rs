//! What the runtime tells a host beside the frame: per-pass occlusion counts (the hit rate where
//! the frame is drawn) and the debug hit map; and the host's own clock and separate render
//! passes, which change no pixel of what is drawn.

use reproj_runtime::{FrameInputs, FrameTargets, Variant, VariantResources};

use super::app::{App, FRAMES};
use crate::common::instance_marble;

/// What one frame of [`run`] gave back.
struct Frame {
    pixels: Vec<u8>,
    /// Samples each pass drew (its occlusion query).
    occlusion: Vec<u64>,
    /// Green (hit), red (miss), blue (refresh) pixels of the hit map.
    hit_map: [u64; 3],
}

/// [`FRAMES`] frames of `variant` with occlusion queries and the hit map; `inputs` sets the clock
/// (`None`: the runtime's count) and whether each pass has its own render pass.
fn run(
    app: &App,
    variant: &Variant,
    gpu: &mut VariantResources,
    (clock_from, separate_passes): (Option<u32>, bool),
) -> Vec<Frame> {
    let device = &app.device;
    let passes = variant.pass_count() as u32;
    let occlusion = device.create_query_set(&wgpu::QuerySetDescriptor {
        label: Some("occlusion"),
        ty: wgpu::QueryType::Occlusion,
        count: passes,
    });
    let buffer = |usage| {
        device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("occlusion counts"),
            size: 8 * u64::from(passes),
            usage,
            mapped_at_creation: false,
        })
    };
    let resolved = buffer(wgpu::BufferUsages::QUERY_RESOLVE | wgpu::BufferUsages::COPY_SRC);
    let read = buffer(wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::MAP_READ);
    let target = |format, usage| {
        device.create_texture(&wgpu::TextureDescriptor {
            label: Some("hit map"),
            size: wgpu::Extent3d {
                width: app.size[0],
                height: app.size[1],
                depth_or_array_layers: 1,
            },
            mip_level_count: 1,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format,
            usage: wgpu::TextureUsages::RENDER_ATTACHMENT | usage,
            view_formats: &[],
        })
    };
    let map = target(
        wgpu::TextureFormat::Rgba8Unorm,
        wgpu::TextureUsages::COPY_SRC,
    );
    let map_depth = target(
        wgpu::TextureFormat::Depth32Float,
        wgpu::TextureUsages::empty(),
    );
    let (map_view, map_depth_view) = (
        map.create_view(&Default::default()),
        map_depth.create_view(&Default::default()),
    );
    let scene = [(0, &app.scene_group)];
    let mut out = Vec::new();
    for f in 0..FRAMES {
        app.write_frame(f);
        let mut enc = device.create_command_encoder(&Default::default());
        let targets = FrameTargets {
            color: &app.frame_view,
            depth: &app.depth_view,
            clear_color: app.clear_color(),
        };
        let inputs = FrameInputs {
            bind_groups: &scene,
            restart: f == 0,
            occlusion: Some(&occlusion),
            clock: clock_from.map(|c| c + f),
            separate_passes,
            ..Default::default()
        };
        gpu.record(
            &app.queue,
            &mut enc,
            &targets,
            &inputs,
            |pass, pipelines| app.draw(pass, pipelines),
        )
        .unwrap();
        gpu.record_classification(&mut enc, (&map_view, &map_depth_view), &scene, |pass, p| {
            app.draw(pass, p)
        })
        .unwrap();
        enc.resolve_query_set(&occlusion, 0..passes, &resolved, 0);
        enc.copy_buffer_to_buffer(&resolved, 0, &read, 0, None);
        app.queue.submit([enc.finish()]);
        read.slice(..)
            .map_async(wgpu::MapMode::Read, |r| r.unwrap());
        device.poll(wgpu::PollType::wait_indefinitely()).unwrap();
        let counts: Vec<u64> = bytemuck::pod_collect_to_vec(&read.get_mapped_range(..).unwrap());
        read.unmap();
        let mut hit_map = [0u64; 3];
        for px in app.read_bytes(&map, 4).chunks_exact(4) {
            match px {
                [_, g, ..] if *g > 127 => hit_map[0] += 1,
                [r, ..] if *r > 127 => hit_map[1] += 1,
                [_, _, b, _] if *b > 127 => hit_map[2] += 1,
                _ => {}
            }
        }
        out.push(Frame {
            pixels: app.read_bytes(&app.frame, 16),
            occlusion: counts,
            hit_map,
        });
        let errors = std::mem::take(&mut *app.errors.lock().unwrap());
        assert!(errors.is_empty(), "frame {f}: wgpu errors: {errors:#?}");
    }
    out
}

/// A `3pass` variant built from its sources in memory, the hit-map entry appended to its first
/// pass: pass 1's occlusion count is the hit map's green pixels (the hits) every frame, pass 2's
/// its red and blue ones (recomputed and refreshed), pass 3's every pixel covered (each up to
/// the few samples overdrawn nearer); on frame 0
/// nothing is a hit. The host's clock (the runtime's count, given) and a render pass per pass
/// draw the same frames; a clock shifted by 3 refreshes other pixels.
#[test]
fn occlusion_counts_and_the_hit_map_agree_and_the_clock_phases_the_refresh() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path().join("v");
    instance_marble(&dir, &[]);
    let on_disk = Variant::load(&dir).unwrap();
    let manifest = std::fs::read_to_string(dir.join("manifest.json")).unwrap();
    let mut sources: Vec<String> = ["pass1_reproject", "pass2_recompute", "pass3_shade"]
        .iter()
        .map(|p| std::fs::read_to_string(dir.join(format!("{p}.wgsl"))).unwrap())
        .collect();
    sources[0].push_str(&reproj_instance::classify_wgsl(
        reproj_instance::Reprojection::Vertex,
    ));
    let variant = Variant::from_sources(&dir, &manifest, &sources).unwrap();
    assert_eq!(variant.pass_count(), on_disk.pass_count());
    let app = App::new(variant.required_features());
    let vs = app.vertex_module(&variant);
    let stages = app.stages(&vs);
    let mut gpu = app.create_with(&variant, &stages, Some(wgpu::TextureFormat::Rgba8Unorm));
    let plain = run(&app, &variant, &mut gpu, (None, false));
    // An occlusion query counts every sample that passes the depth test: where a later triangle
    // of the torus lies nearer than one drawn before, both count (a few pixels of 4096·…).
    let about = |counted: u64, pixels: u64, what: &str| {
        assert!(
            counted >= pixels && counted - pixels <= 3 + pixels / 1000,
            "{what}: {counted} counted, {pixels} pixels"
        );
    };
    for (f, fr) in plain.iter().enumerate() {
        let [hit, miss, refresh] = fr.hit_map;
        about(
            fr.occlusion[0],
            hit,
            &format!("frame {f}: pass 1 counts the hits"),
        );
        about(
            fr.occlusion[1],
            miss + refresh,
            &format!("frame {f}: pass 2 the rest"),
        );
        about(
            fr.occlusion[2],
            hit + miss + refresh,
            &format!("frame {f}: pass 3 all"),
        );
        if f == 0 {
            assert_eq!(hit, 0, "frame 0 reuses nothing");
        }
    }
    assert!(
        plain[FRAMES as usize - 1].hit_map[0] > 0,
        "later frames hit"
    );
    let same = run(&app, &variant, &mut gpu, (Some(0), true));
    for (f, (a, b)) in plain.iter().zip(&same).enumerate() {
        assert!(
            a.pixels == b.pixels,
            "frame {f}: given clock, own render passes"
        );
        assert_eq!(a.occlusion, b.occlusion, "frame {f}");
    }
    let shifted = run(&app, &variant, &mut gpu, (Some(3), false));
    assert!(
        plain
            .iter()
            .zip(&shifted)
            .skip(1)
            .any(|(a, b)| a.pixels != b.pixels),
        "a shifted clock refreshes other pixels"
    );
    let ran_classification_without = app
        .create(&variant, &stages)
        .record_classification(
            &mut app.device.create_command_encoder(&Default::default()),
            (&app.frame_view, &app.depth_view),
            &[],
            |_, _| {},
        )
        .unwrap_err()
        .to_string();
    assert!(
        ran_classification_without.contains("Setup::classification"),
        "{ran_classification_without}"
    );
}
