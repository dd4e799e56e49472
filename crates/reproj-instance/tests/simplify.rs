//! Code simplification's rewrite: nodes replaced by constants, every module valid and a WGSL
//! fixed point; the probe returns the node's value.

use std::path::PathBuf;

use reproj_front::{LoadOptions, Loaded, load};
use reproj_instance::{InstanceError, Replacement, SimplifyOptions, probe, simplify};

fn fixture() -> Loaded {
    let p = PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../reproj-compare/tests/data/flat_and_stripes.wgsl");
    load(&p, None, &LoadOptions::default()).unwrap()
}

fn node(l: &Loaded, text: &str) -> u32 {
    l.table
        .cacheable()
        .find(|n| n.text == text)
        .unwrap_or_else(|| {
            let all: Vec<_> = l.table.cacheable().map(|n| n.text.clone()).collect();
            panic!("no node `{text}` among {all:?}")
        })
        .id
}

fn round_trips(wgsl: &str) {
    let m = naga::front::wgsl::parse_str(wgsl).unwrap();
    let info = reproj_front::validator().validate(&m).unwrap();
    assert_eq!(reproj_instance::write_wgsl(&m, &info).unwrap(), wgsl);
}

#[test]
fn a_replaced_node_becomes_its_constant_and_its_subtree_goes() {
    let l = fixture();
    let stripes = node(&l, "0.5 + 0.5 * sin(in.world_pos.x * 40.0)");
    let s = simplify(
        &l.norm,
        &l.table,
        &SimplifyOptions {
            replace: vec![Replacement {
                node: stripes,
                value: [0.625, 9.0, 9.0, 9.0],
            }],
        },
    )
    .unwrap();
    round_trips(&s.wgsl);
    assert!(s.wgsl.contains("0.625f"), "{}", s.wgsl);
    assert!(!s.wgsl.contains("40f"), "the subtree is dead: {}", s.wgsl);
    assert!(
        !s.wgsl.contains("9f"),
        "only the node's one component: {}",
        s.wgsl
    );
    // Nothing replaced: the shader computes what it did.
    let same = simplify(&l.norm, &l.table, &SimplifyOptions::default()).unwrap();
    round_trips(&same.wgsl);
    assert!(same.wgsl.contains("40f"));
}

#[test]
fn vector_nodes_and_several_nodes_are_replaced_together() {
    let l = fixture();
    let tex = l
        .table
        .cacheable()
        .find(|n| n.components == 3 && n.text.starts_with("textureSample"))
        .expect("the texture sample is a vec3 node")
        .id;
    let stripes = node(&l, "0.5 + 0.5 * sin(in.world_pos.x * 40.0)");
    let s = simplify(
        &l.norm,
        &l.table,
        &SimplifyOptions {
            replace: vec![
                Replacement {
                    node: tex,
                    value: [0.25, 0.5, 0.75, 0.0],
                },
                Replacement {
                    node: stripes,
                    value: [0.125, 0.0, 0.0, 0.0],
                },
            ],
        },
    )
    .unwrap();
    round_trips(&s.wgsl);
    assert!(!s.wgsl.contains("textureSample"), "{}", s.wgsl);
    // naga folds the two constants into one: (0.25, 0.5, 0.75) × 0.125.
    assert!(
        s.wgsl.contains("vec3<f32>(0.03125f, 0.0625f, 0.09375f)"),
        "{}",
        s.wgsl
    );
}

#[test]
fn the_probe_returns_the_node_and_bad_nodes_are_refused() {
    let l = fixture();
    let stripes = node(&l, "0.5 + 0.5 * sin(in.world_pos.x * 40.0)");
    let p = probe(&l.norm, &l.table, stripes).unwrap();
    round_trips(&p.wgsl);
    assert!(
        p.wgsl.contains("40f") && !p.wgsl.contains("textureSample"),
        "{}",
        p.wgsl
    );
    let root = l.table.root().id;
    let max = l.table.nodes.last().unwrap().id;
    assert!(matches!(
        probe(&l.norm, &l.table, max + 10),
        Err(InstanceError::UnknownNode { .. })
    ));
    // The root (a vec4) can be probed; a culled node cannot.
    assert!(probe(&l.norm, &l.table, root).is_ok());
}
