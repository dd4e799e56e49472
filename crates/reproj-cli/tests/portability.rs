//! What reproj writes compiles with compilers that are not reproj's own: runs
//! `scripts/check-portability.sh` against the built binary (every sample shader; the root and one
//! node, every strategy). The compilers are not dependencies of the workspace: the test skips, with
//! a message, when none of them is installed (`scripts/ensure-tools.sh` installs glslang and
//! SPIRV-Tools; naga is `cargo install naga-cli`) — except under CI (`CI` set), where the ones the
//! set-up script installs must be there: a missing one fails the test instead of passing it.

use std::path::PathBuf;
use std::process::Command;

fn installed(tool: &str) -> bool {
    Command::new("sh")
        .args(["-c", &format!("command -v {tool}")])
        .output()
        .is_ok_and(|o| o.status.success())
}

#[test]
fn emitted_passes_compile_with_naga_tint_glslang_and_spirv_val() {
    let tools = ["naga", "tint", "glslangValidator", "spirv-val"];
    if std::env::var_os("CI").is_some() {
        for t in ["glslangValidator", "spirv-val", "bash"] {
            assert!(
                installed(t),
                "CI is set and {t} is missing: scripts/ensure-tools.sh installs it (Debian glslang-tools, spirv-tools); a skipped check must not pass"
            );
        }
    }
    let present: Vec<&str> = tools.into_iter().filter(|t| installed(t)).collect();
    if present.is_empty() || !installed("bash") {
        eprintln!("skipped: none of {tools:?} is installed (see scripts/ensure-tools.sh)");
        return;
    }
    let root = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../..");
    let out = Command::new("bash")
        .arg(root.join("scripts/check-portability.sh"))
        .args(["--reproj", env!("CARGO_BIN_EXE_reproj"), "--nodes", "1"])
        .current_dir(&root)
        .output()
        .expect("run scripts/check-portability.sh");
    let stdout = String::from_utf8_lossy(&out.stdout);
    let stderr = String::from_utf8_lossy(&out.stderr);
    eprintln!("{stdout}{stderr}");
    assert!(out.status.success(), "the portability check failed");
    assert!(stdout.contains("check-portability: all passed"), "{stdout}");
    // Every installed tool checked something (glslang and spirv-val compile naga's output).
    let naga = present.contains(&"naga");
    for &t in &present {
        let name = match t {
            "glslangValidator" if naga => "glslang es300:",
            "spirv-val" if naga => "spirv-val:",
            "naga" => "naga:",
            "tint" => "tint:",
            _ => continue,
        };
        assert!(stdout.contains(name), "{name} missing from\n{stdout}");
    }
    // What `instance --lang glsl,spv` writes itself is compiled too.
    for (tool, name) in [
        ("glslangValidator", "reproj glsl:"),
        ("spirv-val", "reproj spv:"),
    ] {
        if present.contains(&tool) {
            assert!(stdout.contains(name), "{name} missing from\n{stdout}");
        }
    }
}
