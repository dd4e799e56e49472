//! What the runtime's tests share: the `reproj` binary (to write variants and render references)
//! and the workspace's files.

#![allow(dead_code)]

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

mod reproj_bin;
pub use reproj_bin::reproj_bin;

pub fn workspace() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

/// Run `reproj ARGS` in the workspace root; panic with its output unless it succeeds.
pub fn reproj(args: &[&str]) -> Output {
    let out = Command::new(reproj_bin())
        .current_dir(workspace())
        .args(args)
        .env(
            "NODEVICE_SELECT",
            std::env::var("NODEVICE_SELECT").unwrap_or_else(|_| "1".into()),
        )
        .output()
        .expect("starting reproj");
    assert!(
        out.status.success(),
        "reproj {} failed ({}):\n{}\n{}",
        args.join(" "),
        out.status,
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr)
    );
    out
}

pub fn s(p: &Path) -> &str {
    p.to_str().expect("UTF-8 temp path")
}

/// `reproj instance shaders/marble.wgsl --node root EXTRA... --out DIR`.
pub fn instance_marble(dir: &Path, extra: &[&str]) {
    let mut args = vec![
        "instance",
        "shaders/marble.wgsl",
        "--node",
        "root",
        "--out",
        s(dir),
    ];
    args.extend(extra);
    reproj(&args);
}
