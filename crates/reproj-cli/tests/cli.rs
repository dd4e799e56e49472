//! Command-line hygiene through the real binary: backends, closed pipes, `--out -`, and the schema
//! fields of the JSON reports. The tests that render use the machine's Vulkan adapter (lavapipe
//! where there is no GPU) on the replay's 64×64 test data.

use std::io::Read;
use std::path::PathBuf;
use std::process::{Command, Stdio};

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../..")
}

fn reproj_env(args: &[&str], env: &[(&str, &str)]) -> (i32, String, String) {
    let out = Command::new(env!("CARGO_BIN_EXE_reproj"))
        .args(args)
        .env("REPROJ_NO_CEILING", "1")
        .envs(env.iter().copied())
        .current_dir(root())
        .output()
        .expect("run reproj");
    (
        out.status.code().unwrap_or(-1),
        String::from_utf8_lossy(&out.stdout).into_owned(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

fn reproj(args: &[&str]) -> (i32, String, String) {
    reproj_env(args, &[])
}

const TINY: &str = "crates/reproj-replay/tests/data/tiny.wgsl";
const TINY_SESSION: &str = "crates/reproj-replay/tests/data/tiny_static_plane.json";

/// Run reproj with its stdout a pipe whose reading end is closed before it writes anything: the
/// first write fails with a broken pipe. Returns the exit code and stderr.
fn with_closed_stdout(args: &[&str]) -> (i32, String) {
    let mut child = Command::new(env!("CARGO_BIN_EXE_reproj"))
        .args(args)
        .env("REPROJ_NO_CEILING", "1")
        .current_dir(root())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("run reproj");
    drop(child.stdout.take());
    let mut err = String::new();
    child
        .stderr
        .take()
        .unwrap()
        .read_to_string(&mut err)
        .unwrap();
    let status = child.wait().unwrap();
    (status.code().unwrap_or(-1), err)
}

#[test]
fn unknown_backend_is_a_user_error_naming_the_accepted_ones() {
    for cmd in [
        vec!["render", TINY, "--session", TINY_SESSION],
        vec!["analyze", TINY, "--session", TINY_SESSION],
        vec!["emit", "--max-error", "0.1"],
    ] {
        for backend in ["bogus", "gl"] {
            let mut args = cmd.clone();
            args.extend(["--backend", backend]);
            let (code, _, err) = reproj(&args);
            assert_eq!(code, 2, "{args:?}: {err}");
            assert!(err.contains(&format!("`{backend}`")), "{err}");
            assert!(err.contains("vulkan, vk"), "{err}");
            assert!(!err.contains("panicked"), "{err}");
        }
    }
    // The same check applies to the environment variable.
    let (code, _, err) = reproj_env(
        &["render", TINY, "--session", TINY_SESSION],
        &[("WGPU_BACKEND", "opengl")],
    );
    assert_eq!(code, 2, "{err}");
    assert!(
        err.contains("WGPU_BACKEND") && err.contains("not built into"),
        "{err}"
    );
    // `--backend` is a hidden flag (the error above names what this build has); `--help`
    // leaves it out.
    let (code, out, _) = reproj(&["render", "--help"]);
    assert_eq!(code, 0);
    assert!(!out.contains("--backend"), "{out}");
}

#[test]
fn out_dash_is_refused() {
    let tmp = tempfile::tempdir().unwrap();
    let profile = tmp.path().join("p.json");
    let profile = profile.to_str().unwrap();
    for args in [
        vec!["instance", TINY, "--node", "root", "--out", "-"],
        vec!["analyze", TINY, "--session", TINY_SESSION, "--out", "-"],
        vec![
            "emit",
            "--max-error",
            "0.1",
            "--profile",
            profile,
            "--out",
            "-",
        ],
        vec!["render", TINY, "--session", TINY_SESSION, "--frames", "-"],
    ] {
        let (code, out, err) = reproj(&args);
        assert_eq!(code, 2, "{args:?}: {err}");
        assert!(err.contains("`-` (stdout) is not supported"), "{err}");
        assert!(out.is_empty(), "{out}");
    }
    assert!(!root().join("-").exists(), "a file named `-` was written");
}

#[test]
fn closed_stdout_is_a_quiet_exit() {
    for args in [
        vec!["nodes", "shaders/marble.wgsl", "--all"],
        vec!["nodes", "shaders/marble.wgsl", "--all", "--json"],
        vec![
            "render",
            TINY,
            "--session",
            TINY_SESSION,
            "--max-frames",
            "2",
            "--json",
        ],
        vec![
            "render",
            TINY,
            "--session",
            TINY_SESSION,
            "--max-frames",
            "2",
        ],
    ] {
        let (code, err) = with_closed_stdout(&args);
        assert!(!err.contains("panicked"), "{args:?}: {err}");
        assert_eq!(code, 0, "{args:?}: {err}");
        assert!(!err.contains("Broken pipe"), "{args:?}: {err}");
    }
}

#[test]
fn json_reports_carry_schema_and_version() {
    let (code, out, err) = reproj(&[
        "render",
        TINY,
        "--session",
        TINY_SESSION,
        "--max-frames",
        "2",
        "--json",
    ]);
    assert_eq!(code, 0, "{err}");
    let v: serde_json::Value = serde_json::from_str(&out).unwrap();
    assert_eq!(v["schema"], "reproj.render");
    assert_eq!(v["version"], 2);

    // analyze (tiny, static) then emit: report.json and `emit --json` are the same report.
    let tmp = tempfile::tempdir().unwrap();
    let profile = tmp.path().join("tiny.profile.json");
    let out_dir = tmp.path().join("out");
    let (code, _, err) = reproj(&[
        "analyze",
        TINY,
        "--session",
        TINY_SESSION,
        "--nodes",
        "35",
        "--delta-n",
        "2,4",
        "--holdout",
        "3",
        "--max-frames",
        "4",
        "--strategy",
        "3pass",
        "--no-charts",
        "--out",
        profile.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{err}");
    let (code, out, err) = reproj(&[
        "emit",
        "--profile",
        profile.to_str().unwrap(),
        "--max-error",
        "0.1",
        "--out",
        out_dir.to_str().unwrap(),
        "--json",
    ]);
    assert_eq!(code, 0, "{err}");
    let printed: serde_json::Value = serde_json::from_str(&out).unwrap();
    let file: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out_dir.join("report.json")).unwrap())
            .unwrap();
    for v in [&printed, &file] {
        assert_eq!(v["schema"], "reproj.report", "{v}");
        assert_eq!(v["version"], 6, "{v}");
    }
    assert_eq!(printed, file);

    // `emit` with its stdout closed: the files are written, the exit is quiet.
    let again = tmp.path().join("again");
    let (code, err) = with_closed_stdout(&[
        "emit",
        "--profile",
        profile.to_str().unwrap(),
        "--max-error",
        "0.1",
        "--out",
        again.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{err}");
    assert!(!err.contains("panicked"), "{err}");
    assert!(again.join("report.json").exists());
}

/// `render` says how far it is per frame on stderr: without a terminal, lines like `analyze`'s
/// (one every 2 s once a replay runs that long; `REPROJ_PROGRESS_EVERY_MS=0` gives one per frame
/// here), for the original and then the variant; none with `--json`, and none for a short render
/// at the default period.
#[test]
fn render_reports_progress_per_frame_on_stderr() {
    let args = [
        "render",
        TINY,
        "--session",
        TINY_SESSION,
        "--node",
        "root",
        "--max-frames",
        "3",
    ];
    let every = [("REPROJ_PROGRESS_EVERY_MS", "0")];
    let (code, out, err) = reproj_env(&args, &every);
    assert_eq!(code, 0, "{err}");
    let lines: Vec<&str> = err.lines().filter(|l| l.starts_with('[')).collect();
    for phase in ["original", "variant"] {
        let of_phase: Vec<&&str> = lines
            .iter()
            .filter(|l| l.contains(&format!("] {phase} frames:")))
            .collect();
        assert_eq!(of_phase.len(), 3, "{phase}: {err}");
        assert!(of_phase[2].starts_with("[3/3]"), "{err}");
        assert!(of_phase.iter().all(|l| l.contains("ETA")), "{err}");
    }
    assert!(!out.contains("ETA"), "progress stays off stdout: {out}");

    let mut json = args.to_vec();
    json.push("--json");
    let (code, out, err) = reproj_env(&json, &every);
    assert_eq!(code, 0, "{err}");
    assert!(!err.contains("frames:"), "--json: no progress: {err}");
    serde_json::from_str::<serde_json::Value>(&out).expect("stdout is the JSON report");

    let (code, _, err) = reproj(&args);
    assert_eq!(code, 0, "{err}");
    assert!(
        !err.contains("frames:"),
        "a short render prints no line: {err}"
    );
}

/// Every flag `--help` shows, per command, besides help, version, json, quiet, verbose and color:
/// a flag added to (or hidden from) the help is a decision made here. Tuning flags are hidden
/// (still accepted; USAGE.md, "Tuning flags").
#[test]
fn the_visible_flags_are_these() {
    // The shader-input flags (`ShaderInputArgs` and `--lang-in`) of every command that reads a
    // shader.
    let input = ["def", "defs-preset", "include-dir"];
    // (command, reads a shader, its other visible flags)
    let expected: [(&str, bool, &[&str]); 11] = [
        ("nodes", true, &["entry", "all"]),
        (
            "instance",
            true,
            &[
                "node",
                "out",
                "entry",
                "delta-n",
                "strategy",
                "group",
                "load",
                "reproject",
                "lang",
            ],
        ),
        (
            "render",
            true,
            &[
                "session",
                "node",
                "variant",
                "delta-n",
                "adaptive",
                "strategy",
                "frames",
                "max-frames",
                "entry",
                "time",
            ],
        ),
        (
            "analyze",
            true,
            &[
                "session",
                "out",
                "fit-delta-n",
                "nodes",
                "max-frames",
                "strategy",
                "entry",
            ],
        ),
        ("merge", false, &["out"]),
        (
            "emit",
            false,
            &[
                "max-error",
                "profile",
                "out",
                "strategy",
                "node",
                "verify",
                "session",
                "adaptive",
                "group",
                "load",
                "reproject",
                "lang",
            ],
        ),
        ("report", false, &["out", "compare"]),
        (
            "compare",
            true,
            &[
                "entry",
                "session",
                "speedup",
                "max-error",
                "profile",
                "out",
                "max-frames",
            ],
        ),
        (
            "bench",
            true,
            &["session", "delta-n", "adaptive", "max-frames", "entry"],
        ),
        (
            "session init",
            true,
            &["entry", "out", "frames", "resolution"],
        ),
        ("completions", false, &[]),
    ];
    let not_counted = ["help", "version", "json", "quiet", "verbose", "color"];
    let mut total = 0;
    for (command, reads_shader, flags) in expected {
        let mut args: Vec<&str> = command.split(' ').collect();
        args.push("--help");
        let (code, out, err) = reproj(&args);
        assert_eq!(code, 0, "{err}");
        let mut shown: Vec<String> = out
            .lines()
            .filter_map(|l| {
                let l = l.trim_start();
                let l = l
                    .strip_prefix("-")
                    .filter(|r| r.len() > 3 && &r[1..3] == ", ")
                    .map_or(l, |r| &r[3..]);
                let name = l.strip_prefix("--")?;
                let name: String = name
                    .chars()
                    .take_while(|c| c.is_ascii_alphanumeric() || *c == '-')
                    .collect();
                (!name.is_empty()).then_some(name)
            })
            .filter(|n| !not_counted.contains(&n.as_str()))
            .collect();
        shown.sort();
        shown.dedup();
        // The global flag every command shows.
        let mut want: Vec<String> = flags.iter().map(|f| f.to_string()).collect();
        if reads_shader {
            want.extend(input.iter().map(|f| f.to_string()));
        }
        want.sort();
        assert_eq!(shown, want, "`reproj {command} --help`");
        total += want.len();
    }
    // A user reads at most 80 flags across the commands; the rest are tuning (docs/USAGE.md).
    assert!(total <= 80, "{total} flags visible across the commands");
}
