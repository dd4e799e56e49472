//! Engine shaders as they sit in their repositories: naga_oil shader defs (`#ifdef`, `#if N > 2`),
//! asset-path imports found under an import path, entry points behind an `#ifdef`, and the
//! warning on a def nobody reads (`tests/fixtures/defs/`).

use std::path::{Path, PathBuf};

use reproj_front::parse::FrontError;
use reproj_front::{
    DefValue, DefsPreset, InputWarning, Lang, LoadOptions, ShaderInput, load, load_file_with,
};

fn fixtures() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fixtures/defs")
}

/// Input with these defs.
fn defs(list: &[(&str, DefValue)]) -> ShaderInput {
    ShaderInput {
        defs: list.iter().map(|(n, v)| ((*n).to_owned(), *v)).collect(),
        ..Default::default()
    }
}

/// The composed WGSL of `name` read with `input`.
fn composed(name: &str, input: &ShaderInput) -> String {
    load_file_with(&fixtures().join(name), Some(Lang::Wgsl), input)
        .unwrap_or_else(|e| panic!("{e}"))
        .source
}

/// `#ifdef FOO` picks one of two outputs, `#if LEVELS > 2` one of two shadings: with and without
/// the defs the composed shader is the one branch or the other.
#[test]
fn defs_choose_the_branches_of_ifdef_and_if() {
    let three = ("LEVELS", DefValue::UInt(3));
    let with = composed(
        "choice.wgsl",
        &defs(&[("FOO", DefValue::Bool(true)), three]),
    );
    assert!(with.contains("sin(") && !with.contains("cos("), "{with}");
    assert!(with.contains("floor(") && !with.contains("sqrt("), "{with}");

    let one = ("LEVELS", DefValue::UInt(1));
    let without = composed("choice.wgsl", &defs(&[one]));
    assert!(
        without.contains("cos(") && !without.contains("sin("),
        "{without}"
    );
    assert!(
        without.contains("sqrt(") && !without.contains("floor("),
        "{without}"
    );

    // A comparison with a def not given is refused at its line, naming the def.
    let e = load_file_with(&fixtures().join("choice.wgsl"), None, &defs(&[])).unwrap_err();
    let FrontError::Parse(d) = &e else {
        panic!("expected a parse error, got {e}")
    };
    let text = d.render();
    assert!(
        text.contains("shader def `LEVELS`, which is not defined"),
        "{text}"
    );
    assert!(text.contains("choice.wgsl:12:1"), "{text}");

    // A negative value compares as an integer too.
    let negative = composed("choice.wgsl", &defs(&[("LEVELS", DefValue::Int(-1))]));
    assert!(negative.contains("sqrt("), "{negative}");
}

/// The nodes differ with the defs: `load` passes them through [`LoadOptions`].
#[test]
fn load_options_carry_the_defs() {
    let path = fixtures().join("choice.wgsl");
    let options = |foo: bool| LoadOptions {
        input: defs(if foo {
            &[("FOO", DefValue::Bool(true)), ("LEVELS", DefValue::UInt(3))]
        } else {
            &[("LEVELS", DefValue::UInt(3))]
        }),
        ..Default::default()
    };
    let a = load(&path, None, &options(true)).unwrap();
    let b = load(&path, None, &options(false)).unwrap();
    assert!(a.table.nodes.iter().any(|n| n.text.starts_with("sin(")));
    assert!(b.table.nodes.iter().any(|n| n.text.starts_with("cos(")));
}

/// `#import "shaders/noise.wgsl"::hash` is the file at that path under an import path, read with
/// the importer's defs; without the import path it is refused, naming the module and the folders
/// searched.
#[test]
fn an_asset_path_import_is_found_under_an_import_path() {
    let path = fixtures().join("asset_import.wgsl");
    let input = |fast: bool| ShaderInput {
        import_paths: vec![fixtures().join("assets")],
        ..defs(if fast {
            &[("FAST_HASH", DefValue::Bool(true))]
        } else {
            &[]
        })
    };
    let slow = load_file_with(&path, None, &input(false)).unwrap_or_else(|e| panic!("{e}"));
    assert!(slow.source.contains("sin("), "{}", slow.source);
    let fast = load_file_with(&path, None, &input(true)).unwrap_or_else(|e| panic!("{e}"));
    assert!(!fast.source.contains("sin("), "{}", fast.source);
    // FAST_HASH is read by the imported module: no warning.
    assert_eq!(fast.warnings, []);

    let e = load_file_with(&path, None, &ShaderInput::default()).unwrap_err();
    let FrontError::Parse(d) = &e else {
        panic!("expected a parse error, got {e}")
    };
    let text = d.render();
    assert!(
        text.contains("no module \"shaders/noise.wgsl\" was found"),
        "{text}"
    );
    assert!(text.contains("asset_import.wgsl:3:"), "{text}");
    assert!(
        text.contains("searched: ") && text.contains("fixtures/defs"),
        "{text}"
    );
}

/// A fragment entry point behind `#ifdef PREPASS_FRAGMENT`: without the def the error names the
/// directive, its line and the def to pass; with it the shader loads.
#[test]
fn an_entry_point_behind_ifdef_names_the_def_that_exposes_it() {
    let path = fixtures().join("prepass.wgsl");
    let options = |input| LoadOptions {
        input,
        ..Default::default()
    };
    let e = load(&path, None, &options(ShaderInput::default())).unwrap_err();
    assert!(matches!(e, FrontError::NoFragmentEntry { .. }), "{e}");
    let text = e.to_string();
    assert!(
        text.contains(
            "no @fragment entry point with the defs given; `#ifdef PREPASS_FRAGMENT` at line 4 \
             guards `@fragment fn fragment`: pass --def PREPASS_FRAGMENT"
        ),
        "{text}"
    );
    let named = load(&path, Some("fragment"), &options(ShaderInput::default())).unwrap_err();
    assert!(
        named.to_string().contains("pass --def PREPASS_FRAGMENT"),
        "{named}"
    );

    let exposed = defs(&[("PREPASS_FRAGMENT", DefValue::Bool(true))]);
    let loaded = load(&path, None, &options(exposed)).unwrap();
    assert_eq!(loaded.table.entry, "fragment");
}

/// A def that no directive of the shader or its modules reads is a warning naming it; the defs
/// of a preset are not (an engine defines many that one shader does not read).
#[test]
fn a_def_nobody_reads_is_a_warning() {
    let path = fixtures().join("choice.wgsl");
    let input = ShaderInput {
        preset: Some(DefsPreset::Bevy),
        ..defs(&[
            ("FOOO", DefValue::Bool(true)),
            ("LEVELS", DefValue::UInt(2)),
        ])
    };
    let shader = load_file_with(&path, None, &input).unwrap();
    assert_eq!(
        shader.warnings,
        [InputWarning::UnreadDef {
            name: "FOOO".into(),
            path: path.clone()
        }]
    );
    assert!(shader.warnings[0].to_string().contains("`FOOO`"));

    // A plain WGSL shader reads no def at all.
    let plain = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fixtures/basic.wgsl");
    let shader = load_file_with(&plain, None, &defs(&[("FOO", DefValue::Bool(true))])).unwrap();
    assert_eq!(shader.warnings.len(), 1, "{:?}", shader.warnings);
}

/// GLSL takes the defs as macros (glslang's `-D`, or naga's GLSL front end where glslang is
/// missing), and a def no word of the shader names is a warning too.
#[test]
fn glsl_takes_the_defs_as_macros() {
    let path = fixtures().join("choice.frag");
    let wgsl = |input: &ShaderInput| {
        let shader = load_file_with(&path, None, input).unwrap_or_else(|e| panic!("{e}"));
        (shader.to_wgsl().unwrap().source, shader.warnings)
    };
    let (with, warnings) = wgsl(&defs(&[
        ("FOO", DefValue::Bool(true)),
        ("BAR", DefValue::UInt(2)),
    ]));
    assert!(with.contains("sin(") && !with.contains("cos("), "{with}");
    let names: Vec<String> = warnings
        .iter()
        .filter_map(|w| match w {
            InputWarning::UnreadDef { name, .. } => Some(name.clone()),
            _ => None,
        })
        .collect();
    assert_eq!(names, ["BAR"]);
    let (without, warnings) = wgsl(&ShaderInput::default());
    assert!(
        without.contains("cos(") && !without.contains("sin("),
        "{without}"
    );
    assert_eq!(warnings, []);
}

/// Bevy 0.19's view types size the rect lights by `#{MAX_RECT_LIGHTS}`: a material importing
/// them parses under `--defs-preset bevy`, and names the def without it.
#[test]
fn the_bevy_preset_sizes_the_rect_lights() {
    let path = fixtures().join("rect_lights.wgsl");
    let bevy = ShaderInput {
        preset: Some(DefsPreset::Bevy),
        ..Default::default()
    };
    let shader = load_file_with(&path, None, &bevy).unwrap_or_else(|e| panic!("{e}"));
    assert!(
        shader.source.contains("array<RectLight"),
        "{}",
        shader.source
    );
    assert!(load_file_with(&path, None, &ShaderInput::default()).is_err());
}

/// A shader and a module it imports written for an older naga, which read `binding_array`
/// without `enable wgpu_binding_array;`: both are read as if they enabled it, and the lines of
/// the shader stay where they were.
#[test]
fn binding_arrays_need_no_enable_directive() {
    let path = fixtures().join("binding_arrays.wgsl");
    let shader =
        load_file_with(&path, None, &ShaderInput::default()).unwrap_or_else(|e| panic!("{e}"));
    assert!(shader.source.contains("binding_array<texture_2d<f32>"));
    let loaded = load(&path, None, &LoadOptions::default()).unwrap_or_else(|e| panic!("{e}"));
    assert!(loaded.table.cacheable().count() > 0);
}

/// Blade's WGSL declares its resources without `@group`/`@binding` and an integer varying
/// without `@interpolate(flat)`: the resources take the free bindings of group 0, each named in a
/// warning, the varying is read as flat, and the shader loads with its nodes.
#[test]
fn unbound_resources_and_integer_varyings_are_filled_in() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fixtures/host/unbound.wgsl");
    let loaded = load(&path, None, &LoadOptions::default()).unwrap_or_else(|e| panic!("{e}"));
    let bound: Vec<(String, u32)> = loaded
        .shader
        .warnings
        .iter()
        .filter_map(|w| match w {
            InputWarning::BindingAssigned { name, binding, .. } => Some((name.clone(), *binding)),
            _ => None,
        })
        .collect();
    assert_eq!(
        bound,
        [
            ("globals".to_owned(), 0),
            ("sprite".to_owned(), 1),
            ("sprite_sampler".to_owned(), 2)
        ]
    );
    assert!(loaded.table.cacheable().count() > 0);
}

/// A module with a ray query (in an entry point reproj does not rebuild) is read and its fragment
/// entry point normalized; writing the whole module as WGSL, which naga's writer cannot do for a
/// ray query, is an error, not a panic.
#[test]
fn a_ray_query_elsewhere_in_the_module_is_no_panic() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fixtures/host/ray_query.wgsl");
    let loaded =
        load(&path, Some("fs_main"), &LoadOptions::default()).unwrap_or_else(|e| panic!("{e}"));
    assert!(loaded.table.cacheable().count() > 0);
    let err = reproj_front::write_wgsl(&loaded.shader.module, &loaded.shader.info).unwrap_err();
    assert!(err.to_string().contains("ray query"), "{err}");
}
