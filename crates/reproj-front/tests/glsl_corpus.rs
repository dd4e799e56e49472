//! The GLSL corpus (`tests/corpus/shaders/glsl/`): Vulkan-style GLSL 450 fragment shaders (combined
//! image samplers, push constants with `layout(offset = N)`, specialization constants, uniform
//! blocks), read through glslang. Each must parse and yield nodes; the counts are compared with the
//! committed snapshot `tests/corpus/snapshots/integration__glsl_corpus__table.snap` at the top of
//! the repository (insta: `INSTA_UPDATE=always` accepts a change in place, to review with `git
//! diff`; `tests/README.md`). Needs `glslangValidator` (`scripts/ensure-tools.sh`): without it
//! these tests fail under `CI` and say they skipped otherwise.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use reproj_front::{Lang, LoadOptions, load};
use serde_json::{Value, json};

fn corpus() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../tests/corpus/shaders/glsl")
}

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

fn shaders() -> Vec<PathBuf> {
    let mut files: Vec<PathBuf> = std::fs::read_dir(corpus())
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "frag"))
        .collect();
    files.sort();
    files
}

fn stem(p: &Path) -> String {
    p.file_stem().unwrap().to_str().unwrap().to_owned()
}

/// One shader's row: node counts and the samplers split, or the error.
fn measure(path: &Path) -> Value {
    match load(path, None, &LoadOptions::default()) {
        Ok(l) => {
            assert_eq!(l.shader.lang, Lang::Glsl);
            json!({
                "parses": true,
                "nodes": l.table.nodes.len(),
                "cacheable": l.table.cacheable().count(),
                "split_samplers": l.shader.split_samplers.len(),
            })
        }
        Err(e) => {
            // The message without the file's (absolute) path.
            let text = e
                .to_string()
                .replace(&format!("{}", path.display()), &stem(path));
            json!({"parses": false, "error": text})
        }
    }
}

#[test]
fn every_corpus_shader_parses_and_matches_the_table() {
    if !glslang_here("glsl corpus") {
        return;
    }
    let files = shaders();
    assert!(files.len() >= 30, "{} GLSL corpus shaders", files.len());
    let measured: BTreeMap<String, Value> = files.iter().map(|p| (stem(p), measure(p))).collect();
    let parsed = measured.values().filter(|v| v["parses"] == true).count();
    eprintln!("{parsed} of {} GLSL corpus shaders parse", measured.len());
    let table = serde_json::to_string_pretty(&measured).unwrap();
    let snapshots = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../tests/corpus/snapshots");
    insta::with_settings!({snapshot_path => snapshots}, {
        insta::assert_snapshot!("table", table);
    });
    for (name, row) in &measured {
        assert_eq!(row["parses"], true, "{name}: {row}");
        assert!(row["nodes"].as_u64().unwrap() > 0, "{name}: no nodes");
    }
}
