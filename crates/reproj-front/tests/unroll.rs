//! Loop unrolling: what is unrolled, what is left alone, the node counts it gives, and a snapshot of
//! an unrolled fixture.
//!
//! After an intended change: `INSTA_UPDATE=always cargo test -p reproj-front --test integration
//! unroll::` (or `cargo insta review`) and review the diff of `tests/snapshots/`.

use std::path::Path;

use reproj_front::{
    LoadOptions, NodeTable, NormalizeOptions, Normalized, UnrollOptions, enumerate, load,
    normalize, parse_shader,
};

fn repo(path: &str) -> std::path::PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../..")
        .join(path)
}

fn normalized(src: &str, max_trip: u32) -> (Normalized, NodeTable) {
    let shader = parse_shader(Path::new("fixture.wgsl"), src.to_owned()).unwrap();
    let norm = normalize(
        &shader,
        &NormalizeOptions {
            entry: None,
            unroll: UnrollOptions { max_trip },
        },
    )
    .unwrap_or_else(|e| panic!("{e}"));
    let table = enumerate(&shader, &norm);
    (norm, table)
}

fn loops(block: &naga::Block) -> usize {
    block
        .iter()
        .map(|s| match s {
            naga::Statement::Loop {
                body, continuing, ..
            } => 1 + loops(body) + loops(continuing),
            naga::Statement::Block(b) => loops(b),
            naga::Statement::If { accept, reject, .. } => loops(accept) + loops(reject),
            _ => 0,
        })
        .sum()
}

fn loop_count(norm: &Normalized) -> usize {
    loops(&norm.function().body)
}

fn wgsl(norm: &Normalized) -> String {
    naga::back::wgsl::write_string(
        &norm.module,
        &norm.info,
        naga::back::wgsl::WriterFlags::empty(),
    )
    .unwrap()
}

fn wrap(body: &str) -> String {
    format!(
        "@group(0) @binding(0) var<uniform> n: u32;
        @fragment fn fs_main(@location(0) p: vec3<f32>) -> @location(0) vec4<f32> {{
            var acc = 0.0;
            {body}
            return vec4<f32>(vec3<f32>(acc), 1.0);
        }}"
    )
}

#[test]
fn nested_loops_unroll_into_nodes_and_match_the_snapshot() {
    let src = std::fs::read_to_string(repo("crates/reproj-front/tests/fixtures/nested_loops.wgsl"))
        .unwrap();
    let (rolled, before) = normalized(&src, 0);
    let (unrolled, after) = normalized(&src, 32);
    assert_eq!(loop_count(&rolled), 3);
    assert_eq!(loop_count(&unrolled), 0, "{}", wgsl(&unrolled));
    // 3 × 2 + 2 partial sums, each now a cacheable node.
    assert!(
        after.cacheable().count() >= before.cacheable().count() + 8,
        "{} cacheable before, {} after",
        before.cacheable().count(),
        after.cacheable().count()
    );
    assert!(
        after
            .nodes
            .iter()
            .all(|n| n.reason != Some(reproj_front::CullReason::InLoop))
    );
    insta::assert_snapshot!("nested_loops_unrolled", wgsl(&unrolled));
}

#[test]
fn the_trip_limit_leaves_longer_loops_alone() {
    let src = wrap("for (var i = 0; i < 8; i++) { acc += sin(p.x * f32(i)); }");
    assert_eq!(loop_count(&normalized(&src, 7).0), 1);
    assert_eq!(loop_count(&normalized(&src, 8).0), 0);
    assert_eq!(loop_count(&normalized(&src, 0).0), 1);
}

#[test]
fn other_loop_shapes_are_left_alone() {
    for body in [
        // A break of its own.
        "for (var i = 0; i < 4; i++) { if p.x > f32(i) { break; } acc += p.y; }",
        // A continue.
        "for (var i = 0; i < 4; i++) { if p.x > f32(i) { continue; } acc += p.y; }",
        // A bound that is not a literal.
        "for (var i = 0u; i < n; i++) { acc += p.y; }",
        // A write to the counter in the body.
        "for (var i = 0; i < 4; i++) { acc += p.y; i += 1; }",
        // A start that is not known.
        "var i = i32(p.x); loop { if i >= 4 { break; } acc += p.y; continuing { i += 1; } }",
        // A counter that wraps around.
        "for (var i = 2u; i != 1u; i += 2u) { acc += p.y; }",
    ] {
        let (norm, _) = normalized(&wrap(body), 32);
        assert_eq!(loop_count(&norm), 1, "{body}");
    }
}

#[test]
fn counting_down_and_by_steps_unrolls() {
    for (body, trips) in [
        (
            "for (var i = 7; i >= 0; i -= 2) { acc += sin(p.x * f32(i)); }",
            4,
        ),
        (
            "for (var i = 1u; i <= 9u; i += 4u) { acc += sin(p.x * f32(i)); }",
            3,
        ),
        (
            "var i = 0; loop { if !(i < 3) { break; } acc += sin(p.x * f32(i)); continuing { i = i + 1; } }",
            3,
        ),
    ] {
        let (norm, table) = normalized(&wrap(body), 32);
        assert_eq!(loop_count(&norm), 0, "{body}");
        let sines = table
            .nodes
            .iter()
            .filter(|n| n.text.starts_with("sin("))
            .count();
        assert_eq!(sines, trips, "{body}");
    }
}

/// The figures the issue asks for: node counts before and after unrolling.
#[test]
fn node_counts_of_the_shaders_with_loops() {
    for (shader, grows) in [
        ("shaders/ambient_occlusion.wgsl", true),
        ("shaders/envmap.wgsl", false),
    ] {
        let count = |max_trip| {
            let l = load(
                &repo(shader),
                None,
                &LoadOptions {
                    unroll: UnrollOptions { max_trip },
                    ..Default::default()
                },
            )
            .unwrap();
            (l.table.nodes.len(), l.table.cacheable().count())
        };
        let (before, after) = (count(0), count(32));
        eprintln!(
            "{shader}: nodes {} → {}, cacheable {} → {}",
            before.0, after.0, before.1, after.1
        );
        assert_eq!(
            after.1 > before.1,
            grows,
            "{shader}: {before:?} → {after:?}"
        );
    }
}
