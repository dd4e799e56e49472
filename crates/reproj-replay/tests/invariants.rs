//! The cache invariants on real instancer output, rendered on the machine's adapter (lavapipe in CI):
//!
//! - at Δn = 1 a variant reproduces the original shader (every pixel refreshed every frame), for
//!   every cacheable node of every sample shader;
//! - with nothing moving, a variant at Δn = 8 reuses its cache exactly: error < 1e-4 after frame 0,
//!   hit rate about 1 − 1/8.

use std::path::PathBuf;

use reproj_front::{enumerate, load_file, normalize};
use reproj_instance::{InstanceOptions, NodeSelector, instance};
use reproj_replay::{RenderOptions, Renderer, RendererOptions, VariantInput};
use reproj_scene::Session;

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../..")
}

fn samples() -> Vec<PathBuf> {
    let mut v: Vec<PathBuf> = std::fs::read_dir(root().join("shaders"))
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "wgsl"))
        .collect();
    v.sort();
    v
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

#[test]
fn delta_n_1_reproduces_the_original_for_every_cacheable_node() {
    let renderer =
        Renderer::new(&RendererOptions::default()).expect("a Vulkan adapter (lavapipe in CI)");
    let session = Session::load(root().join("sessions/test_static.json")).unwrap();
    let mut checked = 0;
    for path in samples() {
        let shader = load_file(&path).unwrap();
        let norm = normalize(&shader, &Default::default()).unwrap();
        let table = enumerate(&shader, &norm);
        let entry = shader.fragment_entry(None).unwrap();
        let reference = renderer
            .render_original(&shader, entry, &session, &opts(2))
            .unwrap();
        let nodes: Vec<_> = table.cacheable().collect();
        // Two threads, each with its own device: most of the time goes to compiling pipelines.
        std::thread::scope(|scope| {
            for half in nodes.chunks(nodes.len().div_ceil(2)) {
                let (shader, norm, table, reference, session, path) =
                    (&shader, &norm, &table, &reference, &session, &path);
                scope.spawn(move || {
                    let renderer = Renderer::new(&RendererOptions::default()).unwrap();
                    for node in half {
                        let sel = if node.root {
                            NodeSelector::Root
                        } else {
                            NodeSelector::Id(node.id)
                        };
                        let v = instance(shader, norm, table, sel, &InstanceOptions::default())
                            .unwrap();
                        let input = VariantInput::new(
                            v.passes.iter().map(|p| p.wgsl.clone()).collect(),
                            v.manifest.clone(),
                            1,
                        );
                        let report = renderer
                            .render_variant(shader, session, &input, reference, &opts(2))
                            .unwrap_or_else(|e| panic!("{} node {}: {e}", path.display(), node.id));
                        for f in &report.frames {
                            assert!(
                                f.max_abs_diff <= 1e-4,
                                "{} node {} `{}`: frame {} differs by {} at Δn = 1",
                                path.display(),
                                node.id,
                                node.text,
                                f.frame,
                                f.max_abs_diff
                            );
                            assert_eq!(f.hits, 0, "Δn = 1 refreshes every pixel");
                        }
                    }
                });
            }
        });
        checked += nodes.len();
    }
    assert!(checked > 100, "{checked}");
}

#[test]
fn static_scene_reuses_the_cache_exactly() {
    let renderer =
        Renderer::new(&RendererOptions::default()).expect("a Vulkan adapter (lavapipe in CI)");
    let session = Session::load(root().join("sessions/test_static.json")).unwrap();
    for name in ["marble.wgsl", "ambient_occlusion.wgsl", "envmap.wgsl"] {
        let shader = load_file(&root().join("shaders").join(name)).unwrap();
        let norm = normalize(&shader, &Default::default()).unwrap();
        let table = enumerate(&shader, &norm);
        let reference = renderer
            .render_original(
                &shader,
                shader.fragment_entry(None).unwrap(),
                &session,
                &opts(8),
            )
            .unwrap();
        // The root and the most expensive cacheable node that is not the root.
        let inner = table
            .cacheable()
            .filter(|n| !n.root)
            .max_by(|a, b| (a.cost - a.overlap).total_cmp(&(b.cost - b.overlap)))
            .unwrap();
        for sel in [NodeSelector::Root, NodeSelector::Id(inner.id)] {
            let v = instance(&shader, &norm, &table, sel, &InstanceOptions::default()).unwrap();
            let input = VariantInput::new(
                v.passes.iter().map(|p| p.wgsl.clone()).collect(),
                v.manifest.clone(),
                8,
            );
            let report = renderer
                .render_variant(&shader, &session, &input, &reference, &opts(8))
                .unwrap();
            for f in report.frames.iter().skip(1) {
                assert!(
                    f.error < 1e-4,
                    "{name} {sel:?}: frame {} error {}",
                    f.frame,
                    f.error
                );
                assert!(
                    (f.hit_rate - (1.0 - 1.0 / 8.0)).abs() < 0.05,
                    "{name} {sel:?}: frame {} hit rate {}",
                    f.frame,
                    f.hit_rate
                );
            }
        }
    }
}

#[test]
fn half_float_cache_works_and_stays_close() {
    let renderer =
        Renderer::new(&RendererOptions::default()).expect("a Vulkan adapter (lavapipe in CI)");
    let session = Session::load(root().join("sessions/test_static.json")).unwrap();
    let shader = load_file(&root().join("shaders/marble.wgsl")).unwrap();
    let norm = normalize(&shader, &Default::default()).unwrap();
    let table = enumerate(&shader, &norm);
    let reference = renderer
        .render_original(
            &shader,
            shader.fragment_entry(None).unwrap(),
            &session,
            &opts(8),
        )
        .unwrap();
    let options = InstanceOptions {
        cache_format: reproj_instance::CacheFormatChoice::Exact(
            reproj_instance::CacheFormat::Rgba16float,
        ),
        ..InstanceOptions::default()
    };
    let v = instance(&shader, &norm, &table, NodeSelector::Root, &options).unwrap();
    assert!(
        v.manifest.required_features.is_empty(),
        "rgba16float is filterable everywhere"
    );
    for dn in [1, 8] {
        let input = VariantInput::new(
            v.passes.iter().map(|p| p.wgsl.clone()).collect(),
            v.manifest.clone(),
            dn,
        );
        let report = renderer
            .render_variant(&shader, &session, &input, &reference, &opts(8))
            .unwrap();
        for f in &report.frames {
            // 16-bit floats carry about 3 decimal digits (an ulp near 1.0 is 0.001), and lavapipe
            // filters them with a few ulps of error: a handful of ulps at worst, far less on average.
            assert!(
                f.max_abs_diff < 5e-3,
                "Δn = {dn}, frame {}: max {}",
                f.frame,
                f.max_abs_diff
            );
            assert!(
                f.error < 5e-4,
                "Δn = {dn}, frame {}: mean {}",
                f.frame,
                f.error
            );
        }
    }
}

/// A node inside a uniform branch is cacheable: the recompute slice returns it from inside the
/// branch (and zero on the other path), the shade pass reads it where the branch uses it.
#[test]
fn node_inside_a_uniform_branch_round_trips() {
    let src = "
struct Scene { camera_pos: vec3<f32>, time: f32, light_pos: vec3<f32> };
@group(0) @binding(0) var<uniform> scene: Scene;
@fragment
fn fs_main(@location(0) p: vec3<f32>, @location(1) n: vec3<f32>) -> @location(0) vec4<f32> {
    var c = vec3<f32>(0.1);
    if scene.time >= 0.0 {
        c = abs(cos(p * 7.0)) * max(dot(normalize(n), normalize(scene.light_pos - p)), 0.0);
    }
    return vec4<f32>(c, 1.0);
}";
    let shader =
        reproj_front::parse_shader(std::path::Path::new("uniform_branch.wgsl"), src.into())
            .unwrap();
    let norm = normalize(&shader, &Default::default()).unwrap();
    let table = enumerate(&shader, &norm);
    let node = table
        .cacheable()
        .find(|n| n.text == "abs(cos(p * 7.0))")
        .expect("the node inside the uniform branch is cacheable");
    let renderer =
        Renderer::new(&RendererOptions::default()).expect("a Vulkan adapter (lavapipe in CI)");
    let session = Session::load(root().join("sessions/test_static.json")).unwrap();
    let reference = renderer
        .render_original(&shader, 0, &session, &opts(8))
        .unwrap();
    let v = instance(
        &shader,
        &norm,
        &table,
        NodeSelector::Id(node.id),
        &InstanceOptions::default(),
    )
    .unwrap();
    for dn in [1, 8] {
        let input = VariantInput::new(
            v.passes.iter().map(|p| p.wgsl.clone()).collect(),
            v.manifest.clone(),
            dn,
        );
        let report = renderer
            .render_variant(&shader, &session, &input, &reference, &opts(8))
            .unwrap();
        for f in &report.frames {
            assert!(
                f.max_abs_diff <= 1e-4,
                "Δn = {dn}, frame {}: {}",
                f.frame,
                f.max_abs_diff
            );
        }
        if dn == 8 {
            assert!(report.hit_rate > 0.8, "{}", report.hit_rate);
        }
    }
}

/// The nodes of a sample the strategy tests cover: the root and the three most expensive
/// cacheable nodes that are not the root (every node is covered for the 3pass strategy above;
/// the strategies share the node slice, so these catch what differs between them).
fn strategy_nodes(table: &reproj_front::NodeTable) -> Vec<NodeSelector> {
    let mut inner: Vec<_> = table.cacheable().filter(|n| !n.root).collect();
    inner.sort_by(|a, b| (b.cost - b.overlap).total_cmp(&(a.cost - a.overlap)));
    let mut sels = vec![NodeSelector::Root];
    sels.extend(inner.iter().take(3).map(|n| NodeSelector::Id(n.id)));
    sels
}

/// Every strategy, cache format family, reconstruction and place of the depth (its own copy, or a
/// spare payload channel) reproduces the original at Δn = 1, and reuses its cache exactly (error < 1e-4, hit rate about 7/8) in a static scene at Δn = 8.
#[test]
fn every_strategy_reproduces_the_original_and_reuses_its_cache() {
    use reproj_instance::{CacheFormatChoice, Reconstruct, Strategy};
    let session = Session::load(root().join("sessions/test_static.json")).unwrap();
    let variants = [
        (
            Strategy::TwoPass,
            CacheFormatChoice::Narrowest32,
            Reconstruct::Bilinear,
        ),
        (
            Strategy::Fused,
            CacheFormatChoice::Narrowest32,
            Reconstruct::Bilinear,
        ),
        (
            Strategy::Fused,
            CacheFormatChoice::Narrowest32,
            Reconstruct::Nearest,
        ),
        (
            Strategy::TwoPass,
            CacheFormatChoice::Narrowest16,
            Reconstruct::Nearest,
        ),
        (
            Strategy::ThreePass,
            CacheFormatChoice::Narrowest16,
            Reconstruct::Nearest,
        ),
        (
            Strategy::ThreePass,
            CacheFormatChoice::Narrowest32,
            Reconstruct::CatmullRom,
        ),
        // The depth in the payload's spare channel with the sharper filter (the rows above with
        // `f32` and a filter pack it too, where the node leaves a channel free).
        (
            Strategy::TwoPass,
            CacheFormatChoice::Exact(reproj_instance::CacheFormat::Rgba32float),
            Reconstruct::CatmullRom,
        ),
    ];
    let shaders = samples();
    // Two threads, each with its own device: most of the time goes to compiling pipelines.
    std::thread::scope(|scope| {
        for half in shaders.chunks(shaders.len().div_ceil(2)) {
            let session = &session;
            let variants = &variants;
            scope.spawn(move || {
                let renderer = Renderer::new(&RendererOptions::default())
                    .expect("a Vulkan adapter (lavapipe in CI)");
                for path in half {
                    let shader = load_file(path).unwrap();
                    let norm = normalize(&shader, &Default::default()).unwrap();
                    let table = enumerate(&shader, &norm);
                    let entry = shader.fragment_entry(None).unwrap();
                    let reference = renderer
                        .render_original(&shader, entry, session, &opts(8))
                        .unwrap();
                    for sel in strategy_nodes(&table) {
                        for &(strategy, cache_format, reconstruct) in variants {
                            let options = InstanceOptions {
                                strategy,
                                cache_format,
                                reconstruct,
                                block: strategy.default_block(),
                                ..InstanceOptions::default()
                            };
                            let v = instance(&shader, &norm, &table, sel, &options).unwrap();
                            let what = format!(
                                "{} {sel:?} {strategy} {cache_format:?} {reconstruct:?}",
                                path.display()
                            );
                            let half = matches!(cache_format, CacheFormatChoice::Narrowest16);
                            for dn in [1, 8] {
                                let input = VariantInput::new(
                                    v.passes.iter().map(|p| p.wgsl.clone()).collect(),
                                    v.manifest.clone(),
                                    dn,
                                );
                                let frames = if dn == 1 { 2 } else { 8 };
                                let report = renderer
                                    .render_variant(
                                        &shader,
                                        session,
                                        &input,
                                        &reference,
                                        &opts(frames),
                                    )
                                    .unwrap_or_else(|e| panic!("{what}: {e}"));
                                for f in &report.frames {
                                    if dn == 1 {
                                        // At a refresh 3pass shades from the cache texture it just
                                        // wrote (rounded to half floats); the others compute inline.
                                        let bound = if half && strategy == Strategy::ThreePass {
                                            5e-3
                                        } else {
                                            1e-4
                                        };
                                        assert!(
                                            f.max_abs_diff <= bound,
                                            "{what}: frame {} differs by {} at Δn = 1",
                                            f.frame,
                                            f.max_abs_diff
                                        );
                                        assert_eq!(
                                            f.hits, 0,
                                            "{what}: Δn = 1 refreshes every pixel"
                                        );
                                    } else if f.frame > 0 {
                                        // Half floats round the cached value (an ulp near 1 is 0.001).
                                        let bound = if half { 5e-4 } else { 1e-4 };
                                        assert!(
                                            f.error < bound,
                                            "{what}: frame {} error {} at Δn = 8",
                                            f.frame,
                                            f.error
                                        );
                                        // 64 blocks of 8×8 at 64²: a frame's share of
                                        // refreshed blocks scatters around 1/8; a whole period
                                        // refreshes each block once (checked below).
                                        assert!(
                                            (f.hit_rate - 7.0 / 8.0).abs() < 0.15,
                                            "{what}: frame {} hit rate {}",
                                            f.frame,
                                            f.hit_rate
                                        );
                                    }
                                }
                                if dn == 8 {
                                    // Over frames 1..=7 every block refreshes once except those
                                    // that refreshed at frame 0: the mean stays within a few
                                    // thousandths of 7/8 even with 64 blocks.
                                    let after0 = &report.frames[1..];
                                    let mean = after0.iter().map(|f| f.hit_rate).sum::<f64>()
                                        / after0.len() as f64;
                                    assert!(
                                        (mean - 7.0 / 8.0).abs() < 0.03,
                                        "{what}: mean hit rate over frames 1.. {mean}"
                                    );
                                }
                            }
                        }
                    }
                }
            });
        }
    });
}

/// An unrolled shader renders as the original: at Δn = 1 the variants of the unrolled ambient
/// occlusion shader (its root and per-iteration partial sums, nodes only unrolling makes) match
/// the original shader's frames.
#[test]
fn unrolled_shader_reproduces_the_original_at_delta_n_1() {
    let renderer =
        Renderer::new(&RendererOptions::default()).expect("a Vulkan adapter (lavapipe in CI)");
    let session = Session::load(root().join("sessions/test_static.json")).unwrap();
    let shader = load_file(&root().join("shaders/ambient_occlusion.wgsl")).unwrap();
    let norm = normalize(
        &shader,
        &reproj_front::NormalizeOptions {
            entry: None,
            unroll: reproj_front::UnrollOptions { max_trip: 32 },
        },
    )
    .unwrap();
    let table = enumerate(&shader, &norm);
    let rolled = enumerate(&shader, &normalize(&shader, &Default::default()).unwrap());
    assert!(table.cacheable().count() > rolled.cacheable().count() * 4);
    let entry = shader.fragment_entry(None).unwrap();
    // The reference is the original, loops and all.
    let reference = renderer
        .render_original(&shader, entry, &session, &opts(2))
        .unwrap();
    let cacheable: Vec<_> = table.cacheable().collect();
    let picks = [
        0,
        cacheable.len() / 3,
        2 * cacheable.len() / 3,
        cacheable.len() - 1,
    ];
    let mut selectors: Vec<NodeSelector> = picks
        .iter()
        .map(|&i| NodeSelector::Id(cacheable[i].id))
        .collect();
    selectors.push(NodeSelector::Root);
    for sel in selectors {
        let v = instance(&shader, &norm, &table, sel, &InstanceOptions::default()).unwrap();
        let input = VariantInput::new(
            v.passes.iter().map(|p| p.wgsl.clone()).collect(),
            v.manifest.clone(),
            1,
        );
        let report = renderer
            .render_variant(&shader, &session, &input, &reference, &opts(2))
            .unwrap_or_else(|e| panic!("node {sel:?}: {e}"));
        for f in &report.frames {
            assert!(
                f.max_abs_diff <= 1e-4,
                "unrolled node {sel:?}: frame {} differs by {} at Δn = 1",
                f.frame,
                f.max_abs_diff
            );
            assert_eq!(f.hits, 0, "Δn = 1 refreshes every pixel");
        }
    }
}

/// A variant caching two nodes together (packed in one payload) reproduces the original at
/// Δn = 1 in the three-pass, two-pass and fused strategies, and reuses its cache when nothing
/// moves.
#[test]
fn two_node_variant_reproduces_the_original_at_delta_n_1() {
    use reproj_instance::{Strategy, instance_nodes};
    let renderer =
        Renderer::new(&RendererOptions::default()).expect("a Vulkan adapter (lavapipe in CI)");
    let session = Session::load(root().join("sessions/test_static.json")).unwrap();
    for name in ["ambient_occlusion", "envmap"] {
        let shader = load_file(&root().join(format!("shaders/{name}.wgsl"))).unwrap();
        let norm = normalize(&shader, &Default::default()).unwrap();
        let table = enumerate(&shader, &norm);
        let entry = shader.fragment_entry(None).unwrap();
        let reference = renderer
            .render_original(&shader, entry, &session, &opts(3))
            .unwrap();
        // The two costliest non-root nodes whose floats fit in one payload together.
        let mut nodes: Vec<_> = table.cacheable().filter(|n| !n.root).collect();
        nodes.sort_by(|a, b| b.cost.total_cmp(&a.cost));
        let first = nodes[0];
        let second = nodes[1..]
            .iter()
            .find(|n| n.components + first.components <= 4)
            .expect("a second node that fits");
        let pair = [NodeSelector::Id(first.id), NodeSelector::Id(second.id)];
        for strategy in [Strategy::ThreePass, Strategy::TwoPass, Strategy::Fused] {
            let what = format!("{name} nodes {} + {} {strategy:?}", first.id, second.id);
            let options = InstanceOptions {
                strategy,
                ..Default::default()
            };
            let v = instance_nodes(&shader, &norm, &table, &pair, &options)
                .unwrap_or_else(|e| panic!("{what}: {e}"));
            assert_eq!(v.manifest.also.len(), 1);
            assert_eq!(v.manifest.also[0].offset, first.components);
            for delta_n in [1, 8] {
                let input = VariantInput::new(
                    v.passes.iter().map(|p| p.wgsl.clone()).collect(),
                    v.manifest.clone(),
                    delta_n,
                );
                let report = renderer
                    .render_variant(&shader, &session, &input, &reference, &opts(3))
                    .unwrap_or_else(|e| panic!("{what}: {e}"));
                for f in &report.frames {
                    if delta_n == 1 {
                        assert!(
                            f.max_abs_diff <= 1e-4,
                            "{what}: frame {} differs by {} at Δn = 1",
                            f.frame,
                            f.max_abs_diff
                        );
                        assert_eq!(f.hits, 0, "{what}: Δn = 1 refreshes every pixel");
                    } else if f.frame > 0 {
                        // Nothing moves: the reused payload is the one computed, exactly.
                        assert!(f.hits > 0, "{what}: no hits at Δn = 8");
                        assert!(
                            f.error < 1e-4,
                            "{what}: frame {} error {} reusing the cache",
                            f.frame,
                            f.error
                        );
                    }
                }
            }
        }
    }
}

/// Passes that write the same targets share one render pass by default, as a host draws them
/// (`2pass`'s two, `3pass`'s first two): the frames are exactly those of one render pass per
/// pass (`VariantInput::pass_times`), with the same hit and miss counts; only the separate
/// render passes time each pass.
#[test]
fn one_render_pass_for_passes_sharing_their_targets_renders_the_same_frames() {
    use reproj_instance::Strategy;
    let renderer =
        Renderer::new(&RendererOptions::default()).expect("a Vulkan adapter (lavapipe in CI)");
    let session = Session::load(root().join("sessions/marble.json")).unwrap();
    let shader = load_file(&root().join("shaders/marble.wgsl")).unwrap();
    let norm = normalize(&shader, &Default::default()).unwrap();
    let table = enumerate(&shader, &norm);
    let entry = shader.fragment_entry(None).unwrap();
    let reference = renderer
        .render_original(&shader, entry, &session, &opts(12))
        .unwrap();
    let node = table.cacheable().find(|n| n.text == "s3 + n4").unwrap().id;
    for strategy in [Strategy::ThreePass, Strategy::TwoPass] {
        let options = InstanceOptions {
            strategy,
            block: strategy.default_block(),
            delta_n: 4,
            ..InstanceOptions::default()
        };
        let v = instance(&shader, &norm, &table, NodeSelector::Id(node), &options).unwrap();
        let input = VariantInput::new(
            v.passes.iter().map(|p| p.wgsl.clone()).collect(),
            v.manifest.clone(),
            4,
        );
        let mut o = opts(12);
        o.raw_frames = false;
        let shared = renderer
            .render_variant(&shader, &session, &input, &reference, &o)
            .unwrap();
        let separate = renderer
            .render_variant(
                &shader,
                &session,
                &VariantInput {
                    pass_times: true,
                    ..input.clone()
                },
                &reference,
                &o,
            )
            .unwrap();
        assert!(shared.hit_rate > 0.5, "{strategy}: {}", shared.hit_rate);
        for (a, b) in shared.frames.iter().zip(&separate.frames) {
            assert_eq!(a.error, b.error, "{strategy} frame {}", a.frame);
            assert_eq!(
                a.max_abs_diff, b.max_abs_diff,
                "{strategy} frame {}",
                a.frame
            );
            assert_eq!((a.hits, a.recomputes), (b.hits, b.recomputes), "{strategy}");
            assert!(
                a.pass_ms.is_empty(),
                "{strategy}: passes share a render pass"
            );
            if renderer.timing_method() == reproj_metrics::TimingMethod::GpuTimestamps {
                assert_eq!(b.pass_ms.len(), v.passes.len(), "{strategy}");
            }
        }
    }
}
