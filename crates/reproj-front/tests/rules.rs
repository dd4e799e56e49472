//! One minimal fixture per culling rule, plus inlining, load forwarding and values read after loops.

use std::path::Path;

use reproj_front::{CullReason, Node, NodeTable, enumerate, normalize, parse_shader};

const HEADER: &str = "
struct Scene { camera_pos: vec3<f32>, time: f32, light_pos: vec3<f32>, gain: f32 };
@group(0) @binding(0) var<uniform> scene: Scene;
";

fn table(body: &str) -> NodeTable {
    let src = format!("{HEADER}\n{body}");
    let shader = parse_shader(Path::new("fixture.wgsl"), src).unwrap_or_else(|e| panic!("{e}"));
    let norm = normalize(&shader, &Default::default()).unwrap_or_else(|e| panic!("{e}"));
    enumerate(&shader, &norm)
}

fn node<'a>(t: &'a NodeTable, text: &str) -> &'a Node {
    let found: Vec<&Node> = t.nodes.iter().filter(|n| n.text == text).collect();
    assert!(
        !found.is_empty(),
        "no node `{text}` in {:#?}",
        t.nodes.iter().map(|n| &n.text).collect::<Vec<_>>()
    );
    found[0]
}

fn reason(t: &NodeTable, text: &str) -> Option<CullReason> {
    node(t, text).reason
}

#[test]
fn in_loop() {
    let t = table(
        "@fragment fn fs_main(@location(0) p: vec3<f32>) -> @location(0) vec4<f32> {
            var acc = 0.0;
            for (var i = 0; i < 4; i++) { acc += sin(p.x * 3.0); }
            return vec4<f32>(acc, 0.0, 0.0, 1.0);
        }",
    );
    assert_eq!(reason(&t, "sin(p.x * 3.0)"), Some(CullReason::InLoop));
}

#[test]
fn value_after_loop_is_cacheable_and_costs_the_loop() {
    let t = table(
        "@fragment fn fs_main(@location(0) p: vec3<f32>) -> @location(0) vec4<f32> {
            var acc = 0.0;
            for (var i = 0; i < 4; i++) { acc += sin(p.x * 3.0); }
            let total = acc;
            return vec4<f32>(total * 2.0, 0.0, 0.0, 1.0);
        }",
    );
    let after: Vec<&Node> = t
        .nodes
        .iter()
        .filter(|n| n.text == "acc" && n.cacheable)
        .collect();
    assert_eq!(after.len(), 1, "{:#?}", t.nodes);
    let sin = node(&t, "sin(p.x * 3.0)");
    // sin (8) + multiply (1), four trips.
    assert_eq!(sin.cost, 4.0 * 9.0);
    assert!(
        after[0].cost > sin.cost,
        "the loop is in the subtree: {} vs {}",
        after[0].cost,
        sin.cost
    );
}

#[test]
fn non_uniform_branch() {
    let t = table(
        "@fragment fn fs_main(@location(0) p: vec3<f32>) -> @location(0) vec4<f32> {
            var c = vec3<f32>(0.0);
            if p.x > 0.5 { c = cos(p * 2.0); }
            return vec4<f32>(c, 1.0);
        }",
    );
    assert_eq!(
        reason(&t, "cos(p * 2.0)"),
        Some(CullReason::NonUniformBranch)
    );
}

#[test]
fn uniform_branch_is_cacheable() {
    let t = table(
        "@fragment fn fs_main(@location(0) p: vec3<f32>) -> @location(0) vec4<f32> {
            var c = vec3<f32>(0.0);
            if scene.gain > 0.5 { c = cos(p * 2.0); }
            return vec4<f32>(c, 1.0);
        }",
    );
    assert_eq!(reason(&t, "cos(p * 2.0)"), None);
}

#[test]
fn discontinuous() {
    let t = table(
        "@fragment fn fs_main(@location(0) p: vec3<f32>) -> @location(0) vec4<f32> {
            let a = sin(p.x * 7.0);
            let b = cos(p.y * 5.0);
            let s = step(0.3, a);
            let f = floor(b * 4.0);
            let c = select(0.2, 0.8, exp(p.z) > 1.5);
            return vec4<f32>(s, f, c, 1.0);
        }",
    );
    assert_eq!(
        reason(&t, "sin(p.x * 7.0)"),
        Some(CullReason::Discontinuous)
    );
    assert_eq!(reason(&t, "b * 4.0"), Some(CullReason::Discontinuous));
    assert_eq!(reason(&t, "exp(p.z)"), Some(CullReason::Discontinuous));
    // One continuous path is enough.
    let t = table(
        "@fragment fn fs_main(@location(0) p: vec3<f32>) -> @location(0) vec4<f32> {
            let a = sin(p.x * 7.0);
            return vec4<f32>(step(0.3, a), a, 0.0, 1.0);
        }",
    );
    assert_eq!(reason(&t, "sin(p.x * 7.0)"), None);
}

#[test]
fn discontinuous_through_integer_conversion() {
    let t = table(
        "@fragment fn fs_main(@location(0) p: vec3<f32>) -> @location(0) vec4<f32> {
            let cell = u32(abs(p.x * 10.0));
            let h = f32((cell * 747796405u) & 255u) / 255.0;
            return vec4<f32>(h, h, h, 1.0);
        }",
    );
    assert_eq!(
        reason(&t, "abs(p.x * 10.0)"),
        Some(CullReason::Discontinuous)
    );
}

#[test]
fn derivative() {
    let t = table(
        "@fragment fn fs_main(@location(0) p: vec3<f32>) -> @location(0) vec4<f32> {
            let q = sin(p * 9.0);
            let w = fwidth(q.x);
            return vec4<f32>(q, w);
        }",
    );
    assert_eq!(reason(&t, "sin(p * 9.0)"), Some(CullReason::Derivative));
}

#[test]
fn payload_type() {
    let t = table(
        "@fragment fn fs_main(@location(0) p: vec3<f32>) -> @location(0) vec4<f32> {
            let m = mat3x3<f32>(p * 2.0, p.yzx, p.zxy);
            return vec4<f32>(m * p, 1.0);
        }",
    );
    assert_eq!(
        reason(&t, "mat3x3<f32>(p * 2.0, p.yzx, p.zxy)"),
        Some(CullReason::PayloadType)
    );
    assert_eq!(node(&t, "m * p").reason, None);
}

#[test]
fn trivial() {
    let t = table(
        "@fragment fn fs_main(@location(0) p: vec3<f32>) -> @location(0) vec4<f32> {
            let l = scene.light_pos;
            return vec4<f32>(p.x + l.x, 0.5, scene.time, 1.0);
        }",
    );
    assert_eq!(reason(&t, "0.5"), Some(CullReason::Trivial));
    assert_eq!(reason(&t, "scene.time"), Some(CullReason::Trivial));
    assert_eq!(reason(&t, "p.x"), Some(CullReason::Trivial));
    assert_eq!(reason(&t, "p.x + l.x"), None);
}

#[test]
fn root_is_a_cacheable_candidate() {
    let t = table(
        "@fragment fn fs_main(@location(0) p: vec3<f32>) -> @location(0) vec4<f32> {
            return vec4<f32>(sin(p), 1.0);
        }",
    );
    let root = t.root();
    assert!(root.cacheable);
    assert_eq!(root.text, "vec4<f32>(sin(p), 1.0)");
}

#[test]
fn helper_called_twice_gives_two_nodes_with_call_sites() {
    let t = table(
        "fn lum(c: vec3<f32>) -> f32 { return dot(c, vec3<f32>(0.2, 0.7, 0.1)); }
        @fragment fn fs_main(@location(0) p: vec3<f32>) -> @location(0) vec4<f32> {
            let a = lum(sin(p));
            let b = lum(cos(p));
            return vec4<f32>(a, b, 0.0, 1.0);
        }",
    );
    let dots: Vec<&Node> = t
        .nodes
        .iter()
        .filter(|n| n.text.starts_with("dot(c"))
        .collect();
    assert_eq!(dots.len(), 2);
    assert!(dots.iter().all(|n| n.cacheable && n.call_line.is_some()));
    assert_ne!(dots[0].call_line, dots[1].call_line);
}

#[test]
fn helper_with_locals_is_inlined_and_forwarded() {
    let src = format!(
        "{HEADER}
        fn soft(x: f32) -> f32 {{
            var y = x * 0.5;
            y = y + 0.25;
            var z: f32;
            z = y * y;
            return z;
        }}
        @fragment fn fs_main(@location(0) p: vec3<f32>) -> @location(0) vec4<f32> {{
            return vec4<f32>(soft(p.x), soft(p.y), 0.0, 1.0);
        }}"
    );
    let shader = parse_shader(Path::new("fixture.wgsl"), src).unwrap();
    let norm = normalize(&shader, &Default::default()).unwrap();
    let f = norm.function();
    // Every load was forwarded: no local variable survives, and there is no call.
    assert_eq!(f.local_variables.len(), 0, "{:#?}", f.local_variables);
    assert!(norm.module.functions.is_empty());
    let t = enumerate(&shader, &norm);
    assert_eq!(t.nodes.iter().filter(|n| n.text == "y * y").count(), 2);
}

#[test]
fn identical_computation_is_one_node() {
    let t = table(
        "@fragment fn fs_main(@location(0) p: vec3<f32>) -> @location(0) vec4<f32> {
            let a = sin(p.x * 3.0);
            let b = sin(p.x * 3.0);
            return vec4<f32>(a, b, 0.0, 1.0);
        }",
    );
    assert_eq!(
        t.nodes
            .iter()
            .filter(|n| n.text.starts_with("sin(p.x * 3.0)"))
            .count(),
        1
    );
}

#[test]
fn early_return_in_helper_is_inlined() {
    // Once refused ("early return in helper fn"); now one exit per function (tests/shapes.rs).
    let t = table(
        "fn f(x: f32) -> f32 { if x > 0.0 { return 1.0; } return sin(x); }
        @fragment fn fs_main(@location(0) p: vec3<f32>) -> @location(0) vec4<f32> {
            return vec4<f32>(f(p.x), 0.0, 0.0, 1.0);
        }",
    );
    assert_eq!(reason(&t, "sin(x)"), Some(CullReason::NonUniformBranch));
}

#[test]
fn ids_are_stable() {
    let src = std::fs::read_to_string(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../shaders/marble.wgsl"
    ))
    .unwrap();
    let a = {
        let s = parse_shader(Path::new("marble.wgsl"), src.clone()).unwrap();
        enumerate(&s, &normalize(&s, &Default::default()).unwrap())
    };
    let b = {
        let s = parse_shader(Path::new("marble.wgsl"), src).unwrap();
        enumerate(&s, &normalize(&s, &Default::default()).unwrap())
    };
    assert_eq!(a, b);
}

#[test]
fn struct_output_root_is_location_zero() {
    let t = table(
        "struct Out { @location(0) color: vec4<f32>, @location(1) extra: vec4<f32> };
        @fragment fn fs_main(@location(0) p: vec3<f32>) -> Out {
            return Out(vec4<f32>(sin(p), 1.0), vec4<f32>(cos(p), 1.0));
        }",
    );
    assert_eq!(t.root().text, "vec4<f32>(sin(p), 1.0)");
}

#[test]
fn implicit_lod_sample_coordinates_are_derivative() {
    let t = table(
        "@group(1) @binding(0) var tex: texture_2d<f32>;
        @group(1) @binding(1) var samp: sampler;
        @fragment fn fs_main(@location(0) p: vec3<f32>) -> @location(0) vec4<f32> {
            let a = textureSample(tex, samp, p.xy * 3.0);
            let b = textureSampleLevel(tex, samp, p.yz * 5.0, 0.0);
            return a + b;
        }",
    );
    assert_eq!(reason(&t, "p.xy * 3.0"), Some(CullReason::Derivative));
    assert_eq!(reason(&t, "p.yz * 5.0"), None);
}
