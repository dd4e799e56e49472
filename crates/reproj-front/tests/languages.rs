//! GLSL and SPIR-V input: the same nodes as the WGSL twin, diagnostics with file:line and a caret,
//! outputs that cannot be traced rejected, and why a shader has no cacheable node.

use std::path::{Path, PathBuf};

use reproj_front::{
    CullReason, FrontError, Lang, LoadOptions, Loaded, load, parse_glsl, parse_shader, parse_spirv,
};

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../..")
}

fn cacheable(l: &Loaded) -> usize {
    l.table.cacheable().count()
}

/// `a` within ±5 % of `b`.
fn close(a: usize, b: usize) -> bool {
    (a as f64 - b as f64).abs() <= 0.05 * b as f64
}

#[test]
fn glsl_marble_has_the_nodes_of_its_wgsl_twin() {
    let wgsl = load(
        &root().join("shaders/marble.wgsl"),
        None,
        &LoadOptions::default(),
    )
    .unwrap();
    let glsl = load(
        &root().join("shaders/glsl/marble.frag"),
        None,
        &LoadOptions::default(),
    )
    .unwrap();
    assert_eq!(glsl.shader.lang, Lang::Glsl);
    let (w, g) = (cacheable(&wgsl), cacheable(&glsl));
    assert!(w > 300, "{w}");
    // glslang's SPIR-V spells a few values in more steps than naga's WGSL (vector splats).
    assert!(
        g >= w && g * 10 <= w * 11,
        "GLSL marble: {g} cacheable nodes, WGSL: {w}"
    );
    // The root is the color written to the `out` variable, at its line and column in the GLSL
    // file (glslang's OpLine names the line; the line's parse, the column and text).
    let root = glsl.table.root();
    assert!(root.cacheable);
    assert_eq!(root.text, "vec4(color, 1.0)");
    assert_eq!((root.line, root.col), (104, 18));
    // The octave sums are nodes, where they are written.
    for (line, col, text) in [(79, 16, "n0 + n1"), (82, 16, "s3 + n4")] {
        assert!(
            glsl.table
                .cacheable()
                .any(|n| (n.line, n.col, n.text.as_str()) == (line, col, text)),
            "no cacheable `{text}` at {line}:{col}"
        );
    }
}

/// glslang writes an OpLine before each statement: every node has its GLSL line (and its
/// column, from the line's parse), and no text runs past its line.
#[test]
fn glsl_nodes_are_placed_at_their_glsl_lines() {
    let glsl = load(
        &root().join("shaders/glsl/marble.frag"),
        None,
        &LoadOptions::default(),
    )
    .unwrap();
    let nodes = &glsl.table.nodes;
    let unplaced = nodes.iter().filter(|n| n.line == 0).count();
    assert!(
        unplaced == 0,
        "{unplaced} of {} nodes without a position",
        nodes.len()
    );
    assert!(
        nodes
            .iter()
            .any(|n| n.text == "normalize(l + v)" && (n.line, n.col) == (95, 14)),
        "the half vector's line is not a node"
    );
    for n in nodes {
        assert!(
            !n.text.contains(';') && !n.text.contains('\n'),
            "node {}: {:?}",
            n.id,
            n.text
        );
    }
}

#[test]
fn marble_through_spirv_has_the_same_nodes() {
    let path = root().join("shaders/marble.wgsl");
    let wgsl = load(&path, None, &LoadOptions::default()).unwrap();
    let words = naga::back::spv::write_vec(
        &wgsl.shader.module,
        &wgsl.shader.info,
        &naga::back::spv::Options::default(),
        None,
    )
    .unwrap();
    let bytes: Vec<u8> = words.iter().flat_map(|w| w.to_le_bytes()).collect();
    let dir = tempfile::tempdir().unwrap();
    let spv = dir.path().join("marble.spv");
    std::fs::write(&spv, &bytes).unwrap();
    let loaded = load(&spv, None, &LoadOptions::default()).unwrap();
    assert_eq!(loaded.shader.lang, Lang::SpirV);
    let (w, s) = (cacheable(&wgsl), cacheable(&loaded));
    assert!(close(s, w), "SPIR-V marble: {s} cacheable nodes, WGSL: {w}");
    // The same bytes with the language named explicitly.
    let renamed = dir.path().join("marble.bin");
    std::fs::write(&renamed, &bytes).unwrap();
    let again = load(
        &renamed,
        None,
        &LoadOptions {
            lang: Some(Lang::SpirV),
            ..Default::default()
        },
    )
    .unwrap();
    assert_eq!(cacheable(&again), s);
}

#[test]
fn glsl_parse_errors_show_file_line_and_caret() {
    let src =
        "#version 450\nlayout(location = 0) out vec4 c;\nvoid main() {\n    c = vec4(1.0) +;\n}\n";
    let err = parse_glsl(Path::new("bad.frag"), src.into()).unwrap_err();
    // Kept as data; its one-line form says where, its rendering shows the line and a caret.
    let FrontError::Parse(d) = &err else {
        panic!("{err:?}")
    };
    assert!(err.to_string().starts_with("bad.frag:4:"), "{err}");
    let shown = d.render();
    assert!(shown.contains("bad.frag:4:"), "{shown}");
    assert!(
        shown.contains("c = vec4(1.0) +;") && shown.contains('^'),
        "{shown}"
    );
}

#[test]
fn invalid_spirv_is_a_clear_error() {
    let err = parse_spirv(Path::new("junk.spv"), b"not spir-v at all").unwrap_err();
    let msg = err.to_string();
    assert!(matches!(err, FrontError::Parse(_)), "{err:?}");
    assert!(msg.contains("junk.spv") && msg.contains("SPIR-V"), "{msg}");
}

#[test]
fn private_globals_written_once_are_forwarded() {
    // The WGSL spelling of what naga's GLSL front end produces: inputs copied into private
    // globals, a wrapper entry point calling the real main, the output read back.
    let src = r#"
        var<private> p_in: vec3<f32>;
        var<private> color_out: vec4<f32>;
        fn main_1() {
            let x = p_in;
            let s = sin(x * 3.0) * cos(x.yzx * 5.0) + sqrt(abs(x));
            color_out = vec4<f32>(s, 1.0);
        }
        @fragment fn main(@location(0) p: vec3<f32>) -> @location(0) vec4<f32> {
            p_in = p;
            main_1();
            return color_out;
        }
    "#;
    let shader = parse_shader(Path::new("private.wgsl"), src.into()).unwrap();
    let loaded = Loaded::new(shader, None).unwrap();
    let root = loaded.table.root();
    assert_eq!(root.text, "vec4<f32>(s, 1.0)");
    assert!(loaded.table.cacheable().any(|n| n.text == "sin(x * 3.0)"));
    // The private globals are gone from the normalized module.
    assert!(
        loaded
            .norm
            .module
            .global_variables
            .iter()
            .all(|(_, g)| g.space != naga::AddressSpace::Private)
    );
}

#[test]
fn glsl_output_never_written_is_rejected() {
    let src = "#version 450\nlayout(location = 0) in vec3 p;\nlayout(location = 0) out vec4 c;\nvoid main() {\n    vec3 unused = sin(p);\n}\n";
    let shader = parse_glsl(Path::new("unwritten.frag"), src.into()).unwrap();
    let err = Loaded::new(shader, None).unwrap_err();
    let msg = err.to_string();
    assert!(matches!(err, FrontError::Unsupported(_)), "{err:?}");
    assert!(msg.contains("unwritten.frag"), "{msg}");
    assert!(msg.contains("never written"), "{msg}");
}

#[test]
fn glsl_output_read_back_from_a_buffer_is_rejected() {
    let src = "#version 450\nlayout(location = 0) in vec3 p;\nlayout(location = 0) out vec4 c;\nlayout(std430, set = 0, binding = 1) buffer Scratch { vec4 v; } scratch;\nvoid main() {\n    scratch.v = vec4(sin(p), 1.0);\n    c = scratch.v;\n}\n";
    let shader = parse_glsl(Path::new("buffer.frag"), src.into()).unwrap();
    let err = Loaded::new(shader, None).unwrap_err();
    let msg = err.to_string();
    assert!(msg.contains("scratch"), "{msg}");
    assert!(msg.contains("cannot follow"), "{msg}");
}

#[test]
fn no_cacheable_node_counts_the_reasons() {
    // The color is the interpolated input (trivial); the work only decides a discard.
    let src = r#"
        @fragment fn fs(@location(0) p: vec3<f32>) -> @location(0) vec4<f32> {
            if length(sin(p * 9.0)) > 0.5 {
                discard;
            }
            return vec4<f32>(p, 1.0);
        }
    "#;
    let shader = parse_shader(Path::new("flat.wgsl"), src.into()).unwrap();
    let loaded = Loaded::new(shader, None).unwrap();
    assert_eq!(loaded.table.cacheable().count(), 0);
    let summary = loaded.table.cull_summary();
    let total: usize = summary.counts.iter().map(|(_, n)| n).sum();
    assert_eq!(total, loaded.table.nodes.len());
    let count = |reason| {
        summary
            .counts
            .iter()
            .find(|&&(r, _)| r == reason)
            .map(|&(_, n)| n)
    };
    assert_eq!(count(CullReason::Discontinuous), Some(3), "{summary:?}");
    assert!(count(CullReason::Trivial) > Some(0), "{summary:?}");
    assert_eq!(count(CullReason::InLoop), None, "{summary:?}");
    assert_eq!(summary.hint, CullReason::Trivial.hint());
}

/// Every node of a GLSL shader read through glslang sits at a real line and column of the GLSL
/// file, with that line's text: values glslang's SPIR-V gives no line (a read after a loop or a
/// `?:`, a constant, an input, the zero an output starts as) take the line where the variable
/// was last written or declared, or of their first user. Where glslang is installed (under CI it
/// must be).
#[test]
fn glsl_nodes_sit_at_their_lines_with_their_text() {
    if !reproj_front::glslang::glslang_available() {
        assert!(
            std::env::var_os("CI").is_none(),
            "CI is set and glslangValidator is missing: scripts/ensure-tools.sh installs it"
        );
        eprintln!("skipped: glslangValidator is not installed");
        return;
    }
    for file in [
        "shaders/glsl/marble.frag",
        "tests/corpus/shaders/glsl/cel_outline.frag",
        "tests/corpus/shaders/glsl/grid_debug.frag",
    ] {
        let loaded = load(&root().join(file), None, &LoadOptions::default()).unwrap();
        let lines = loaded.shader.source.lines().count() as u32;
        for n in &loaded.table.nodes {
            assert!(
                (1..=lines).contains(&n.line) && n.col >= 1 && !n.text.trim().is_empty(),
                "{file}: node {} at {}:{} {:?}",
                n.id,
                n.line,
                n.col,
                n.text
            );
        }
        // The most expensive cacheable node reads as GLSL, not as a bare variable.
        let top = loaded
            .table
            .cacheable()
            .max_by(|a, b| a.cost.total_cmp(&b.cost))
            .unwrap();
        assert!(top.text.contains([' ', '(']), "{file}: {top:?}");
    }
}
