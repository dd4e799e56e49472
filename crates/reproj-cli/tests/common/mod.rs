//! What the CLI tests share: the repository root and running the real binary.
#![allow(dead_code)] // each test module uses part of it

use std::path::{Path, PathBuf};
use std::process::Command;

/// The repository root.
pub fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../..")
}

/// Run `reproj ARGS` in `cwd` (headless): exit code, stdout, stderr.
pub fn run(cwd: &Path, args: &[&str]) -> (i32, String, String) {
    let out = Command::new(env!("CARGO_BIN_EXE_reproj"))
        .args(args)
        .current_dir(cwd)
        .env("NODEVICE_SELECT", "1")
        .env("REPROJ_NO_CEILING", "1")
        .output()
        .expect("run reproj");
    (
        out.status.code().unwrap_or(-1),
        String::from_utf8_lossy(&out.stdout).into_owned(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

/// [`run`] with `analyze`'s ceiling race on (the other runs set `REPROJ_NO_CEILING`: the tests'
/// tiny shaders cost less than a variant's own passes, and their profiles need nodes).
pub fn run_with_ceiling(cwd: &Path, args: &[&str]) -> (i32, String, String) {
    let out = Command::new(env!("CARGO_BIN_EXE_reproj"))
        .args(args)
        .current_dir(cwd)
        .env("NODEVICE_SELECT", "1")
        .env_remove("REPROJ_NO_CEILING")
        .output()
        .expect("run reproj");
    (
        out.status.code().unwrap_or(-1),
        String::from_utf8_lossy(&out.stdout).into_owned(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

/// [`run`] with extra environment variables (e.g. the writers' failure hook `REPROJ_IO_FAIL`).
pub fn run_env(cwd: &Path, args: &[&str], env: &[(&str, &str)]) -> (i32, String, String) {
    let out = Command::new(env!("CARGO_BIN_EXE_reproj"))
        .args(args)
        .current_dir(cwd)
        .env("NODEVICE_SELECT", "1")
        .env("REPROJ_NO_CEILING", "1")
        .envs(env.iter().copied())
        .output()
        .expect("run reproj");
    (
        out.status.code().unwrap_or(-1),
        String::from_utf8_lossy(&out.stdout).into_owned(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

/// Copy the two-term fixture into `dir`: its shader as `shader`, its session as `session`.
pub fn two_terms(dir: &Path, shader: &str, session: &str) {
    let data = root().join("crates/reproj-cli/tests/data");
    std::fs::copy(data.join("two_terms.wgsl"), dir.join(shader)).unwrap();
    std::fs::copy(data.join("two_terms.json"), dir.join(session)).unwrap();
}

/// Write the two-term session under faster motion into `dir/name`: the same scene, the camera
/// orbiting 300° instead of 40° and the light swinging through.
pub fn two_terms_fast(dir: &Path, name: &str) {
    let text = std::fs::read_to_string(root().join("crates/reproj-cli/tests/data/two_terms.json"))
        .unwrap();
    let mut fast: serde_json::Value = serde_json::from_str(&text).unwrap();
    fast["camera"]["orbit"]["start_deg"] = serde_json::json!(0);
    fast["camera"]["orbit"]["end_deg"] = serde_json::json!(300);
    fast["light"]["keys"][1]["position"] = serde_json::json!([-3, -3, -3]);
    std::fs::write(dir.join(name), fast.to_string()).unwrap();
}

/// `reproj analyze SHADER --session S... --out OUT` on the two-term fixture with the short plan
/// the CLI tests share (Δn 2, 8, 16, 24 and 4 held out, at most 3 nodes, no sets, no charts),
/// then `extra` (a strategy, a filter, …).
pub fn analyze_short(
    dir: &Path,
    shader: &str,
    sessions: &[&str],
    out: &str,
    extra: &[&str],
) -> (i32, String, String) {
    let mut args = vec!["analyze", shader];
    for s in sessions {
        args.extend(["--session", s]);
    }
    args.extend(["--out", out]);
    args.extend([
        "--delta-n",
        "2,8,16,24",
        "--holdout",
        "4",
        "--max-nodes",
        "3",
        "--no-sets",
        "--no-charts",
    ]);
    args.extend(extra);
    run(dir, &args)
}
