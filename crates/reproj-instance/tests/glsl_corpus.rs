//! Variants of Vulkan-style GLSL shaders (`tests/corpus/shaders/glsl/`, read through glslang with their
//! combined samplers split): every strategy's passes validate in naga and are written in every
//! `--lang`; the SPIR-V passes pass `spirv-val` and the GLSL passes compile with
//! `glslangValidator`. Needs glslang (and spirv-val): under `CI` a missing tool fails the test,
//! elsewhere it says what it skipped.

use std::path::{Path, PathBuf};
use std::process::Command;

use reproj_instance::backends::{OutputLang, Outputs, pass_file_in};
use reproj_instance::{InstanceOptions, NodeSelector, Strategy, instance, write_variant_in};

fn corpus(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../../tests/corpus/shaders/glsl")
        .join(name)
}

/// Whether `tool` runs; under CI a missing tool fails.
fn installed(tool: &str) -> bool {
    let ok = Command::new(tool)
        .arg("--version")
        .output()
        .is_ok_and(|o| o.status.success());
    if !ok {
        assert!(
            std::env::var_os("CI").is_none(),
            "{tool} is missing (scripts/ensure-tools.sh installs it)"
        );
        eprintln!("SKIPPED: {tool} is not installed");
    }
    ok
}

fn check(tool: &str, args: &[&str], file: &Path) {
    let out = Command::new(tool).args(args).arg(file).output().unwrap();
    assert!(
        out.status.success(),
        "{tool} {}: {}{}",
        file.display(),
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr)
    );
}

#[test]
fn glsl_corpus_variants_validate_in_every_language() {
    if !installed("glslangValidator") {
        return;
    }
    let spirv_val = installed("spirv-val");
    let langs = [
        OutputLang::Glsl,
        OutputLang::Hlsl,
        OutputLang::Msl,
        OutputLang::SpirV,
    ];
    for name in [
        "normal_map.frag",
        "material_array.frag",
        "terrain_layers.frag",
        "shadow_compare.frag",
    ] {
        let loaded = reproj_front::load(&corpus(name), None, &Default::default())
            .unwrap_or_else(|e| panic!("{name}: {e}"));
        assert!(!loaded.shader.split_samplers.is_empty(), "{name}");
        for strategy in Strategy::ALL {
            let opts = InstanceOptions {
                strategy,
                block: strategy.default_block(),
                ..Default::default()
            };
            let v = instance(
                &loaded.shader,
                &loaded.norm,
                &loaded.table,
                NodeSelector::Root,
                &opts,
            )
            .unwrap_or_else(|e| panic!("{name} {strategy}: {e}"));
            // naga's GLSL writer has no binding arrays (`sampler2D textures[4]`): refused by name.
            let arrays = name == "material_array.frag";
            let langs: Vec<OutputLang> = langs
                .into_iter()
                .filter(|&l| !(arrays && l == OutputLang::Glsl))
                .collect();
            if arrays {
                let e = write_variant_in(
                    &v,
                    &std::env::temp_dir().join("never-written"),
                    &Outputs::langs(&[OutputLang::Glsl]),
                )
                .unwrap_err();
                assert!(
                    e.to_string()
                        .contains("`textures` is a binding array, which naga's GLSL writer"),
                    "{e}"
                );
            }
            let dir = tempfile::tempdir().unwrap();
            write_variant_in(&v, dir.path(), &Outputs::langs(&langs))
                .unwrap_or_else(|e| panic!("{name} {strategy}: {e}"));
            for p in &v.passes {
                reproj_front::validator()
                    .validate(&p.module)
                    .unwrap_or_else(|e| panic!("{name} {strategy}: {e}"));
                let spv = dir.path().join(pass_file_in(p, OutputLang::SpirV));
                if spirv_val {
                    check("spirv-val", &[], &spv);
                }
                if !arrays {
                    let frag = dir.path().join(pass_file_in(p, OutputLang::Glsl));
                    check("glslangValidator", &["-S", "frag"], &frag);
                }
            }
        }
    }
}
