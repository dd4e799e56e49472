//! Interrupted runs leave nothing hidden behind, and one analysis at a time writes a profile.
//!
//! - SIGINT during `render --frames`: exit 130, no `.frames.staged*` directory left, the previous
//!   frames directory untouched.
//! - A staged directory left by a process that is gone (SIGKILL) is swept by the next run.
//! - A memory fault (SIGSEGV, as a Vulkan driver raises on a shader it cannot run) during
//!   `render --frames`: exit 1 with a message saying what happened, the old frames intact, and the
//!   staged directory swept by the next run.
//! - A second `analyze` to the same `--out` while the first runs: exit 2 naming the first's pid;
//!   SIGTERM on the first removes its lock and keeps its journal.

use std::path::Path;
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};

use crate::common::{root, run};

fn spawn(cwd: &Path, args: &[&str]) -> Child {
    Command::new(env!("CARGO_BIN_EXE_reproj"))
        .args(args)
        .current_dir(cwd)
        .env("NODEVICE_SELECT", "1")
        .env("REPROJ_NO_CEILING", "1")
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .expect("run reproj")
}

fn hidden(dir: &Path) -> Vec<String> {
    std::fs::read_dir(dir)
        .unwrap()
        .flatten()
        .map(|e| e.file_name().to_string_lossy().into_owned())
        .filter(|n| n.starts_with('.'))
        .collect()
}

/// Wait until `ready()` holds (at most 120 s).
fn wait_for(what: &str, ready: impl Fn() -> bool) {
    let start = Instant::now();
    while !ready() {
        assert!(
            start.elapsed() < Duration::from_secs(120),
            "timed out waiting for {what}"
        );
        std::thread::sleep(Duration::from_millis(50));
    }
}

fn signal(child: &Child, sig: &str) {
    let ok = Command::new("kill")
        .args([sig, &child.id().to_string()])
        .status()
        .expect("kill")
        .success();
    assert!(ok, "kill {sig}");
}

fn setup() -> tempfile::TempDir {
    let tmp = tempfile::tempdir().unwrap();
    for (from, to) in [
        ("shaders/marble.wgsl", "marble.wgsl"),
        ("sessions/marble.json", "marble.json"),
    ] {
        std::fs::copy(root().join(from), tmp.path().join(to)).unwrap();
    }
    tmp
}

#[test]
fn an_interrupted_render_leaves_nothing_hidden_and_the_old_frames_intact() {
    let tmp = setup();
    let dir = tmp.path();
    std::fs::create_dir(dir.join("frames")).unwrap();
    std::fs::write(dir.join("frames/frame_000.png"), b"old").unwrap();
    // A stale staged directory of a process that is gone (a pid above any pid_max).
    std::fs::create_dir(dir.join(".frames.staged4999999-0")).unwrap();
    let child = spawn(
        dir,
        &[
            "render",
            "marble.wgsl",
            "--session",
            "marble.json",
            "--frames",
            "frames",
        ],
    );
    wait_for("the staged frames", || {
        hidden(dir)
            .iter()
            .any(|n| n.starts_with(".frames.staged") && !n.contains("4999999"))
    });
    assert!(
        !dir.join(".frames.staged4999999-0").exists(),
        "the stale directory is swept when the new one is made"
    );
    signal(&child, "-INT");
    let out = child.wait_with_output().unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(130), "{err}");
    assert!(err.contains("interrupted"), "{err}");
    assert!(hidden(dir).is_empty(), "{:?}", hidden(dir));
    assert_eq!(
        std::fs::read(dir.join("frames/frame_000.png")).unwrap(),
        b"old"
    );
}

#[test]
fn a_memory_fault_is_said_and_exits_1_and_the_next_run_sweeps_what_it_left() {
    let tmp = setup();
    let dir = tmp.path();
    std::fs::create_dir(dir.join("frames")).unwrap();
    std::fs::write(dir.join("frames/frame_000.png"), b"old").unwrap();
    let args = [
        "render",
        "marble.wgsl",
        "--session",
        "marble.json",
        "--frames",
        "frames",
    ];
    let child = spawn(dir, &args);
    wait_for("the staged frames", || {
        hidden(dir).iter().any(|n| n.starts_with(".frames.staged"))
    });
    signal(&child, "-SEGV");
    let out = child.wait_with_output().unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{err}");
    assert!(
        err.contains("error: reproj stopped on a memory fault (SIGSEGV or SIGBUS)"),
        "{err}"
    );
    assert_eq!(
        std::fs::read(dir.join("frames/frame_000.png")).unwrap(),
        b"old"
    );
    // The next run sweeps the staged directory the faulted process left.
    let (code, _, err) = run(dir, &[&args[..], &["--max-frames", "2"]].concat());
    assert_eq!(code, 0, "{err}");
    assert!(hidden(dir).is_empty(), "{:?}", hidden(dir));
}

#[test]
fn one_analysis_per_profile_and_sigterm_keeps_the_journal() {
    let tmp = setup();
    let dir = tmp.path();
    let args = [
        "analyze",
        "marble.wgsl",
        "--session",
        "marble.json",
        "--out",
        "m.profile.json",
        "--max-nodes",
        "3",
        "--no-charts",
        "--no-sets",
    ];
    let first = spawn(dir, &args);
    wait_for("the first analysis's journal", || {
        dir.join("m.profile.journal").exists()
    });
    let (code, _, err) = run(dir, &args);
    assert_eq!(code, 2, "{err}");
    assert!(err.contains(&format!("pid {}", first.id())), "{err}");
    assert!(dir.join("m.profile.json.lock").exists());
    signal(&first, "-TERM");
    let out = first.wait_with_output().unwrap();
    assert_eq!(
        out.status.code(),
        Some(130),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert!(!dir.join("m.profile.json.lock").exists());
    assert!(
        dir.join("m.profile.journal").exists(),
        "the journal stays for a resume"
    );
    assert!(!dir.join("m.profile.json").exists());
    assert!(hidden(dir).is_empty(), "{:?}", hidden(dir));
}
