//! Instancer invariants over every sample shader, snapshots of chosen variants, the contract
//! with the hosts, and bad input. What the passes hold is `passes.rs`; the other output languages
//! `languages.rs`; WGSL that naga rewrites on every trip `round_trips.rs`.

use std::path::Path;

use reproj_front::{enumerate, load_file, normalize};
use reproj_instance::{
    InstanceError, InstanceOptions, NodeSelector, PassKind, Strategy, instance, write_variant,
};

use crate::common::{check_round_trip, load, node_by_text, pass, root, samples};

/// Every cacheable node of every sample, in every strategy: each pass validates (inside
/// `instance`, before and after compaction) and its WGSL is a fixed point of parse → validate →
/// write. One thread a strategy (63 s on one core of two).
#[test]
fn every_cacheable_node_of_every_sample_instances() {
    let count: usize = std::thread::scope(|scope| {
        let threads: Vec<_> = Strategy::ALL
            .into_iter()
            .map(|strategy| scope.spawn(move || every_node_instances(strategy)))
            .collect();
        threads
            .into_iter()
            .map(|t| t.join().unwrap_or_else(|e| std::panic::resume_unwind(e)))
            .sum()
    });
    assert!(count > 300);
}

/// [`every_cacheable_node_of_every_sample_instances`] in one strategy: how many nodes.
fn every_node_instances(strategy: Strategy) -> usize {
    let mut count = 0;
    let opts = InstanceOptions {
        strategy,
        block: strategy.default_block(),
        ..Default::default()
    };
    let passes = match strategy {
        Strategy::ThreePass => 3,
        Strategy::TwoPass => 2,
        Strategy::Fused => 1,
    };
    for name in samples() {
        let (shader, norm, table) = load(&name);
        let ids: Vec<u32> = table.cacheable().map(|n| n.id).collect();
        assert!(!ids.is_empty());
        for id in ids {
            let v = instance(&shader, &norm, &table, NodeSelector::Id(id), &opts)
                .unwrap_or_else(|e| panic!("{name} node {id} ({strategy}): {e}"));
            assert_eq!(v.passes.len(), passes);
            assert_eq!(v.manifest.passes.len(), passes);
            assert_eq!(v.manifest.strategy, strategy);
            check_round_trip(&v);
            count += 1;
        }
        let v = instance(&shader, &norm, &table, NodeSelector::Root, &opts).unwrap();
        check_round_trip(&v);
    }
    count
}

/// The payload format is the narrowest that holds the node unless one is asked for, and a format
/// too narrow for the node is a clear error.
#[test]
fn cache_formats_fit_the_node() {
    use reproj_instance::{CacheFormat, CacheFormatChoice};
    let (shader, norm, table) = load("marble.wgsl");
    let scalar = NodeSelector::Id(node_by_text(&table, "s3 + n4"));
    let v = instance(&shader, &norm, &table, scalar, &Default::default()).unwrap();
    assert_eq!(v.manifest.cache_format, CacheFormat::R32float);
    let half = InstanceOptions {
        cache_format: CacheFormatChoice::Narrowest16,
        ..Default::default()
    };
    let v = instance(&shader, &norm, &table, NodeSelector::Root, &half).unwrap();
    assert_eq!(v.manifest.cache_format, CacheFormat::Rgba16float);
    assert!(v.manifest.required_features.is_empty());
    let narrow = InstanceOptions {
        cache_format: CacheFormatChoice::Exact(CacheFormat::Rg32float),
        ..Default::default()
    };
    let e = instance(&shader, &norm, &table, NodeSelector::Root, &narrow).unwrap_err();
    assert!(matches!(e, InstanceError::FormatTooNarrow { .. }), "{e}");
}

/// Nearest reconstruction reads the previous payload with `textureLoad` and needs no sampler for
/// it, so no `float32-filterable` feature either.
#[test]
fn nearest_reconstruction_needs_no_filtering() {
    let (shader, norm, table) = load("marble.wgsl");
    let opts = InstanceOptions {
        reconstruct: reproj_instance::Reconstruct::Nearest,
        ..Default::default()
    };
    let v = instance(&shader, &norm, &table, NodeSelector::Root, &opts).unwrap();
    let p1 = pass(&v, PassKind::Reproject);
    assert!(p1.contains("textureLoad(reproj_prev_payload"), "{p1}");
    assert!(!p1.contains("reproj_linear_sampler"), "{p1}");
    assert!(v.manifest.required_features.is_empty());
}

#[test]
fn output_is_deterministic() {
    for name in samples() {
        let (shader, norm, table) = load(&name);
        let id = table
            .cacheable()
            .nth(table.cacheable().count() / 2)
            .unwrap()
            .id;
        let a = instance(
            &shader,
            &norm,
            &table,
            NodeSelector::Id(id),
            &Default::default(),
        )
        .unwrap();
        let (shader, norm, table) = load(&name);
        let b = instance(
            &shader,
            &norm,
            &table,
            NodeSelector::Id(id),
            &Default::default(),
        )
        .unwrap();
        for (x, y) in a.passes.iter().zip(&b.passes) {
            assert_eq!(x.wgsl, y.wgsl);
        }
        assert_eq!(a.manifest, b.manifest);
    }
}

#[test]
fn snapshots_of_chosen_variants() {
    let picks: &[(&str, &str, Strategy)] = &[
        ("marble.wgsl", "s3 + n4", Strategy::ThreePass),
        ("marble.wgsl", "root", Strategy::ThreePass),
        ("ambient_occlusion.wgsl", "root", Strategy::ThreePass),
        ("marble.wgsl", "s3 + n4", Strategy::TwoPass),
        ("marble.wgsl", "s3 + n4", Strategy::Fused),
    ];
    for (name, text, strategy) in picks {
        let (shader, norm, table) = load(name);
        let sel = if *text == "root" {
            NodeSelector::Root
        } else {
            NodeSelector::Id(node_by_text(&table, text))
        };
        let opts = InstanceOptions {
            strategy: *strategy,
            block: strategy.default_block(),
            ..Default::default()
        };
        let v = instance(&shader, &norm, &table, sel, &opts).unwrap();
        let suffix = match strategy {
            Strategy::ThreePass => String::new(),
            s => format!("_{s}"),
        };
        let stem = format!(
            "{}_{}{suffix}",
            name.trim_end_matches(".wgsl"),
            text.replace(|c: char| !c.is_ascii_alphanumeric(), "_")
        );
        for p in &v.passes {
            insta::assert_snapshot!(format!("{stem}_{:?}", p.kind).to_lowercase(), p.wgsl);
        }
        insta::assert_json_snapshot!(format!("{stem}_manifest"), v.manifest);
    }
}

#[test]
fn bad_input_gives_clear_errors() {
    let (shader, norm, table) = load("marble.wgsl");
    let e = instance(
        &shader,
        &norm,
        &table,
        NodeSelector::Id(99_999),
        &Default::default(),
    )
    .unwrap_err();
    assert!(matches!(e, InstanceError::UnknownNode { .. }), "{e}");
    let culled = table
        .nodes
        .iter()
        .find(|n| !n.cacheable)
        .map(|n| n.id)
        .expect("marble has culled nodes");
    let e = instance(
        &shader,
        &norm,
        &table,
        NodeSelector::Id(culled),
        &Default::default(),
    )
    .unwrap_err();
    assert!(e.to_string().contains("culled as"), "{e}");

    let full = "
        @group(0) @binding(0) var<uniform> a: vec4<f32>;
        @group(1) @binding(0) var<uniform> b: vec4<f32>;
        @group(2) @binding(0) var<uniform> c: vec4<f32>;
        @group(3) @binding(0) var<uniform> d: vec4<f32>;
        @fragment fn fs(@location(0) p: vec3<f32>) -> @location(0) vec4<f32> { return sin(a + b + c + d) * p.x; }";
    let shader = reproj_front::parse_shader(Path::new("full.wgsl"), full.into()).unwrap();
    let norm = normalize(&shader, &Default::default()).unwrap();
    let table = enumerate(&shader, &norm);
    // Every group taken: the variant's bindings join the highest, past the shader's own.
    let v = instance(
        &shader,
        &norm,
        &table,
        NodeSelector::Root,
        &Default::default(),
    )
    .unwrap();
    assert_eq!((v.manifest.group, v.manifest.binding_base), (3, 1));
    let lines: Vec<&str> = v.passes[0].wgsl.lines().collect();
    let at = lines
        .iter()
        .position(|l| l.contains("reproj_params:"))
        .expect("pass 1 declares the params");
    assert!(
        lines[at - 1..=at]
            .concat()
            .contains("@group(3) @binding(1)"),
        "{}",
        lines[at - 1]
    );
    for b in &v.manifest.passes[0].bindings {
        assert_eq!(
            b.added,
            (b.group, b.binding) != (3, 0) && b.group == 3,
            "{b:?}"
        );
    }
}

#[test]
fn write_variant_into_unwritable_place_fails_cleanly() {
    let (shader, norm, table) = load("marble.wgsl");
    let v = instance(
        &shader,
        &norm,
        &table,
        NodeSelector::Root,
        &Default::default(),
    )
    .unwrap();
    let dir = tempfile::tempdir().unwrap();
    let file = dir.path().join("a_file");
    std::fs::write(&file, "x").unwrap();
    let e = write_variant(&v, &file.join("sub")).unwrap_err();
    assert!(matches!(e, InstanceError::Write(_)), "{e}");
    let out = dir.path().join("out");
    write_variant(&v, &out).unwrap();
    let mut names: Vec<String> = std::fs::read_dir(&out)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    names.sort();
    assert_eq!(
        names,
        [
            "manifest.json",
            "pass1_reproject.wgsl",
            "pass2_recompute.wgsl",
            "pass3_shade.wgsl"
        ]
    );
}

/// The GLSL twin of marble (`shaders/glsl/marble.frag`): its root and a spread of its cacheable
/// nodes instance in every strategy, every pass validates (inside `instance`) and survives a WGSL
/// round trip.
#[test]
fn glsl_marble_instances_in_every_strategy() {
    let shader = load_file(&root().join("shaders/glsl/marble.frag")).unwrap();
    let norm = normalize(&shader, &Default::default()).unwrap();
    let table = enumerate(&shader, &norm);
    let ids: Vec<u32> = table.cacheable().map(|n| n.id).collect();
    assert!(ids.len() > 300, "{}", ids.len());
    for strategy in Strategy::ALL {
        let opts = InstanceOptions {
            strategy,
            block: strategy.default_block(),
            ..Default::default()
        };
        for &id in ids.iter().step_by(37) {
            let v = instance(&shader, &norm, &table, NodeSelector::Id(id), &opts)
                .unwrap_or_else(|e| panic!("node {id} ({strategy}): {e}"));
            check_round_trip(&v);
        }
        let v = instance(&shader, &norm, &table, NodeSelector::Root, &opts).unwrap();
        check_round_trip(&v);
    }
}

/// The manifest's `params` layout (size, field names and offsets) is the contract's
/// `#[repr(C)]` `ReprojParams`, and its added bindings are the contract's, by name and number,
/// in every strategy.
#[test]
fn manifest_params_and_bindings_match_the_contract() {
    use reproj_instance::contract::{ADDED_BINDINGS, PARAMS_OFFSETS, PARAMS_SIZE, ReprojParams};
    let (shader, norm, table) = load("marble.wgsl");
    for strategy in Strategy::ALL {
        let opts = InstanceOptions {
            strategy,
            block: strategy.default_block(),
            ..Default::default()
        };
        let v = instance(&shader, &norm, &table, NodeSelector::Root, &opts).unwrap();
        let params = &v.manifest.params;
        assert_eq!(params.size, PARAMS_SIZE);
        assert_eq!(params.size as usize, std::mem::size_of::<ReprojParams>());
        let fields: Vec<(&str, u32)> = params
            .fields
            .iter()
            .map(|f| (f.name.as_str(), f.offset))
            .collect();
        assert_eq!(fields, PARAMS_OFFSETS.to_vec(), "{strategy:?}");
        for pass in &v.manifest.passes {
            for b in pass.bindings.iter().filter(|b| b.added) {
                assert!(
                    ADDED_BINDINGS.contains(&(b.name.as_str(), b.binding)),
                    "{strategy:?} {:?}: added binding {} at {} is not in the contract",
                    pass.kind,
                    b.name,
                    b.binding
                );
            }
        }
    }
}
