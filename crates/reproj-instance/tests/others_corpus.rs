//! Shaders written by others: fragment shaders from public, permissively licensed
//! repositories, kept as found. They are a set *kept aside* for checking, not part of the
//! repository: `tests/others/SOURCES.md` names each file's repository, path, commit and
//! license, so the set can be fetched again into `tests/others/{glsl,wgsl}/` (ignored by
//! git) or any folder `REPROJ_OTHERS_CORPUS` names. The test is ignored by default and run on
//! purpose: `cargo test -p reproj-instance --test others_corpus -- --ignored` (it fails when the set
//! is missing). Each file is loaded as `reproj nodes` loads it;
//! every fragment entry point is normalized and its nodes listed; the first cacheable node is
//! instanced (3pass) and written in every `--lang`, and the passes are checked by their own tools:
//! the WGSL by `tint`, the SPIR-V by `spirv-val`, the GLSL by `glslangValidator` (the HLSL and MSL
//! are written by naga's writers; no validator for them is installed here).
//!
//! The rows are compared with the committed snapshot `tests/others/snapshots/others_corpus__table.snap`
//! at the top of the repository (insta: `INSTA_UPDATE=always`
//! accepts a change in place, to review with `git diff`; `tests/README.md`); no file may
//! panic or report an internal error, and the parse
//! rates must stay at their targets (GLSL ≥ 85 %, WGSL ≥ 95 %). Needs glslangValidator, tint
//! and spirv-val (`scripts/ensure-tools.sh`): a missing one fails the test.

use std::collections::BTreeMap;
use std::panic::{AssertUnwindSafe, catch_unwind};
use std::path::{Path, PathBuf};
use std::process::Command;

use reproj_front::{Loaded, load_file_as};
use reproj_instance::backends::{OutputLang, Outputs};
use reproj_instance::{InstanceOptions, NodeSelector, instance, write_variant_in};
use serde_json::{Value, json};

/// The parse-rate targets, in percent: what a user of another project's shaders may expect.
const GLSL_TARGET: f64 = 85.0;
const WGSL_TARGET: f64 = 95.0;

/// Where the shaders are: `REPROJ_OTHERS_CORPUS`, else `tests/others`.
fn others() -> PathBuf {
    std::env::var_os("REPROJ_OTHERS_CORPUS").map_or_else(
        || PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../tests/others"),
        PathBuf::from,
    )
}

/// Whether `tool` can be started (tint has no `--version`: any exit status will do).
fn installed(tool: &str) -> bool {
    Command::new(tool).arg("--help").output().is_ok()
}

/// The corpus files of one language, sorted.
fn files(lang: &str, ext: &str) -> Vec<PathBuf> {
    let mut files: Vec<PathBuf> = std::fs::read_dir(others().join(lang))
        .unwrap_or_else(|e| panic!("tests/others/{lang}: {e}"))
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == ext))
        .collect();
    files.sort();
    files
}

/// `tool args file`'s failure, as one short line, or `None` when it accepts the file.
fn rejects(tool: &str, args: &[&str], file: &Path) -> Option<String> {
    let out = match Command::new(tool).args(args).arg(file).output() {
        Ok(out) => out,
        Err(e) => return Some(format!("{tool} did not run: {e}")),
    };
    if out.status.success() {
        return None;
    }
    let text =
        String::from_utf8_lossy(&out.stdout).into_owned() + &String::from_utf8_lossy(&out.stderr);
    let first = text
        .lines()
        .map(str::trim)
        .find(|l| !l.is_empty())
        .unwrap_or("no message");
    // Without the temporary directory, so that the table does not change from run to run.
    let dir = file
        .parent()
        .map(|d| format!("{}/", d.display()))
        .unwrap_or_default();
    Some(format!("{tool}: {}", first.replace(&dir, "")))
}

/// Every pass file of the variant in `dir` through its language's validator: the failures.
fn validate_outputs(dir: &Path) -> Vec<String> {
    let mut names: Vec<PathBuf> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .collect();
    names.sort();
    let mut failures = Vec::new();
    for file in names {
        let ext = file.extension().and_then(|e| e.to_str()).unwrap_or("");
        let failure = match ext {
            "wgsl" => rejects("tint", &["--format", "wgsl", "-o", "/dev/null"], &file),
            "spv" => rejects("spirv-val", &[], &file),
            "frag" => rejects("glslangValidator", &["-S", "frag"], &file),
            _ => None,
        };
        if let Some(f) = failure {
            let name = file.file_name().unwrap().to_string_lossy();
            failures.push(format!("{name}: {f}"));
        }
    }
    failures
}

/// A front-end error's text without the file's (absolute) path.
fn message(e: &dyn std::fmt::Display, path: &Path, name: &str) -> String {
    e.to_string().replace(&path.display().to_string(), name)
}

/// One fragment entry point's row: its nodes, and the first cacheable node's variant.
fn measure_entry(shader: &reproj_front::Shader, entry: Option<&str>, name: &str) -> Value {
    let loaded = match Loaded::new(shader.clone(), entry) {
        Ok(l) => l,
        Err(e) => return json!({"normalizes": false, "error": message(&e, &shader.path, name)}),
    };
    let cacheable: Vec<u32> = loaded.table.cacheable().map(|n| n.id).collect();
    let mut row = json!({
        "normalizes": true,
        "nodes": loaded.table.nodes.len(),
        "cacheable": cacheable.len(),
    });
    let Some(&first) = cacheable.first() else {
        return row;
    };
    row["variant_node"] = json!(first);
    let variant = instance(
        &loaded.shader,
        &loaded.norm,
        &loaded.table,
        NodeSelector::Id(first),
        &InstanceOptions::default(),
    );
    let variant = match variant {
        Ok(v) => v,
        Err(e) => {
            row["variant"] = json!(format!("instance: {e}"));
            return row;
        }
    };
    let dir = tempfile::tempdir().unwrap();
    let langs = [
        OutputLang::Glsl,
        OutputLang::Hlsl,
        OutputLang::Msl,
        OutputLang::SpirV,
    ];
    if let Err(e) = write_variant_in(&variant, dir.path(), &Outputs::langs(&langs)) {
        row["variant"] = json!(format!("write: {e}"));
        return row;
    }
    let failures = validate_outputs(dir.path());
    row["variant"] = if failures.is_empty() {
        json!("validates")
    } else {
        json!(failures)
    };
    row
}

/// One file's row: whether it loads, and each fragment entry point's row.
fn measure(path: &Path) -> Value {
    let name = path.file_name().unwrap().to_string_lossy().into_owned();
    let shader = match load_file_as(path, None) {
        Ok(s) => s,
        Err(e) => return json!({"parses": false, "error": message(&e, path, &name)}),
    };
    let entries: Vec<String> = shader
        .module
        .entry_points
        .iter()
        .filter(|ep| ep.stage == naga::ShaderStage::Fragment)
        .map(|ep| ep.name.clone())
        .collect();
    // With one fragment entry point the CLI needs no `--entry`: measure it as the CLI loads it.
    let rows: BTreeMap<String, Value> = match entries.as_slice() {
        [one] => [(one.clone(), measure_entry(&shader, None, &name))].into(),
        _ => entries
            .iter()
            .map(|e| (e.clone(), measure_entry(&shader, Some(e), &name)))
            .collect(),
    };
    let parses = !rows.is_empty() && rows.values().all(|r| r["normalizes"] == true);
    json!({"parses": parses, "entries": rows})
}

/// The row, or the panic it raised (a failure of the test, recorded first so every file runs).
fn measure_guarded(path: &Path) -> Value {
    match catch_unwind(AssertUnwindSafe(|| measure(path))) {
        Ok(row) => row,
        Err(payload) => {
            let text = payload
                .downcast_ref::<String>()
                .cloned()
                .or_else(|| payload.downcast_ref::<&str>().map(|s| s.to_string()))
                .unwrap_or_default();
            json!({"parses": false, "panic": text})
        }
    }
}

fn rate(rows: &BTreeMap<String, Value>, prefix: &str) -> (usize, usize) {
    let of: Vec<&Value> = rows
        .iter()
        .filter(|(k, _)| k.starts_with(prefix))
        .map(|(_, v)| v)
        .collect();
    let parsed = of.iter().filter(|v| v["parses"] == true).count();
    (parsed, of.len())
}

#[test]
#[ignore = "needs the kept-aside shaders of tests/others/SOURCES.md: run with -- --ignored"]
fn shaders_written_by_others_parse_instance_and_validate() {
    let tools = ["glslangValidator", "spirv-val", "tint"];
    for t in tools {
        assert!(
            installed(t),
            "{t} is missing (scripts/ensure-tools.sh installs it)"
        );
    }
    // Asked for on purpose: without the shaders the test fails.
    assert!(
        others().join("glsl").is_dir() && others().join("wgsl").is_dir(),
        "{}/{{glsl,wgsl}} is missing: fetch the files SOURCES.md lists (or set REPROJ_OTHERS_CORPUS)",
        others().display()
    );
    let glsl = files("glsl", "frag");
    let wgsl = files("wgsl", "wgsl");
    assert!(
        glsl.len() + wgsl.len() >= 40,
        "{} + {} shaders written by others (the set must hold at least 40)",
        glsl.len(),
        wgsl.len()
    );
    let measured: BTreeMap<String, Value> = glsl
        .iter()
        .map(|p| {
            (
                format!("glsl/{}", p.file_name().unwrap().to_string_lossy()),
                p,
            )
        })
        .chain(wgsl.iter().map(|p| {
            (
                format!("wgsl/{}", p.file_name().unwrap().to_string_lossy()),
                p,
            )
        }))
        .map(|(k, p)| (k, measure_guarded(p)))
        .collect();

    let (glsl_ok, glsl_n) = rate(&measured, "glsl/");
    let (wgsl_ok, wgsl_n) = rate(&measured, "wgsl/");
    let pct = |ok: usize, n: usize| 100.0 * ok as f64 / n.max(1) as f64;
    eprintln!(
        "shaders written by others: GLSL {glsl_ok}/{glsl_n} parse ({:.1} %), WGSL {wgsl_ok}/{wgsl_n} ({:.1} %)",
        pct(glsl_ok, glsl_n),
        pct(wgsl_ok, wgsl_n)
    );

    let text = serde_json::to_string(&measured).unwrap();
    for (name, row) in &measured {
        assert!(row.get("panic").is_none(), "{name} panicked: {row}");
    }
    assert!(
        !text.contains("internal error"),
        "an internal error: {}",
        serde_json::to_string_pretty(&measured).unwrap()
    );

    let table = serde_json::to_string_pretty(&measured).unwrap();
    // The table stays beside SOURCES.md even when REPROJ_OTHERS_CORPUS points elsewhere.
    let snapshots = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../tests/others/snapshots");
    insta::with_settings!({snapshot_path => snapshots}, {
        insta::assert_snapshot!("table", table);
    });
    assert!(
        pct(glsl_ok, glsl_n) >= GLSL_TARGET,
        "GLSL parse rate {glsl_ok}/{glsl_n}"
    );
    assert!(
        pct(wgsl_ok, wgsl_n) >= WGSL_TARGET,
        "WGSL parse rate {wgsl_ok}/{wgsl_n}"
    );
}
