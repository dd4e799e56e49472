//! The CLI as a program's tool, through the real binary: every command's `--json` carries `schema`
//! and `version`; `--color never` (and a pipe) print no escape codes; `completions` prints a
//! script; `--help` lists the exit codes of docs/CI.md; one `error:` prefix; `-q` silences notes.
//! The commands that render use the machine's Vulkan adapter (lavapipe where there is no GPU) on
//! the replay's 64×64 test data, a few frames each.

use std::path::Path;

use crate::common::{root, run, run_env};

const TINY: &str = "crates/reproj-replay/tests/data/tiny.wgsl";
const TINY_SESSION: &str = "crates/reproj-replay/tests/data/tiny_static_plane.json";

/// `reproj ARGS` from the repository root; the exit code must be 0; stdout parsed as JSON, with
/// its `schema` and `version` checked.
fn json(args: &[&str], schema: &str) -> serde_json::Value {
    let (code, out, err) = run(&root(), args);
    assert_eq!(code, 0, "{args:?}: {err}");
    let v: serde_json::Value =
        serde_json::from_str(&out).unwrap_or_else(|e| panic!("{args:?}: {e}: {out}"));
    assert_eq!(v["schema"], schema, "{args:?}: {v}");
    assert!(v["version"].is_u64(), "{args:?}: no version: {v}");
    v
}

fn path(p: &Path) -> &str {
    p.to_str().unwrap()
}

#[test]
fn every_command_prints_json_with_schema_and_version() {
    let tmp = tempfile::tempdir().unwrap();
    let t = tmp.path();
    json(&["nodes", TINY, "--json"], "reproj.nodes");
    let variant = t.join("variant");
    let v = json(
        &[
            "instance",
            TINY,
            "--node",
            "root",
            "--out",
            path(&variant),
            "--json",
        ],
        "reproj.instance",
    );
    assert_eq!(v["manifest"]["schema"], "reproj.manifest");
    assert!(v["files"].as_array().unwrap().len() >= 2, "{v}");
    json(
        &[
            "render",
            TINY,
            "--session",
            TINY_SESSION,
            "--max-frames",
            "2",
            "--json",
        ],
        "reproj.render",
    );
    // A variant's render: the original's own time beside it and, asked, the timing engine's
    // speedup (interleaved, with its interval).
    let v = json(
        &[
            "render",
            TINY,
            "--session",
            TINY_SESSION,
            "--variant",
            path(&variant),
            "--max-frames",
            "4",
            "--speedup",
            "--json",
        ],
        "reproj.render",
    );
    assert!(v["original_frame_ms"].as_f64().unwrap() > 0.0, "{v}");
    assert!(v["speedup"]["rounds"].as_u64().unwrap() > 0, "{v}");
    assert!(
        v["speedup"]["original_median_ms"].as_f64().unwrap() > 0.0,
        "{v}"
    );
    let profile = t.join("tiny.profile.json");
    let analyze = |out: &Path, shard: Option<&str>| {
        let mut args = vec![
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
            "--no-sets",
            "--out",
            path(out),
            "--json",
        ];
        if let Some(s) = shard {
            args.extend(["--shard", s]);
        }
        json(&args, "reproj.analyze")
    };
    let v = analyze(&profile, None);
    assert_eq!(v["profiles"][0]["profile"], path(&profile), "{v}");
    let shard = t.join("shard.profile.json");
    analyze(&shard, Some("0/1"));
    json(
        &[
            "merge",
            path(&shard),
            "--out",
            path(&t.join("merged.profile.json")),
            "--json",
        ],
        "reproj.merge",
    );
    json(
        &[
            "emit",
            "--profile",
            path(&profile),
            "--max-error",
            "0.1",
            "--out",
            path(&t.join("emitted")),
            "--json",
        ],
        "reproj.report",
    );
    json(
        &[
            "report",
            path(&profile),
            "--out",
            path(&t.join("report.html")),
            "--max-rendered",
            "1",
            "--json",
        ],
        "reproj.report-run",
    );
    json(
        &[
            "bench",
            TINY,
            path(&variant),
            "--session",
            TINY_SESSION,
            "--max-frames",
            "4",
            "--block-frames",
            "2",
            "--rounds",
            "2",
            "--min-rounds",
            "2",
            "--json",
        ],
        "reproj.bench",
    );
    json(
        &[
            "compare",
            TINY,
            "--session",
            TINY_SESSION,
            "--speedup",
            "1.2",
            "--max-frames",
            "4",
            "--max-steps",
            "1",
            "--candidates",
            "2",
            "--resize-tries",
            "1",
            "--out",
            path(&t.join("compare")),
            "--json",
        ],
        "reproj.compare",
    );
}

/// `--color never` (and, in `auto`, a pipe or NO_COLOR) print no escape code anywhere: not in
/// an error, not in clap's own messages, not in help; `--color always` colours the label.
#[test]
fn color_only_where_asked() {
    let esc = '\x1b';
    for args in [
        vec!["--color", "never", "nodes", "missing.wgsl"],
        vec!["nodes", "missing.wgsl"],
        vec!["--color", "never", "nodes", "--bogus"],
        vec!["--color", "never", "--help"],
        vec!["--color=never", "emit", "--help"],
    ] {
        let (_, out, err) = run(&root(), &args);
        assert!(
            !out.contains(esc) && !err.contains(esc),
            "{args:?}: {out}{err}"
        );
    }
    let (_, _, err) = run_env(
        &root(),
        &["--color", "auto", "nodes", "missing.wgsl"],
        &[("NO_COLOR", "1")],
    );
    assert!(!err.contains(esc), "{err}");
    let (code, _, err) = run(&root(), &["--color", "always", "nodes", "missing.wgsl"]);
    assert_eq!(code, 2, "{err}");
    assert!(err.starts_with("\x1b[1;31merror\x1b[0m: "), "{err:?}");
}

/// One prefix: every error line reproj prints starts `error: ` (a user error, clap's parse
/// errors, an unknown node), never `reproj:` or `error: error:`.
#[test]
fn one_error_prefix() {
    let tmp = tempfile::tempdir().unwrap();
    for args in [
        vec!["nodes", "missing.wgsl"],
        vec!["nodes", "--bogus"],
        vec!["instance", TINY, "--node", "99999", "--out", "x"],
        vec![
            "emit",
            "--max-error",
            "0.1",
            "--profile",
            "missing.profile.json",
        ],
    ] {
        let (code, _, err) = run(tmp.path(), &args);
        assert_eq!(code, 2, "{args:?}: {err}");
        assert!(err.starts_with("error: "), "{args:?}: {err}");
        assert!(!err.contains("error: error:"), "{args:?}: {err}");
        assert!(!err.contains("reproj:"), "{args:?}: {err}");
    }
}

#[test]
fn completions_print_a_script() {
    let (code, out, err) = run(&root(), &["completions", "bash"]);
    assert_eq!(code, 0, "{err}");
    assert!(out.contains("_reproj()"), "{out}");
    for command in ["nodes", "emit", "render", "completions"] {
        assert!(out.contains(command), "{command} missing");
    }
    for shell in ["zsh", "fish", "elvish", "powershell"] {
        let (code, out, err) = run(&root(), &["completions", shell]);
        assert_eq!(code, 0, "{shell}: {err}");
        assert!(out.contains("reproj"), "{shell}: {out}");
    }
}

/// `--help` (the top level and every command's) lists the exit codes, the same as docs/CI.md.
#[test]
fn exit_codes_are_in_help_as_in_the_ci_doc() {
    let doc = std::fs::read_to_string(root().join("docs/CI.md")).unwrap();
    let line = doc
        .split("Exit codes:")
        .nth(1)
        .expect("docs/CI.md lists the exit codes");
    let line = &line[..line.find("\n\n").unwrap_or(line.len())];
    let mut documented: Vec<u32> = line
        .split([',', ' ', '\n'])
        .filter_map(|w| w.parse().ok())
        .collect();
    documented.dedup();
    assert_eq!(documented, [0, 1, 2, 3, 4, 5, 130], "{line}");
    for args in [vec!["--help"], vec!["emit", "--help"], vec!["nodes", "-h"]] {
        let (code, out, err) = run(&root(), &args);
        assert_eq!(code, 0, "{err}");
        let listed = out.split("Exit codes:").nth(1).expect("exit codes in help");
        let codes: Vec<u32> = listed
            .lines()
            .filter_map(|l| l.split_whitespace().next()?.parse().ok())
            .collect();
        assert_eq!(codes, documented, "{args:?}: {out}");
    }
}

/// `-q` leaves out the notes (which profile, progress), `-v` adds what happened; stdout is the
/// same.
#[test]
fn quiet_and_verbose() {
    let (code, out, err) = run(&root(), &["-q", "nodes", TINY]);
    assert_eq!(code, 0, "{err}");
    assert!(err.is_empty(), "{err}");
    let (_, out_v, _) = run(&root(), &["-v", "nodes", TINY]);
    assert_eq!(out, out_v);
    let (code, _, err) = run(&root(), &["-v", "nodes", "missing.wgsl"]);
    assert_eq!(code, 2);
    assert!(err.contains("exit code 2"), "{err}");
    let (code, _, err) = run(&root(), &["-q", "-v", "nodes", TINY]);
    assert_eq!(code, 2, "-q and -v conflict: {err}");
}
