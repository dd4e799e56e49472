//! Shaders written by others: fragment shaders from public, permissively licensed
//! repositories, kept as found. They are a set *kept aside* for checking, not part of the
//! repository: `tests/others/SOURCES.md` names each file's repository, path, commit and
//! license, and `scripts/fetch-others.sh` fetches them into `tests/others/{glsl,wgsl,imports}/`
//! (ignored by git) or any folder `REPROJ_OTHERS_CORPUS` names. The test is ignored by default
//! and run on purpose: `cargo test -p reproj-instance --test integration others_corpus:: --
//! --ignored` (it fails when the set is missing).
//!
//! Each file is read as `reproj nodes` reads it with the options a user of its engine would pass
//! (`tests/others/options.json`: shader defs, a defs preset, import paths, include folders, per
//! project; defs the engine's own pipeline always sets for one file or entry point); every
//! `@fragment` entry point of the file's text counts, those its preprocessor leaves out
//! included. Each entry point is normalized, its nodes listed, the bind groups it uses noted,
//! and its first cacheable node instanced (3pass) and written as WGSL, SPIR-V and GLSL, every
//! file through every validator of its target (`validate.rs`).
//!
//! The rows are compared with the committed snapshot
//! `tests/others/snapshots/integration__others_corpus__table.snap` at the top of the repository
//! (insta: `INSTA_UPDATE=always` accepts a change in place, to review with `git diff`;
//! `tests/README.md`). No file may panic or report an internal error, every file written must
//! validate, every entry point that does not parse must have a reason in `options.json`, and the
//! parse rate must reach its target (80 % of the entry points). Needs naga, tint, spirv-val and
//! glslangValidator: a missing one fails the test.

#[path = "others_corpus/options.rs"]
mod options;
#[path = "others_corpus/validate.rs"]
mod validate;

use std::collections::BTreeMap;
use std::panic::{AssertUnwindSafe, catch_unwind};
use std::path::{Path, PathBuf};

use reproj_front::{Lang, Loaded, ShaderInput, load_file_with};
use reproj_instance::{InstanceOptions, NodeSelector, instance};
use serde_json::{Value, json};

use options::{Options, fragment_names};

/// The parse-rate target, in percent of the entry points: what a user of another project's
/// shaders may expect.
const PARSE_TARGET: f64 = 80.0;

/// Where the shaders are: `REPROJ_OTHERS_CORPUS`, else `tests/others`.
fn others() -> PathBuf {
    std::env::var_os("REPROJ_OTHERS_CORPUS").map_or_else(repo_others, PathBuf::from)
}

/// `tests/others` of this repository: `SOURCES.md`, `options.json` and the snapshot.
fn repo_others() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../tests/others")
}

/// The corpus files of one language, sorted, as `glsl/x.frag` or `wgsl/x.wgsl`.
fn files(lang: &str, ext: &str) -> Vec<String> {
    let mut files: Vec<String> = std::fs::read_dir(others().join(lang))
        .unwrap_or_else(|e| panic!("tests/others/{lang}: {e}"))
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == ext))
        .map(|p| format!("{lang}/{}", p.file_name().unwrap().to_string_lossy()))
        .collect();
    files.sort();
    files
}

/// A front-end error's text without the set's (absolute) folder.
fn message(e: &dyn std::fmt::Display) -> String {
    e.to_string()
        .replace(&format!("{}/", others().display()), "")
}

/// The bind groups the entry point `index` of `shader` uses.
fn groups(shader: &reproj_front::Shader, index: usize) -> Vec<u32> {
    let info = shader.info.get_entry_point(index);
    let mut groups: Vec<u32> = shader
        .module
        .global_variables
        .iter()
        .filter(|(h, _)| !info[*h].is_empty())
        .filter_map(|(_, g)| g.binding.as_ref().map(|b| b.group))
        .collect();
    groups.sort_unstable();
    groups.dedup();
    groups
}

/// One fragment entry point's row: its groups and nodes, and the first cacheable node's variant
/// written and validated.
fn measure_entry(shader: &reproj_front::Shader, entry: &str, only: bool) -> Value {
    let index = shader
        .module
        .entry_points
        .iter()
        .position(|ep| ep.name == entry && ep.stage == naga::ShaderStage::Fragment)
        .expect("a fragment entry point of the module");
    let mut row = json!({"reads": true, "groups": groups(shader, index)});
    // With one fragment entry point the CLI needs no `--entry`: measure it as the CLI loads it.
    let loaded = match Loaded::new(shader.clone(), (!only).then_some(entry)) {
        Ok(l) => l,
        Err(e) => {
            row["parses"] = json!(false);
            row["error"] = json!(message(&e));
            return row;
        }
    };
    let cacheable: Vec<u32> = loaded.table.cacheable().map(|n| n.id).collect();
    row["parses"] = json!(true);
    row["nodes"] = json!(loaded.table.nodes.len());
    row["cacheable"] = json!(cacheable.len());
    let Some(&first) = cacheable.first() else {
        return row;
    };
    row["variant_node"] = json!(first);
    match instance(
        &loaded.shader,
        &loaded.norm,
        &loaded.table,
        NodeSelector::Id(first),
        &InstanceOptions::default(),
    ) {
        Ok(variant) => {
            let original_fails = validate::original_fails(&loaded.shader);
            if !original_fails.is_empty() {
                row["original_fails"] = json!(original_fails);
            }
            row["variant"] = validate::write_and_validate(&variant, &original_fails);
        }
        Err(e) => row["variant"] = json!(format!("instance: {e}")),
    }
    row
}

/// The shaders read from one file, each with the input it was read with.
type Reads = Vec<(ShaderInput, Result<reproj_front::Shader, String>)>;

/// The index in `reads` of `path` read with `input`, read now if it was not yet.
fn read(reads: &mut Reads, path: &Path, input: ShaderInput) -> usize {
    if let Some(i) = reads.iter().position(|(x, _)| *x == input) {
        return i;
    }
    let shader = load_file_with(path, None, &input).map_err(|e| message(&e));
    reads.push((input, shader));
    reads.len() - 1
}

/// One file's row: each fragment entry point of its text, read with `options`.
fn measure(file: &str, options: &Options) -> Value {
    let path = others().join(file);
    let text = std::fs::read_to_string(&path).unwrap();
    let lang = Lang::from_path(&path);
    let mut names = match lang {
        Some(Lang::Glsl) => vec!["main".to_owned()],
        _ => fragment_names(&text),
    };
    // The inputs the entry points are read with, each shader read once per input.
    let mut reads: Reads = Vec::new();
    let base = read(&mut reads, &path, options.input(file, None, &others()));
    if let Ok(shader) = &reads[base].1 {
        for ep in &shader.module.entry_points {
            if ep.stage == naga::ShaderStage::Fragment && !names.contains(&ep.name) {
                names.push(ep.name.clone());
            }
        }
    }
    let mut entries = BTreeMap::new();
    for name in &names {
        let at = read(
            &mut reads,
            &path,
            options.input(file, Some(name), &others()),
        );
        let row = match &reads[at].1 {
            Err(e) => json!({"reads": false, "parses": false, "error": e}),
            Ok(shader) => {
                let fragments = shader
                    .module
                    .entry_points
                    .iter()
                    .filter(|ep| ep.stage == naga::ShaderStage::Fragment);
                let only = fragments.clone().count() == 1;
                if fragments.clone().any(|ep| ep.name == *name) {
                    measure_entry(shader, name, only)
                } else {
                    let hidden = shader.hidden_entries.iter().find(|h| h.name == *name);
                    json!({"reads": false, "parses": false, "error": match hidden {
                        Some(h) => format!("left out by the defs given: {h}"),
                        None if lang == Some(Lang::Glsl) => "no fragment entry point".to_owned(),
                        None => "not an entry point of the module read".to_owned(),
                    }})
                }
            }
        };
        entries.insert(name.clone(), row);
    }
    let mut row = json!({"project": options.project(file).name, "entries": entries});
    if names.is_empty() {
        row["error"] = json!("no @fragment entry point in the text");
    }
    row
}

/// The row, or the panic it raised (a failure of the test, recorded first so every file runs).
fn measure_guarded(file: &str, options: &Options) -> Value {
    match catch_unwind(AssertUnwindSafe(|| measure(file, options))) {
        Ok(row) => row,
        Err(payload) => {
            let text = payload
                .downcast_ref::<String>()
                .cloned()
                .or_else(|| payload.downcast_ref::<&str>().map(|s| s.to_string()))
                .unwrap_or_default();
            json!({"panic": text})
        }
    }
}

/// Every entry-point row with its file's name and project.
fn entry_rows(measured: &BTreeMap<String, Value>) -> Vec<(&str, &str, &str, &Value)> {
    measured
        .iter()
        .flat_map(|(file, row)| {
            let project = row["project"].as_str().unwrap_or("?");
            row["entries"]
                .as_object()
                .into_iter()
                .flatten()
                .map(move |(e, r)| (file.as_str(), project, e.as_str(), r))
        })
        .collect()
}

/// Every validator failure in the table, as `file#entry: failure`.
fn invalid_files(measured: &BTreeMap<String, Value>) -> Vec<String> {
    let mut out = Vec::new();
    for (file, _, entry, row) in entry_rows(measured) {
        for lang in ["wgsl", "spirv", "glsl"] {
            if let Some(failures) = row["variant"][lang].as_array() {
                out.extend(failures.iter().map(|f| format!("{file}#{entry}: {f}")));
            }
        }
    }
    out
}

/// The summary printed with `--nocapture`: per project, per reason, the validators' counts and
/// the entry points on three or four bind groups.
fn summary(measured: &BTreeMap<String, Value>, options: &Options) -> String {
    let rows = entry_rows(measured);
    let mut by_project: BTreeMap<&str, (usize, usize, usize)> = BTreeMap::new();
    let mut by_reason: BTreeMap<String, usize> = BTreeMap::new();
    let mut checks = 0;
    let mut groups = Vec::new();
    for (file, project, entry, row) in &rows {
        let p = by_project.entry(project).or_default();
        p.2 += 1;
        if row["reads"] == true {
            p.1 += 1;
        }
        if row["parses"] == true {
            p.0 += 1;
        } else {
            *by_reason
                .entry(
                    options
                        .reason(file)
                        .unwrap_or("(no reason given)")
                        .to_owned(),
                )
                .or_default() += 1;
        }
        for lang in ["wgsl", "spirv", "glsl"] {
            if let Some(n) = row["variant"][lang].as_str().and_then(options::checks_in) {
                checks += n;
            }
        }
        let used = row["groups"].as_array().map_or(0, Vec::len);
        if row["parses"] == true && used >= 3 {
            let accepted = if row["variant"].is_object() {
                "instanced".to_owned()
            } else {
                row["variant"]
                    .as_str()
                    .unwrap_or("no cacheable node")
                    .to_owned()
            };
            groups.push(format!(
                "  {file}#{entry}: groups {}: {accepted}",
                row["groups"]
            ));
        }
    }
    let mut s = String::new();
    s += "per project: entry points read (composed, validated by naga), normalized (parse)\n";
    for (project, (ok, read, n)) in &by_project {
        s += &format!("  {project}: {read}/{n} read, {ok}/{n} parse\n");
    }
    s += "why the others do not:\n";
    for (reason, n) in &by_reason {
        s += &format!("  {n:3}  {reason}\n");
    }
    s += &format!(
        "validator checks passed: {checks}; failed: {}\n",
        invalid_files(measured).len()
    );
    s += "entry points on three or four bind groups:\n";
    s += &groups.join("\n");
    s
}

#[test]
#[ignore = "needs the kept-aside shaders of tests/others/SOURCES.md: run with -- --ignored"]
fn shaders_written_by_others_parse_instance_and_validate() {
    for v in &validate::VALIDATORS {
        assert!(
            validate::installed(v.tool),
            "{} is missing (scripts/ensure-tools.sh installs glslang and spirv-tools; naga: cargo install naga-cli; tint: from Dawn)",
            v.tool
        );
    }
    // Asked for on purpose: without the shaders the test fails.
    assert!(
        others().join("glsl").is_dir() && others().join("wgsl").is_dir(),
        "{}/{{glsl,wgsl}} is missing: run scripts/fetch-others.sh (or set REPROJ_OTHERS_CORPUS)",
        others().display()
    );
    let options = Options::read(&repo_others().join("options.json"));
    let all: Vec<String> = files("glsl", "frag")
        .into_iter()
        .chain(files("wgsl", "wgsl"))
        .collect();
    let measured: BTreeMap<String, Value> = all
        .iter()
        .map(|f| (f.clone(), measure_guarded(f, &options)))
        .collect();

    for (name, row) in &measured {
        assert!(row.get("panic").is_none(), "{name} panicked: {row}");
    }
    let text = serde_json::to_string(&measured).unwrap();
    assert!(
        !text.contains("internal error"),
        "an internal error: {}",
        serde_json::to_string_pretty(&measured).unwrap()
    );

    let rows = entry_rows(&measured);
    let parsed = rows.iter().filter(|r| r.3["parses"] == true).count();
    let projects: std::collections::BTreeSet<&str> = rows.iter().map(|r| r.1).collect();
    let pct = 100.0 * parsed as f64 / rows.len().max(1) as f64;
    eprintln!(
        "shaders written by others: {parsed}/{} entry points parse ({pct:.1} %), {} files, {} projects\n{}",
        rows.len(),
        measured.len(),
        projects.len(),
        summary(&measured, &options)
    );

    let table = serde_json::to_string_pretty(&measured).unwrap();
    // The table stays beside SOURCES.md even when REPROJ_OTHERS_CORPUS points elsewhere.
    insta::with_settings!({snapshot_path => repo_others().join("snapshots")}, {
        insta::assert_snapshot!("table", table);
    });
    let unexplained: Vec<&str> = rows
        .iter()
        .filter(|r| r.3["parses"] != true && options.reason(r.0).is_none())
        .map(|r| r.0)
        .collect();
    assert!(
        unexplained.is_empty(),
        "entry points that do not parse with no reason in options.json: {unexplained:?}"
    );
    let invalid = invalid_files(&measured);
    assert!(
        invalid.is_empty(),
        "files that do not validate: {invalid:#?}"
    );
    assert!(
        rows.len() >= 150 && projects.len() >= 8,
        "the set must hold at least 150 entry points from 8 projects"
    );
    assert!(
        pct >= PARSE_TARGET,
        "parse rate {parsed}/{}: under {PARSE_TARGET} %",
        rows.len()
    );
}
