//! WGSL with `#import`s (Bevy-style materials), composed with naga_oil from modules found beside
//! the shader (`tests/fixtures/imports/`: a material and three stand-in engine modules, one of
//! which imports another).

use std::path::{Path, PathBuf};

use reproj_front::compose::compose_searching;
use reproj_front::parse::FrontError;
use reproj_front::{load, load_file};

fn fixtures() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fixtures/imports")
}

/// The material composes with its imports (a module importing another included): the helpers
/// are inlined into the entry point and their values become nodes, and the composed text is WGSL
/// that parses again.
#[test]
fn a_material_with_imports_is_composed_and_its_nodes_listed() {
    let path = fixtures().join("hologram.wgsl");
    let shader = load_file(&path).unwrap();
    assert!(!shader.source.contains("#import"));
    naga::front::wgsl::parse_str(&shader.source).unwrap();
    let loaded = load::load(&path, None, &Default::default()).unwrap();
    let cacheable = loaded.table.cacheable().count();
    assert!(cacheable >= 20, "{cacheable} cacheable nodes");
    // `fresnel`'s pow, from the lighting module, is a node of the material.
    assert!(
        loaded
            .table
            .nodes
            .iter()
            .any(|n| n.text.starts_with("pow(")),
        "the imported helper's pow is a node"
    );
}

/// A module that is not found is refused at its `#import`, naming it and where it was looked
/// for; the same shader composes once its folder is searched.
#[test]
fn a_missing_module_is_named_at_its_import() {
    let path = fixtures().join("missing.wgsl");
    let e = load_file(&path).unwrap_err();
    let FrontError::Parse(d) = &e else {
        panic!("expected a parse error, got {e}")
    };
    let text = d.render();
    assert!(
        text.contains("no module `engine_pbr::clustered` was found"),
        "{text}"
    );
    assert!(text.contains("missing.wgsl:2:9"), "{text}");
    assert!(text.contains("REPROJ_WGSL_IMPORTS"), "{text}");

    // A material elsewhere finds the engine's modules only in the folders it is given.
    let dir = tempfile::tempdir().unwrap();
    let material = dir.path().join("hologram.wgsl");
    let source = std::fs::read_to_string(fixtures().join("hologram.wgsl")).unwrap();
    std::fs::write(&material, &source).unwrap();
    let alone = compose_searching(&material, &source, &[dir.path().to_owned()]).unwrap_err();
    assert!(
        alone.to_string().contains("no module `engine_pbr::"),
        "{alone}"
    );
    let module =
        compose_searching(&material, &source, &[dir.path().to_owned(), fixtures()]).unwrap();
    assert!(module.entry_points.iter().any(|e| e.name == "fragment"));
}

/// Modules that import each other are refused as a cycle, naming the chain, not as a module
/// that was not found.
#[test]
fn an_import_cycle_is_named_as_a_cycle() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(
        dir.path().join("a.wgsl"),
        "#define_import_path cyc_a\n#import cyc_b::g\nfn f() -> f32 { return g(); }\n",
    )
    .unwrap();
    std::fs::write(
        dir.path().join("b.wgsl"),
        "#define_import_path cyc_b\n#import cyc_a::f\nfn g() -> f32 { return f(); }\n",
    )
    .unwrap();
    let shader = dir.path().join("s.wgsl");
    let source = "#import cyc_a::f\n@fragment fn main() -> @location(0) vec4<f32> { return vec4<f32>(f()); }\n";
    std::fs::write(&shader, source).unwrap();
    let e = load_file(&shader).unwrap_err();
    let text = match &e {
        FrontError::Parse(d) => d.render(),
        other => other.to_string(),
    };
    assert!(text.contains("cycle"), "{text}");
    assert!(text.contains("cyc_a imports cyc_b imports cyc_a"), "{text}");
    assert!(!text.contains("was found"), "{text}");
}
