//! WGSL that naga rewrites on every round trip (the `enable f16;` directive, names its namer
//! changes, constants it folds one level at a time) still instances, and the passes are a fixed
//! point of parse → validate → write.

use std::path::PathBuf;

use reproj_front::{enumerate, load_file, normalize};
use reproj_instance::{InstanceOptions, NodeSelector, Strategy, instance};

use crate::common::{check_round_trip, root_in_every_strategy};

/// `enable f16;` survives the passes of every strategy: each pass of each cacheable node of a
/// shader computing in f16 parses and validates again (it failed to parse without the directive).
#[test]
fn f16_shaders_keep_their_enable_directive() {
    let path = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("tests/fixtures/f16.wgsl");
    let shader = load_file(&path).unwrap();
    let norm = normalize(&shader, &Default::default()).unwrap();
    let table = enumerate(&shader, &norm);
    let ids: Vec<u32> = table.cacheable().map(|n| n.id).collect();
    assert!(
        table.cacheable().any(|n| n.text == "f32(h.x * h.y + h.z)"),
        "{:#?}",
        table.nodes
    );
    for strategy in Strategy::ALL {
        let opts = InstanceOptions {
            strategy,
            block: strategy.default_block(),
            ..Default::default()
        };
        for &id in &ids {
            let v = instance(&shader, &norm, &table, NodeSelector::Id(id), &opts)
                .unwrap_or_else(|e| panic!("node {id} ({strategy}): {e}"));
            // The passes that compute in f16 say so (the others need not ask for the feature).
            assert!(
                v.passes.iter().any(|p| p.wgsl.contains("enable f16;\n")),
                "node {id} ({strategy}): no pass enables f16"
            );
            check_round_trip(&v);
        }
    }
}

/// Names naga's namer changes on every trip (`a`, `a` and `a_1` in one function after inlining:
/// `a_1` becomes `a_1_`, then the second `a` takes `a_1`, …) once made "the WGSL round trip does
/// not reach a fixed point": the passes are now a fixed point up to those renamings, and still
/// parse and validate.
#[test]
fn names_naga_renames_on_every_trip_still_instance() {
    let src = "
fn h(x: f32) -> f32 {
    let a = x * 3.0 + 0.25;
    return a;
}
@fragment fn fs_main(@location(0) p: vec3<f32>) -> @location(0) vec4<f32> {
    let a = sin(p.x * 5.0);
    let b = h(a);
    let a_1 = cos(b * 2.0) + a;
    return vec4<f32>(a_1, b, a, 1.0);
}
";
    for v in root_in_every_strategy("names.wgsl", src) {
        for p in &v.passes {
            let m = naga::front::wgsl::parse_str(&p.wgsl).unwrap();
            reproj_front::validator().validate(&m).unwrap();
        }
    }
}

/// A helper inlined with literal arguments leaves constants nested in its body (`(1 + w) * (1 +
/// w)` with `w = 0.3`), and naga folds one more level of them on each WGSL round trip: that once
/// made "the WGSL round trip does not reach a fixed point" (an internal error) on a real shader.
/// The passes now reach the fixed point after as many trips as the nesting needs.
#[test]
fn constants_folded_over_several_trips_still_instance() {
    let src = "
fn soften(d: f32, w: f32) -> f32 {
    return d / (((1.0 + w) * (1.0 + w)) * (2.0 - w));
}
@fragment fn fs_main(@location(0) p: vec3<f32>) -> @location(0) vec4<f32> {
    let d = soften(p.y, 0.3);
    return vec4<f32>(vec3<f32>(d * sin(p.x * 7.0)), 1.0);
}
";
    for v in root_in_every_strategy("nested.wgsl", src) {
        for p in &v.passes {
            // A fixed point: written again, the text does not change.
            let m = naga::front::wgsl::parse_str(&p.wgsl).unwrap();
            let info = reproj_front::validator().validate(&m).unwrap();
            assert_eq!(reproj_instance::write_wgsl(&m, &info).unwrap(), p.wgsl);
        }
    }
}
