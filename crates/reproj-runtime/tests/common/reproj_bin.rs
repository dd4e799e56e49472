//! The `reproj` binary for the tests of crates other than the CLI (the runtime's; the example
//! host's include this file by path): `REPROJ_BIN` if set, else the workspace's test build of it,
//! brought up to date once per test process with `cargo test --workspace --no-run` in the test's
//! own target directory and profile — nothing to do inside `cargo test --workspace`, which built
//! it for the CLI's tests. (`cargo build -p reproj-cli` would unify features over the CLI alone and
//! compile the binary and its crates a second time: minutes on two cores.)

use std::path::{Path, PathBuf};
use std::process::Command;
use std::sync::OnceLock;

/// See the module docs.
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
        let mut cargo = Command::new(env!("CARGO"));
        cargo
            .current_dir(Path::new(env!("CARGO_MANIFEST_DIR")).join("../.."))
            .args(["test", "-q", "--workspace", "--no-run", "--target-dir"])
            .arg(target_dir);
        match profile_dir.file_name().and_then(|n| n.to_str()) {
            Some("debug") | None => {}
            Some("release") => {
                cargo.arg("--release");
            }
            Some(other) => {
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
