//! What Vulkan-style GLSL written by others does and the front end now reads (
//! `tests/others/`): `#include` beside the shader, matrix fragment inputs, texture reads
//! in non-uniform control flow; and what naga 30 cannot read, refused by name at its place. Needs
//! `glslangValidator`: without it these tests fail under `CI` and say they skipped otherwise.

use std::path::Path;

use reproj_front::{FrontError, LoadOptions, Loaded, load, parse_glsl};

/// Whether glslang is here; fails under CI when it is not.
fn glslang_here(test: &str) -> bool {
    if reproj_front::glslang::glslang_available() {
        return true;
    }
    assert!(
        std::env::var_os("CI").is_none(),
        "{test}: glslangValidator is missing (scripts/ensure-tools.sh installs it)"
    );
    eprintln!("{test}: SKIPPED, glslangValidator is not installed");
    false
}

#[test]
fn includes_are_resolved_beside_the_shader() {
    if !glslang_here("includes") {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    std::fs::create_dir(dir.path().join("inc")).unwrap();
    std::fs::write(
        dir.path().join("inc/tone.glsl"),
        "vec3 tone(vec3 c) { return c / (c + vec3(1.0)); }\n",
    )
    .unwrap();
    let shader = dir.path().join("lit.frag");
    std::fs::write(
        &shader,
        "#version 450\n#extension GL_GOOGLE_include_directive : require\n\
         layout(location = 0) in vec3 n;\nlayout(location = 0) out vec4 c;\n\
         #include \"inc/tone.glsl\"\n\
         void main() {\n    c = vec4(tone(abs(n) * 4.0), 1.0);\n}\n",
    )
    .unwrap();
    let loaded = load(&shader, None, &LoadOptions::default()).unwrap();
    assert!(loaded.table.cacheable().count() > 2);

    // A missing include is glslang's error at the `#include` line.
    std::fs::remove_file(dir.path().join("inc/tone.glsl")).unwrap();
    let err = load(&shader, None, &LoadOptions::default()).unwrap_err();
    assert!(matches!(err, FrontError::Parse(_)), "{err:?}");
    let msg = err.to_string();
    assert!(
        msg.contains("lit.frag:5:") && msg.contains("inc/tone.glsl"),
        "{msg}"
    );
}

/// An `#include` without `#extension GL_GOOGLE_include_directive` (shaderc turns it on by
/// itself, so Vulkan projects never ask) is read as if it asked, found in an include folder
/// given (`-I`), and a later error is still reported at its own line.
#[test]
fn includes_need_no_extension_line() {
    if !glslang_here("includes without the extension") {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    std::fs::create_dir(dir.path().join("framework")).unwrap();
    std::fs::write(
        dir.path().join("framework/lighting.h"),
        "vec3 lit(vec3 n) { return vec3(max(n.z, 0.0)); }\n",
    )
    .unwrap();
    let shader = dir.path().join("forward.frag");
    let text = |body: &str| {
        format!(
            "#version 450\nlayout(location = 0) in vec3 n;\nlayout(location = 0) out vec4 c;\n\
             #include \"lighting.h\"\nvoid main() {{\n    {body}\n}}\n"
        )
    };
    std::fs::write(&shader, text("c = vec4(lit(n) * 2.0, 1.0);")).unwrap();
    let options = LoadOptions {
        input: reproj_front::ShaderInput {
            include_dirs: vec![dir.path().join("framework")],
            ..Default::default()
        },
        ..Default::default()
    };
    let loaded = load(&shader, None, &options).unwrap_or_else(|e| panic!("{e}"));
    assert!(loaded.table.cacheable().count() > 0);
    std::fs::write(&shader, text("c = vec4(lit(n) * 2.0, 1.0) + oops;")).unwrap();
    let msg = load(&shader, None, &options).unwrap_err().to_string();
    assert!(msg.contains("forward.frag:6:"), "{msg}");
}

#[test]
fn matrix_inputs_become_one_vector_per_column() {
    if !glslang_here("matrix inputs") {
        return;
    }
    let src = "#version 450\n\
        layout(location = 0) in vec3 p;\n\
        layout(location = 1) in mat4 view;\n\
        layout(location = 5) in float fade;\n\
        layout(location = 0) out vec4 c;\n\
        void main() {\n    float z = (view * vec4(p, 1.0)).z;\n    c = vec4(z * 0.5, fade, 0.0, 1.0);\n}\n";
    let shader = parse_glsl(Path::new("grid.frag"), src.into()).unwrap();
    let ep = &shader.module.entry_points[0];
    let mut locations: Vec<(u32, String)> = ep
        .function
        .arguments
        .iter()
        .filter_map(|a| match a.binding {
            Some(naga::Binding::Location { location, .. }) => {
                let ty = &shader.module.types[a.ty].inner;
                Some((location, format!("{ty:?}")))
            }
            _ => None,
        })
        .collect();
    locations.sort();
    let at: Vec<u32> = locations.iter().map(|l| l.0).collect();
    assert_eq!(at, [0, 1, 2, 3, 4, 5], "{locations:?}");
    for (location, ty) in &locations[1..5] {
        assert!(
            ty.contains("Vector") && ty.contains("Quad"),
            "{location}: {ty}"
        );
    }
    // The product still reads the matrix: `z` is a node of the whole expression.
    let loaded = Loaded::new(shader, None).unwrap();
    assert!(loaded.table.cacheable().count() >= 3);
}

#[test]
fn texture_reads_in_nonuniform_branches_are_allowed_as_in_glsl() {
    if !glslang_here("derivative uniformity") {
        return;
    }
    let src = "#version 450\n\
        layout(binding = 1) uniform sampler2D shadowMap;\n\
        layout(location = 0) in vec4 sc;\n\
        layout(location = 0) out vec4 c;\n\
        void main() {\n    float s = 1.0;\n    if (sc.z > -1.0 && sc.z < 1.0) {\n        \
        if (texture(shadowMap, sc.st).r < sc.z) { s = 0.1; }\n    }\n    c = vec4(s);\n}\n";
    let shader = parse_glsl(Path::new("shadow.frag"), src.into()).unwrap();
    let leaf = shader
        .module
        .diagnostic_filter_leaf
        .expect("a global diagnostic filter");
    let filter = &shader.module.diagnostic_filters[leaf].inner;
    assert_eq!(filter.new_severity, naga::diagnostic_filter::Severity::Off);
    assert_eq!(
        filter.triggering_rule,
        naga::diagnostic_filter::FilterableTriggeringRule::Standard(
            naga::diagnostic_filter::StandardFilterableTriggeringRule::DerivativeUniformity
        )
    );
}

#[test]
fn input_attachments_are_refused_by_name_with_a_caret() {
    if !glslang_here("input attachments") {
        return;
    }
    let src = "#version 450\n\
        layout(input_attachment_index = 0, binding = 0) uniform subpassInput color;\n\
        layout(location = 0) out vec4 c;\n\
        void main() {\n    c = subpassLoad(color);\n}\n";
    let err = parse_glsl(Path::new("read.frag"), src.into()).unwrap_err();
    let FrontError::Unsupported(d) = &err else {
        panic!("{err:?}")
    };
    let msg = err.to_string();
    assert!(msg.starts_with("read.frag:2:"), "{msg}");
    assert!(msg.contains("input attachment"), "{msg}");
    let shown = d.render();
    assert!(
        shown.contains("uniform subpassInput color") && shown.contains("^^^^^^^^^^^^"),
        "{shown}"
    );
}

/// glslang's lines carry no column: every value of a GLSL line is still listed at its own column
/// with its own text — each sub-expression where it is written, a literal where it is written, a
/// parenthesized operand with its parentheses, an input at its declaration (without the comment
/// after it), a matrix input's columns at the matrix's declaration.
#[test]
fn glsl_nodes_sit_at_their_own_column_with_their_own_text() {
    if !glslang_here("columns") {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let shader = dir.path().join("cols.frag");
    std::fs::write(
        &shader,
        "#version 450\nlayout(location = 0) in vec3 p; // position\n\
         layout(location = 1) in mat3 tbn;\nlayout(location = 0) out vec4 o;\n\
         void main() {\n    float a = sin(p.x) * 2.0 + cos(p.y * 3.0);\n\
         \x20   vec3 c = vec3(a) * (p + 0.5) + tbn * p;\n    o = vec4(c, 1.0);\n}\n",
    )
    .unwrap();
    let loaded = load(&shader, None, &LoadOptions::default()).unwrap();
    let at: Vec<(u32, u32, &str)> = loaded
        .table
        .nodes
        .iter()
        .map(|n| (n.line, n.col, n.text.as_str()))
        .collect();
    for want in [
        (2, 1, "layout(location = 0) in vec3 p"),
        (3, 1, "layout(location = 1) in mat3 tbn"),
        (6, 19, "p.x"),
        (6, 15, "sin(p.x)"),
        (6, 26, "2.0"),
        (6, 15, "sin(p.x) * 2.0"),
        (6, 36, "p.y"),
        (6, 42, "3.0"),
        (6, 36, "p.y * 3.0"),
        (6, 32, "cos(p.y * 3.0)"),
        (6, 15, "sin(p.x) * 2.0 + cos(p.y * 3.0)"),
        (7, 14, "vec3(a)"),
        (7, 25, "p + 0.5"),
        (7, 14, "vec3(a) * (p + 0.5)"),
        (7, 36, "tbn * p"),
        (7, 14, "vec3(a) * (p + 0.5) + tbn * p"),
        (8, 9, "vec4(c, 1.0)"),
    ] {
        assert!(at.contains(&want), "{want:?} not among {at:#?}");
    }
    assert!(at.iter().all(|&(line, _, _)| line > 0), "{at:#?}");
}
