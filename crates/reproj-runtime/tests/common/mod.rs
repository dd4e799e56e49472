//! What the runtime's tests share: the `reproj` binary (to write variants and render references)
//! and the workspace's files.

#![allow(dead_code)]

use std::path::{Path, PathBuf};
use std::process::{Command, Output};
use std::sync::OnceLock;

pub fn workspace() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

/// The `reproj` binary: `REPROJ_BIN` if set, else the workspace's test build of it, brought up to
/// date once per test process with `cargo test --workspace --no-run` in this test's own target
/// directory and profile (a no-op inside `cargo test --workspace`).
pub fn reproj_bin() -> PathBuf {
    static BIN: OnceLock<PathBuf> = OnceLock::new();
    BIN.get_or_init(|| {
        if let Some(p) = std::env::var_os("REPROJ_BIN") {
            return PathBuf::from(p);
        }
        // target/<profile>/deps/<test> → target/<profile>.
        let exe = std::env::current_exe().expect("the test's own path");
        let profile_dir = exe
            .parent()
            .and_then(Path::parent)
            .expect("target/<profile>/deps");
        let target_dir = profile_dir.parent().expect("target directory");
        let profile = match profile_dir.file_name().and_then(|n| n.to_str()) {
            Some("debug") | None => "dev",
            Some(other) => other,
        };
        // The workspace's own test build: what `cargo test --workspace` compiled for the CLI's
        // tests, so nothing is built again when this runs inside it. (`cargo build -p
        // reproj-cli` would unify features over the CLI alone and compile the binary and its
        // crates a second time: minutes on two cores.)
        let mut cargo = Command::new(env!("CARGO"));
        cargo
            .current_dir(workspace())
            .args(["test", "-q", "--workspace", "--no-run"])
            .arg("--target-dir")
            .arg(target_dir);
        match profile {
            "dev" => {}
            "release" => {
                cargo.arg("--release");
            }
            other => {
                cargo.args(["--profile", other]);
            }
        }
        let out = cargo.output().expect("running cargo");
        assert!(
            out.status.success(),
            "building reproj failed:\n{}",
            String::from_utf8_lossy(&out.stderr)
        );
        profile_dir.join(format!("reproj{}", std::env::consts::EXE_SUFFIX))
    })
    .clone()
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
