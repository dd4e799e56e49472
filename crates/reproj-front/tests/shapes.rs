//! The common WGSL shapes that need one exit per function or member-by-member stores,
//! one minimal fixture each: what they normalize to (snapshots of the normalized WGSL) and which
//! of their nodes are cacheable; and the diagnostics of what is still refused.
//!
//! After an intended change: `INSTA_UPDATE=always cargo test -p reproj-front --test integration
//! shapes::` (or `cargo insta review`) and review the diff of `tests/snapshots/`.

use std::path::Path;

use reproj_front::{CullReason, Node, NodeTable, Normalized, enumerate, normalize, parse_shader};

const HEADER: &str =
    "struct Scene { camera_pos: vec3<f32>, time: f32, light_pos: vec3<f32>, mode: u32 };
@group(0) @binding(0) var<uniform> scene: Scene;
";

fn load(body: &str) -> (Normalized, NodeTable) {
    let src = format!("{HEADER}{body}");
    let shader = parse_shader(Path::new("fixture.wgsl"), src).unwrap_or_else(|e| panic!("{e}"));
    let norm = normalize(&shader, &Default::default()).unwrap_or_else(|e| panic!("{e}"));
    let table = enumerate(&shader, &norm);
    (norm, table)
}

fn error(body: &str) -> String {
    let src = format!("{HEADER}{body}");
    let shader = parse_shader(Path::new("fixture.wgsl"), src).unwrap_or_else(|e| panic!("{e}"));
    let e = normalize(&shader, &Default::default()).unwrap_err();
    match e.diagnostic() {
        Some(d) => d.render(),
        None => e.to_string(),
    }
}

fn wgsl(norm: &Normalized) -> String {
    naga::back::wgsl::write_string(
        &norm.module,
        &norm.info,
        naga::back::wgsl::WriterFlags::empty(),
    )
    .unwrap()
}

fn node<'a>(t: &'a NodeTable, text: &str) -> &'a Node {
    t.nodes.iter().find(|n| n.text == text).unwrap_or_else(|| {
        panic!(
            "no node `{text}` in {:#?}",
            t.nodes.iter().map(|n| &n.text).collect::<Vec<_>>()
        )
    })
}

/// The function's `return`s, at any depth.
fn returns(block: &naga::Block) -> usize {
    block
        .iter()
        .map(|s| match s {
            naga::Statement::Return { .. } => 1,
            naga::Statement::Block(b) => returns(b),
            naga::Statement::If { accept, reject, .. } => returns(accept) + returns(reject),
            naga::Statement::Switch { cases, .. } => cases.iter().map(|c| returns(&c.body)).sum(),
            naga::Statement::Loop { body, .. } => returns(body),
            _ => 0,
        })
        .sum()
}

#[test]
fn switch_returning_from_each_case() {
    let (norm, t) = load(
        "@fragment fn fs_main(@location(0) p: vec3<f32>, @location(1) n: vec3<f32>) -> @location(0) vec4<f32> {
            switch scene.mode {
                case 0u: { return vec4<f32>(normalize(n) * 0.5 + 0.5, 1.0); }
                case 1u, 2u: { return vec4<f32>(fract(p * 4.0), 1.0); }
                default: { return vec4<f32>(vec3<f32>(sin(p.x * 10.0 + scene.time)), 1.0); }
            }
        }",
    );
    assert_eq!(returns(&norm.function().body), 1);
    // The branch is on a uniform: the work inside the cases is cacheable.
    for text in ["normalize(n)", "sin(p.x * 10.0 + scene.time)"] {
        let n = node(&t, text);
        assert!(n.cacheable, "{text}: {:?}", n.reason);
    }
    insta::assert_snapshot!("switch_returns", wgsl(&norm));
}

#[test]
fn if_else_returning_on_both_sides_on_a_pixel_value() {
    let (norm, t) = load(
        "@fragment fn fs_main(@location(0) p: vec3<f32>) -> @location(0) vec4<f32> {
            if p.y > 0.5 {
                return vec4<f32>(vec3<f32>(cos(p.x * 7.0)), 1.0);
            } else {
                return vec4<f32>(vec3<f32>(sin(p.z * 3.0)), 1.0);
            }
        }",
    );
    assert_eq!(returns(&norm.function().body), 1);
    assert_eq!(
        node(&t, "cos(p.x * 7.0)").reason,
        Some(CullReason::NonUniformBranch)
    );
    // The value after the branch (the result variable) is a node whose subtree is the branch.
    assert!(t.root().cacheable, "{:?}", t.root());
}

#[test]
fn output_struct_filled_field_by_field() {
    let (norm, t) = load(
        "struct GBuffer {
            @location(0) albedo: vec4<f32>,
            @location(1) normal: vec4<f32>,
            @location(2) material: vec2<f32>,
        };
        @fragment fn fs_main(@location(0) p: vec3<f32>, @location(1) n: vec3<f32>) -> GBuffer {
            var out: GBuffer;
            out.albedo = vec4<f32>(0.5 + 0.5 * sin(p * 6.0), 1.0);
            out.normal = vec4<f32>(normalize(n) * 0.5 + 0.5, 0.0);
            out.material.x = 0.8;
            out.material.y = dot(n, scene.light_pos);
            return out;
        }",
    );
    // The root is the @location(0) member, as the value stored.
    assert_eq!(t.root().text, "vec4<f32>(0.5 + 0.5 * sin(p * 6.0), 1.0)");
    assert!(node(&t, "sin(p * 6.0)").cacheable);
    insta::assert_snapshot!("gbuffer_fields", wgsl(&norm));
}

#[test]
fn early_returns_in_helpers() {
    let (norm, t) = load(
        "fn diffuse(n: vec3<f32>, l: vec3<f32>) -> f32 {
            let d = dot(n, l);
            if d <= 0.0 { return 0.0; }
            return d * d;
        }
        fn tone(c: f32) -> f32 {
            for (var i = 0; i < 4; i++) {
                if c < f32(i) * 0.25 { return f32(i); }
            }
            return 4.0;
        }
        fn pick(m: u32, x: f32) -> f32 {
            switch m {
                case 0u: { return x; }
                default: {
                    if x > 1.0 { return 1.0; }
                }
            }
            return sqrt(x);
        }
        @fragment fn fs_main(@location(0) p: vec3<f32>, @location(1) n: vec3<f32>) -> @location(0) vec4<f32> {
            let l = normalize(scene.light_pos - p);
            let k = diffuse(normalize(n), l);
            return vec4<f32>(k, tone(k), pick(scene.mode, exp(p.x)), 1.0);
        }",
    );
    assert_eq!(returns(&norm.function().body), 1);
    assert!(node(&t, "normalize(scene.light_pos - p)").cacheable);
    insta::assert_snapshot!("helper_early_returns", wgsl(&norm));
}

#[test]
fn return_from_a_loop_in_the_entry_point() {
    let (norm, _) = load(
        "@fragment fn fs_main(@location(0) p: vec3<f32>) -> @location(0) vec4<f32> {
            var x = p.x;
            loop {
                x = x * 1.5;
                if x > 10.0 { return vec4<f32>(x, 0.0, 0.0, 1.0); }
                if x < 0.001 { break; }
            }
            return vec4<f32>(0.0, x, 0.0, 1.0);
        }",
    );
    assert_eq!(returns(&norm.function().body), 1);
    insta::assert_snapshot!("loop_return", wgsl(&norm));
}

#[test]
fn no_output_names_the_entry_point() {
    insta::assert_snapshot!(
        "no_output",
        error(
            "@group(0) @binding(1) var<storage, read_write> o: array<f32>;
@fragment fn fs_main(@location(0) p: vec3<f32>) { o[0] = p.x; }"
        )
    );
}

/// An output struct filled in branches (`if … { out.color = …; } return out;`, Bevy's
/// `pbr.wgsl`) is returned as one built member by member, so its `@location(0)` member is the root.
#[test]
fn output_struct_filled_in_a_branch_is_composed_at_the_return() {
    let (norm, table) = load(
        "struct Out { @location(0) color: vec4<f32>, @location(1) extra: vec4<f32> };
@fragment fn fs_main(@location(0) p: vec3<f32>) -> Out {
    var out: Out;
    out.extra = vec4<f32>(p, 1.0);
    if p.x > 0.5 { out.color = vec4<f32>(sin(p * 3.0), 1.0); } else { out.color = vec4<f32>(0.2); }
    return out;
}",
    );
    insta::assert_snapshot!("struct_in_branch", wgsl(&norm));
    assert_eq!(table.root().ty, "vec4<f32>");
    assert!(table.root().cacheable, "{:?}", table.root().reason);
}

/// A C-style `switch` whose cases fall through (GLSL; WGSL has none, and naga's WGSL writer
/// refuses a case that falls through with a body): each such case is written as its body followed
/// by the bodies it falls into.
#[test]
fn glsl_fall_through_cases_are_merged() {
    let src = "#version 450
layout(location = 0) in vec3 p;
layout(location = 0) out vec4 color;
layout(set = 0, binding = 0) uniform Params { int mode; float gain; };
void main() {
    vec3 c = vec3(0.0);
    switch (mode) {
        case 0:
            c += sin(p * 3.0);
        case 1:
            c *= gain;
            c += cos(p.yzx * 5.0);
            break;
        default:
            c = p;
            break;
    }
    color = vec4(c, 1.0);
}
";
    let shader = reproj_front::parse_glsl(Path::new("fixture.frag"), src.to_owned())
        .unwrap_or_else(|e| panic!("{e}"));
    let norm = normalize(&shader, &Default::default()).unwrap_or_else(|e| panic!("{e}"));
    fn falls_with_body(block: &naga::Block) -> bool {
        block.iter().any(|s| match s {
            naga::Statement::Switch { cases, .. } => cases
                .iter()
                .any(|c| (c.fall_through && !c.body.is_empty()) || falls_with_body(&c.body)),
            naga::Statement::Block(b) => falls_with_body(b),
            naga::Statement::If { accept, reject, .. } => {
                falls_with_body(accept) || falls_with_body(reject)
            }
            naga::Statement::Loop { body, .. } => falls_with_body(body),
            _ => false,
        })
    }
    let has_fall_through = |m: &naga::Module| {
        m.entry_points
            .iter()
            .any(|e| falls_with_body(&e.function.body))
            || m.functions.iter().any(|(_, f)| falls_with_body(&f.body))
    };
    assert!(
        has_fall_through(&shader.module),
        "the fixture falls through"
    );
    assert!(!has_fall_through(&norm.module));
    // naga's WGSL writer takes the normalized module, and the `sin` of case 0 is a node.
    let text = wgsl(&norm);
    assert!(text.contains("sin("), "{text}");
    let table = enumerate(&shader, &norm);
    assert!(table.nodes.len() > 3, "{:#?}", table.nodes);
}

/// The real-style shaders of each shape load, with cacheable nodes inside what was refused: the
/// `switch` cases of the corpus's `debug_views`, the helpers of its `early_returns`, the G-buffer
/// fields of `tests/fixtures/gbuffer.wgsl` (not in the corpus: the replay draws one target).
#[test]
fn real_style_shaders_of_each_shape_load() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    for (path, inside) in [
        (
            "../../tests/corpus/shaders/debug_views.wgsl",
            "n * 0.5 + 0.5",
        ),
        ("tests/fixtures/gbuffer.wgsl", "base * (0.6 + 0.4 * grime)"),
        (
            "../../tests/corpus/shaders/early_returns.wgsl",
            "smoothstep(scene.spot_cos_outer, scene.spot_cos_inner, cos_angle)",
        ),
    ] {
        let name = path.rsplit('/').next().unwrap();
        let shader = reproj_front::load_file(&root.join(path)).unwrap_or_else(|e| panic!("{e}"));
        let norm = normalize(&shader, &Default::default()).unwrap_or_else(|e| panic!("{e}"));
        let t = enumerate(&shader, &norm);
        assert_eq!(returns(&norm.function().body), 1, "{name}");
        let n = node(&t, inside);
        assert!(
            n.cacheable || n.reason == Some(CullReason::NonUniformBranch),
            "{name}: `{inside}`: {:?}",
            n.reason
        );
        assert!(
            t.cacheable().count() >= 10,
            "{name}: {}",
            t.cacheable().count()
        );
    }
}
