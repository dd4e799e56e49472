//! What the passes hold: the shade pass no longer computes the cached node but keeps what the
//! rest of the shader shares with it, a loop's sum takes its loops out of pass 3, every pass that
//! writes the color writes the depth copy, and two nodes share one payload.

use std::path::Path;

use reproj_front::{enumerate, load_file, normalize};
use reproj_instance::{InstanceError, InstanceOptions, NodeSelector, PassKind, Strategy, instance};

use crate::common::{check_round_trip, load, node_by_text, pass, root};

#[test]
fn shade_pass_drops_the_cached_noise_and_keeps_the_overlap() {
    let (shader, norm, table) = load("marble.wgsl");
    // The whole turbulence sum: no noise left in pass 3, but `p` (also used by the vein stripes) is.
    let id = node_by_text(&table, "s3 + n4");
    let v = instance(
        &shader,
        &norm,
        &table,
        NodeSelector::Id(id),
        &Default::default(),
    )
    .unwrap();
    let shade = pass(&v, PassKind::Shade);
    assert!(shade.contains("textureLoad(reproj_cur_payload"));
    // Each octave hashes its 8 lattice corners with `sin`; only the vein stripes' `sin` is left.
    assert_eq!(
        shade.matches("sin(").count(),
        1,
        "noise still in pass 3:\n{shade}"
    );
    assert!(
        !shade.contains("floor("),
        "noise lattice still in pass 3:\n{shade}"
    );
    assert!(
        shade.contains("object_pos"),
        "the shared input was removed:\n{shade}"
    );
    let recompute = pass(&v, PassKind::Recompute);
    assert_eq!(
        recompute.matches("sin(").count(),
        5 * 8,
        "pass 2 computes the five octaves"
    );
    assert!(
        !recompute.contains("pow("),
        "pass 2 computes more than the node:\n{recompute}"
    );

    // An overlap node: `p` is shared between the noise and the stripes; caching the first octave
    // keeps `p` and the other four octaves in pass 3.
    let id = node_by_text(&table, "abs(gradient_noise(p))");
    let node = table.get(id).unwrap();
    assert!(node.overlap > 0.0);
    let v = instance(
        &shader,
        &norm,
        &table,
        NodeSelector::Id(id),
        &Default::default(),
    )
    .unwrap();
    assert_eq!(
        pass(&v, PassKind::Shade).matches("sin(").count(),
        4 * 8 + 1,
        "four of five octaves remain"
    );
}

#[test]
fn ambient_occlusion_post_loop_sum_removes_its_loops_from_pass_3() {
    let (shader, norm, table) = load("ambient_occlusion.wgsl");
    let original_loops = {
        let v = instance(
            &shader,
            &norm,
            &table,
            NodeSelector::Root,
            &Default::default(),
        )
        .unwrap();
        pass(&v, PassKind::Recompute).matches("loop {").count()
    };
    assert!(original_loops >= 3, "{original_loops}");
    let static_sum = table
        .cacheable()
        .find(|n| n.text.contains("static"))
        .expect("a cacheable node reading the static occluders' sum");
    let v = instance(
        &shader,
        &norm,
        &table,
        NodeSelector::Id(static_sum.id),
        &Default::default(),
    )
    .unwrap();
    let shade = pass(&v, PassKind::Shade);
    assert!(shade.matches("loop {").count() < original_loops, "{shade}");
}

/// Every pass that writes the frame color also writes the depth copy: `@builtin(position).z`, or
/// the shader's own `@builtin(frag_depth)` when it writes one. No pass declares a depth texture.
#[test]
fn color_passes_write_the_depth_copy() {
    let src = "
        struct Out {
            @location(0) color: vec4<f32>,
            @builtin(frag_depth) depth: f32,
        }
        @group(0) @binding(0) var<uniform> k: vec4<f32>;
        @fragment fn fs(@location(0) p: vec3<f32>, @builtin(position) pos: vec4<f32>) -> Out {
            let s = sin(p * k.xyz);
            return Out(vec4<f32>(s, 1.0), pos.z * 0.5);
        }";
    let shader = reproj_front::parse_shader(Path::new("depth.wgsl"), src.into()).unwrap();
    let norm = normalize(&shader, &Default::default()).unwrap();
    let table = enumerate(&shader, &norm);
    for strategy in Strategy::ALL {
        let v = instance(
            &shader,
            &norm,
            &table,
            NodeSelector::Root,
            &InstanceOptions {
                strategy,
                block: strategy.default_block(),
                ..Default::default()
            },
        )
        .unwrap();
        check_round_trip(&v);
        for (p, m) in v.passes.iter().zip(&v.manifest.passes) {
            assert!(!p.wgsl.contains("texture_depth"), "{:?}", p.kind);
            let writes_color = m.colors.iter().any(|c| c.attachment == "frame");
            let copy = m
                .colors
                .iter()
                .find(|c| c.attachment == reproj_instance::ROLE_CUR_DEPTH_COPY);
            assert_eq!(writes_color, copy.is_some(), "{strategy} {:?}", p.kind);
            if writes_color {
                assert!(p.wgsl.contains("reproj_depth: f32"), "{}", p.wgsl);
                // The shader's own depth, not the rasterized one, ends the output.
                let ret = p
                    .wgsl
                    .lines()
                    .find(|l| l.contains("return ReprojOutput("))
                    .unwrap();
                assert!(ret.trim_end().ends_with(".depth);"), "{ret}");
            }
        }
    }
}

/// Where the layout writes the cache and the frame in the same entries (two-pass, fused) and the
/// 32-bit filtered payload has a channel to spare, the depth goes there: the payload widens by one
/// channel (`f32`) or uses the spare one (an exact format), the cache clears to the far plane in
/// that channel, no pass writes or reads a depth copy, and the lookup reads depth and payload in
/// one filtered fetch. The three-pass layout, 16-bit payloads, nearest reconstruction and a full
/// `r32float` keep the depth copy.
#[test]
fn the_depth_rides_in_a_spare_payload_channel() {
    use reproj_instance::{CacheFormat, CacheFormatChoice, Reconstruct};
    let (shader, norm, table) = load("marble.wgsl");
    let id = node_by_text(&table, "s3 + n4");
    let make = |strategy: Strategy, cache_format, reconstruct| {
        let v = instance(
            &shader,
            &norm,
            &table,
            NodeSelector::Id(id),
            &InstanceOptions {
                strategy,
                cache_format,
                reconstruct,
                block: strategy.default_block(),
                ..Default::default()
            },
        )
        .unwrap();
        check_round_trip(&v);
        v
    };
    let f32s = CacheFormatChoice::Narrowest32;
    for strategy in [Strategy::TwoPass, Strategy::Fused] {
        for (choice, format, channel) in [
            (f32s, CacheFormat::Rg32float, 1),
            (
                CacheFormatChoice::Exact(CacheFormat::Rgba32float),
                CacheFormat::Rgba32float,
                1,
            ),
        ] {
            for reconstruct in [Reconstruct::Bilinear, Reconstruct::CatmullRom] {
                let v = make(strategy, choice, reconstruct);
                let m = &v.manifest;
                let what = format!("{strategy} {choice:?} {reconstruct:?}");
                assert_eq!(m.depth_channel, Some(channel), "{what}");
                assert_eq!(m.cache_format, format, "{what}");
                assert!(
                    !m.textures.iter().any(|t| t.name.starts_with("depth_copy")),
                    "{what}"
                );
                for (p, mp) in v.passes.iter().zip(&m.passes) {
                    assert!(!p.wgsl.contains("reproj_prev_depth"), "{what}: {}", p.wgsl);
                    assert!(!p.wgsl.contains("reproj_depth"), "{what}: {}", p.wgsl);
                    assert!(
                        mp.colors
                            .iter()
                            .all(|c| c.attachment != reproj_instance::ROLE_CUR_DEPTH_COPY),
                        "{what}"
                    );
                    let cache = mp
                        .colors
                        .iter()
                        .find(|c| c.attachment == reproj_instance::ROLE_CUR_PAYLOAD)
                        .unwrap();
                    if let reproj_instance::LoadOp::Clear { value: Some(v) } = &cache.load {
                        assert_eq!(v, &[0.0, 1.0, 0.0, 0.0], "{what}");
                    }
                    // The cache written carries the fragment's depth in its channel 1.
                    let ret = p
                        .wgsl
                        .lines()
                        .find(|l| l.contains("return ReprojOutput("))
                        .unwrap();
                    assert!(ret.contains(".x, reproj_frag_coord.z, "), "{what}: {ret}");
                }
                let first = &v.passes[0].wgsl;
                assert!(first.contains("reproj_texel.y"), "{what}: {first}");
            }
        }
    }
    // The depth copy stays where the payload has no spare filtered 32-bit channel, or the layout
    // writes the cache and the frame in different passes.
    for (strategy, choice, reconstruct) in [
        (Strategy::ThreePass, f32s, Reconstruct::Bilinear),
        (
            Strategy::TwoPass,
            CacheFormatChoice::Exact(CacheFormat::R32float),
            Reconstruct::Bilinear,
        ),
        (
            Strategy::TwoPass,
            CacheFormatChoice::Narrowest16,
            Reconstruct::Bilinear,
        ),
        (Strategy::Fused, f32s, Reconstruct::Nearest),
    ] {
        let v = make(strategy, choice, reconstruct);
        let what = format!("{strategy} {choice:?} {reconstruct:?}");
        assert_eq!(v.manifest.depth_channel, None, "{what}");
        assert!(
            v.manifest
                .textures
                .iter()
                .any(|t| t.name.starts_with("depth_copy")),
            "{what}"
        );
        let first = &v.passes[0].wgsl;
        assert!(first.contains("reproj_prev_depth"), "{what}");
    }
}

/// Two nodes cached together: their floats packed one after the other (the manifest says where),
/// the recompute pass returns both, the shade pass reads both from the payload and no longer
/// computes either; more than four floats, or a node twice, is refused.
#[test]
fn two_nodes_share_one_payload() {
    use reproj_instance::instance_nodes;
    let (shader, norm, table) = load("ambient_occlusion.wgsl");
    let (s, m) = (
        node_by_text(&table, "static_ao"),
        node_by_text(&table, "moving_ao"),
    );
    let pair = [NodeSelector::Id(s), NodeSelector::Id(m)];
    for strategy in Strategy::ALL {
        let opts = InstanceOptions {
            strategy,
            block: strategy.default_block(),
            ..Default::default()
        };
        let v = instance_nodes(&shader, &norm, &table, &pair, &opts).unwrap();
        check_round_trip(&v);
        let manifest = &v.manifest;
        assert_eq!(manifest.node.id, s.to_string());
        assert_eq!((manifest.node.offset, manifest.also.len()), (0, 1));
        assert_eq!(manifest.also[0].id, m.to_string());
        assert_eq!(manifest.also[0].offset, 1);
        // Two floats; where the layout packs the depth, a third channel holds it.
        let packs = strategy != Strategy::ThreePass;
        assert_eq!(manifest.cache_format.channels(), if packs { 4 } else { 2 });
        assert_eq!(manifest.depth_channel, packs.then_some(2));
        if strategy == Strategy::ThreePass {
            // Pass 3 reads both from the cache: neither loop is left.
            assert!(!pass(&v, PassKind::Shade).contains("loop"));
            assert!(pass(&v, PassKind::Recompute).contains("loop"));
        }
    }
    let (_, envmap_norm, envmap_table) = load("envmap.wgsl");
    let vec3s: Vec<u32> = envmap_table
        .cacheable()
        .filter(|n| n.components == 3 && !n.root)
        .map(|n| n.id)
        .take(2)
        .collect();
    let envmap = load_file(&root().join("shaders/envmap.wgsl")).unwrap();
    let wide = [NodeSelector::Id(vec3s[0]), NodeSelector::Id(vec3s[1])];
    let e = instance_nodes(
        &envmap,
        &envmap_norm,
        &envmap_table,
        &wide,
        &InstanceOptions::default(),
    )
    .unwrap_err();
    assert!(
        matches!(e, InstanceError::PayloadTooWide { components: 6, .. }),
        "{e}"
    );
    let twice = [NodeSelector::Id(s), NodeSelector::Id(s)];
    let e =
        instance_nodes(&shader, &norm, &table, &twice, &InstanceOptions::default()).unwrap_err();
    assert!(matches!(e, InstanceError::RepeatedNode { .. }), "{e}");
}
