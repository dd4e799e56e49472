//! Engine shaders through the real binary: `--def`, `-I`/`--import-path` and their messages, on the
//! front end's fixtures (`crates/reproj-front/tests/fixtures/defs/`).

use crate::common;

use std::path::PathBuf;
use std::process::Command;

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../..")
}

const DEFS: &str = "crates/reproj-front/tests/fixtures/defs";

fn reproj(args: &[&str]) -> (i32, String, String) {
    let out = Command::new(env!("CARGO_BIN_EXE_reproj"))
        .args(args)
        .current_dir(root())
        .output()
        .expect("run reproj");
    (
        out.status.code().unwrap_or(-1),
        String::from_utf8_lossy(&out.stdout).into_owned(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

/// The texts of the nodes `reproj nodes --json` lists.
fn node_texts(out: &str) -> Vec<String> {
    let v: serde_json::Value = serde_json::from_str(out).unwrap();
    v["nodes"]
        .as_array()
        .unwrap()
        .iter()
        .map(|n| n["text"].as_str().unwrap().to_owned())
        .collect()
}

#[test]
fn nodes_takes_defs_and_warns_of_one_nobody_reads() {
    let shader = format!("{DEFS}/choice.wgsl");
    let (code, out, err) = reproj(&[
        "nodes",
        &shader,
        "--def",
        "FOO",
        "--def=LEVELS=3",
        "--json",
        "--all",
    ]);
    assert_eq!(code, 0, "{err}");
    let texts = node_texts(&out);
    assert!(texts.iter().any(|t| t.starts_with("sin(")), "{texts:?}");
    assert!(!err.contains("warning"), "{err}");

    let (code, out, err) = reproj(&[
        "nodes", &shader, "--def", "FOOO", "--def", "LEVELS=3", "--json", "--all",
    ]);
    assert_eq!(code, 0, "{err}");
    assert!(node_texts(&out).iter().any(|t| t.starts_with("cos(")));
    assert!(err.contains("`FOOO`") && err.contains("warning"), "{err}");

    // A bad def is refused at the door.
    let (code, _, err) = reproj(&["nodes", &shader, "--def", "LEVELS=1.5"]);
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("not a shader def value"), "{err}");
}

#[test]
fn an_import_path_finds_an_asset_import_and_a_hidden_entry_is_named() {
    let shader = format!("{DEFS}/asset_import.wgsl");
    let assets = format!("{DEFS}/assets");
    // `-I` serves WGSL imports and GLSL includes; `--import-path` (hidden) WGSL only.
    for flag in ["-I", "--import-path"] {
        let (code, _, err) = reproj(&["nodes", &shader, flag, &assets]);
        assert_eq!(code, 0, "{flag}: {err}");
    }
    let (code, _, err) = reproj(&["nodes", &shader]);
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("\"shaders/noise.wgsl\""), "{err}");

    let prepass = format!("{DEFS}/prepass.wgsl");
    let (code, _, err) = reproj(&["nodes", &prepass]);
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("pass --def PREPASS_FRAGMENT"), "{err}");
    // `session init` reads the shader the same way.
    let (code, out, err) = reproj(&["session", "init", &prepass, "--def", "PREPASS_FRAGMENT"]);
    assert_eq!(code, 0, "{err}");
    assert!(out.contains("\"tint\""), "{out}");
}

/// Every command that reads a shader takes the same input options (one flattened set: clap's
/// checks of each command run on its `--help`, which shows the visible ones).
#[test]
fn every_command_that_reads_a_shader_takes_the_input_options() {
    for command in [
        &["nodes"][..],
        &["instance"],
        &["analyze"],
        &["render"],
        &["bench"],
        &["session", "init"],
        &["compare"],
    ] {
        let mut args = command.to_vec();
        args.push("--help");
        let (code, out, err) = reproj(&args);
        if code == 2 && err.contains("gpu") {
            continue; // a build without the command
        }
        assert_eq!(code, 0, "{command:?}: {err}");
        for flag in ["--def", "--defs-preset", "--include-dir"] {
            assert!(out.contains(flag), "{command:?} has no {flag}: {out}");
        }
    }
}

/// `analyze --def … --import-path …` records them in the profile (`shader_input`, the folder
/// relative to the profile's), and `emit` reads the shader with them: its entry point is behind
/// `#ifdef PREPASS_FRAGMENT`, so `emit` fails without the profile's defs.
#[test]
fn analyze_records_the_input_options_and_emit_reads_the_shader_with_them() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    common::two_terms(dir, "plain.wgsl", "t.json");
    let plain = std::fs::read_to_string(dir.join("plain.wgsl")).unwrap();
    let guarded = plain.replace("@fragment", "#ifdef PREPASS_FRAGMENT\n@fragment") + "#endif\n";
    std::fs::write(dir.join("t.wgsl"), guarded).unwrap();
    std::fs::create_dir(dir.join("modules")).unwrap();
    let input = ["--def", "PREPASS_FRAGMENT", "--import-path", "modules"];
    let (code, _, err) =
        common::analyze_short(dir, "t.wgsl", &["t.json"], "t.profile.json", &input);
    assert_eq!(code, 0, "{err}");
    let text = std::fs::read_to_string(dir.join("t.profile.json")).unwrap();
    let profile: serde_json::Value = serde_json::from_str(&text).unwrap();
    assert_eq!(profile["version"], 14);
    assert_eq!(
        profile["shader_input"],
        serde_json::json!({"defs": {"PREPASS_FRAGMENT": "true"}, "import_paths": ["modules"]})
    );
    let emit = [
        "emit",
        "--profile",
        "t.profile.json",
        "--max-error",
        "0.05",
        "--out",
        "v",
    ];
    let (code, _, err) = common::run(dir, &emit);
    assert_eq!(code, 0, "{err}");
    assert!(dir.join("v/manifest.json").exists());
}
