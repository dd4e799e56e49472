//! CI mode through the real binary: a committed profile used from another directory, comment
//! edits that keep it valid, code edits that make it stale, `--shader`, `--min-speedup` (exit 3),
//! a clean output directory, and progress lines without a terminal.

use std::path::{Path, PathBuf};
use std::process::Command;

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../..")
}

fn reproj(cwd: &Path, args: &[&str]) -> (i32, String, String) {
    let out = Command::new(env!("CARGO_BIN_EXE_reproj"))
        .args(args)
        .current_dir(cwd)
        .env("NODEVICE_SELECT", "1")
        .output()
        .expect("run reproj");
    (
        out.status.code().unwrap_or(-1),
        String::from_utf8_lossy(&out.stdout).into_owned(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

fn names(dir: &Path) -> Vec<String> {
    let mut v: Vec<String> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    v.sort();
    v
}

#[test]
fn a_committed_profile_drives_emit_from_anywhere() {
    let tmp = tempfile::tempdir().unwrap();
    let repo = tmp.path().join("repo");
    std::fs::create_dir_all(repo.join("profiles")).unwrap();
    let data = root().join("crates/reproj-replay/tests/data");
    std::fs::copy(data.join("tiny.wgsl"), repo.join("tiny.wgsl")).unwrap();
    std::fs::copy(data.join("tiny_moving.json"), repo.join("tiny.json")).unwrap();

    // Analyze, stderr not a terminal: one progress line per replay, with an ETA.
    let (code, _, err) = reproj(
        &repo,
        &[
            "analyze",
            "tiny.wgsl",
            "--session",
            "tiny.json",
            "--out",
            "profiles/tiny.profile.json",
            "--delta-n",
            "2,4,8",
            "--holdout",
            "6",
            "--max-nodes",
            "3",
            "--no-charts",
        ],
    );
    assert_eq!(code, 0, "{err}");
    let progress: Vec<&str> = err.lines().filter(|l| l.starts_with('[')).collect();
    assert!(progress.len() >= 4, "{err}");
    assert!(progress.iter().all(|l| l.contains("ETA")), "{err}");
    let profile: serde_json::Value = serde_json::from_str(
        &std::fs::read_to_string(repo.join("profiles/tiny.profile.json")).unwrap(),
    )
    .unwrap();
    assert_eq!(profile["shader"]["path"], "../tiny.wgsl");
    assert_eq!(profile["session"]["path"], "../tiny.json");

    // From another working directory; stale files of an earlier run are gone afterwards.
    let out = tmp.path().join("out");
    std::fs::create_dir_all(&out).unwrap();
    std::fs::write(out.join("pass3_shade.wgsl"), "// stale").unwrap();
    let emit = |extra: &[&str]| {
        let mut a = vec![
            "emit",
            "--max-error",
            "1",
            "--profile",
            "repo/profiles/tiny.profile.json",
            "--out",
            "out",
        ];
        a.extend(extra);
        reproj(tmp.path(), &a)
    };
    let (code, _, err) = emit(&[]);
    assert_eq!(code, 0, "{err}");
    let written = names(&out);
    assert!(written.contains(&"report.json".to_string()), "{written:?}");
    if !written.contains(&"manifest.json".to_string()) {
        // The original was kept: the stale pass must not survive beside it.
        assert!(
            !written.contains(&"pass3_shade.wgsl".to_string()),
            "{written:?}"
        );
    }
    assert!(
        names(tmp.path()).iter().all(|n| !n.starts_with(".out")),
        "no staging directory left: {:?}",
        names(tmp.path())
    );

    // A comment edit keeps the profile valid; a code edit makes it stale (exit 2).
    let shader = repo.join("tiny.wgsl");
    let text = std::fs::read_to_string(&shader).unwrap();
    std::fs::write(&shader, format!("// reviewed\n{text}\n// end\n")).unwrap();
    let (code, _, err) = emit(&[]);
    assert_eq!(code, 0, "{err}");
    let edited = text.replacen("0.5", "0.25", 1);
    assert_ne!(edited, text, "tiny.wgsl has a 0.5 to edit");
    std::fs::write(&shader, &edited).unwrap();
    let (code, _, err) = emit(&[]);
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("changed since the profile was made"), "{err}");
    // `--shader` names another copy of the profiled shader.
    let copy = tmp.path().join("elsewhere.wgsl");
    std::fs::write(&copy, &text).unwrap();
    let (code, _, err) = emit(&["--shader", copy.to_str().unwrap()]);
    assert_eq!(code, 0, "{err}");

    // An unreachable speedup: the output is still written, exit 3.
    let (code, _, err) = emit(&["--shader", copy.to_str().unwrap(), "--min-speedup", "1000"]);
    assert_eq!(code, 3, "{err}");
    assert!(err.contains("--min-speedup 1000"), "{err}");
    assert!(out.join("report.json").exists());

    // A directory holding other files is not replaced.
    let (code, _, err) = reproj(
        tmp.path(),
        &[
            "emit",
            "--max-error",
            "1",
            "--profile",
            "repo/profiles/tiny.profile.json",
            "--shader",
            copy.to_str().unwrap(),
            "--out",
            "repo",
        ],
    );
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("refusing to replace"), "{err}");
    assert!(repo.join("profiles/tiny.profile.json").exists());
}
