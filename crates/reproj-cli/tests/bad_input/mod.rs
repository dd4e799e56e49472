//! The bad-input corpus: malformed shaders, sessions, manifests, profiles and arguments, each run
//! through the real binary. Every case must exit 2 with one clear message naming what is wrong
//! (the expected text), never panic, and write nothing.
//!
//! Each case runs in a fresh directory holding `good.wgsl` and `good.json` (a valid shader and
//! session), `good.profile.json` (their profile), `variant/` (a written variant), plus the case's
//! own files. The files that are bad inputs in themselves (shaders, sessions, manifests, profiles
//! that are not JSON) are in `tests/bad-input/` at the top of the repository (`tests/README.md`),
//! each read by a case here; the sessions and profiles that are good ones with one field made bad
//! are made here from the good ones, so that they follow the formats.
//!
//! The cases, by topic, a file each: `shaders.rs` (and what the instancer refuses),
//! `sessions.rs`, `variants.rs` (written variants), `profiles.rs` and `arguments.rs` (flags and
//! output paths). One test runs them all, over one good profile analyzed once.

use std::collections::BTreeSet;
use std::path::{Path, PathBuf};
use std::sync::Mutex;

use crate::common::{root, run};

mod arguments;
mod hostile;
mod profiles;
mod sessions;
mod shaders;
mod variants;

fn files(dir: &Path) -> BTreeSet<PathBuf> {
    let mut out = BTreeSet::new();
    let mut stack = vec![dir.to_owned()];
    while let Some(d) = stack.pop() {
        for e in std::fs::read_dir(&d).unwrap() {
            let p = e.unwrap().path();
            if p.is_dir() {
                stack.push(p.clone());
            }
            out.insert(p);
        }
    }
    out
}

fn copy_dir(from: &Path, to: &Path) {
    std::fs::create_dir_all(to).unwrap();
    for e in std::fs::read_dir(from).unwrap() {
        let p = e.unwrap().path();
        let dest = to.join(p.file_name().unwrap());
        if p.is_dir() {
            copy_dir(&p, &dest);
        } else {
            std::fs::copy(&p, &dest).unwrap();
        }
    }
}

/// One bad input: its own files (name, contents), the arguments, and text the message must hold.
struct Case {
    name: &'static str,
    files: Vec<(&'static str, Vec<u8>)>,
    args: Vec<&'static str>,
    expect: &'static str,
}

fn case(
    name: &'static str,
    files: &[(&'static str, &str)],
    args: &[&'static str],
    expect: &'static str,
) -> Case {
    Case {
        name,
        files: files
            .iter()
            .map(|(n, c)| (*n, c.as_bytes().to_vec()))
            .collect(),
        args: args.to_vec(),
        expect,
    }
}

/// The bad-input files: `tests/bad-input/` at the top of the repository.
fn bad_input_dir() -> PathBuf {
    root().join("tests/bad-input")
}

/// The bad-input files the cases read, so that none is left unread.
static READ: Mutex<BTreeSet<PathBuf>> = Mutex::new(BTreeSet::new());

/// The bytes of the bad-input file `path` (under `tests/bad-input/`).
fn input_bytes(path: &str) -> Vec<u8> {
    let p = bad_input_dir().join(path);
    let bytes = std::fs::read(&p).unwrap_or_else(|e| panic!("{}: {e}", p.display()));
    READ.lock().unwrap().insert(p);
    bytes
}

/// The text of the bad-input file `path` (under `tests/bad-input/`).
fn input(path: &str) -> String {
    String::from_utf8(input_bytes(path)).unwrap_or_else(|e| panic!("{path}: {e}"))
}

/// The good session and profile every case starts from, as JSON, to be edited into bad ones.
struct Good {
    session: serde_json::Value,
    profile: serde_json::Value,
    /// The written variant's `manifest.json`.
    manifest: serde_json::Value,
}

impl Good {
    /// The good session with `edit` applied, as text.
    fn session(&self, edit: &dyn Fn(&mut serde_json::Value)) -> String {
        let mut v = self.session.clone();
        edit(&mut v);
        serde_json::to_string(&v).unwrap()
    }

    /// The written variant's manifest with `edit` applied, as text.
    fn manifest(&self, edit: &dyn Fn(&mut serde_json::Value)) -> String {
        let mut v = self.manifest.clone();
        edit(&mut v);
        serde_json::to_string(&v).unwrap()
    }

    /// The good profile with `edit` applied, as text.
    fn profile(&self, edit: &dyn Fn(&mut serde_json::Value)) -> String {
        let mut v = self.profile.clone();
        edit(&mut v);
        serde_json::to_string(&v).unwrap()
    }
}

/// `render good.wgsl` over the session `file`, two frames.
fn render_with(file: &'static str) -> Vec<&'static str> {
    vec![
        "render",
        "good.wgsl",
        "--session",
        file,
        "--max-frames",
        "2",
    ]
}

/// `emit` at a budget of 0.01 from the profile `file`.
fn emit_with(file: &'static str) -> Vec<&'static str> {
    vec![
        "emit",
        "--max-error",
        "0.01",
        "--profile",
        file,
        "--out",
        "out",
    ]
}

/// Every case, by topic.
fn cases(good: &Good) -> Vec<Case> {
    let mut v = shaders::cases();
    v.extend(sessions::cases(good));
    v.extend(variants::cases(good));
    v.extend(arguments::cases());
    v.extend(profiles::cases(good));
    v
}

#[test]
fn every_bad_input_exits_2_with_one_clear_message_and_writes_nothing() {
    let base = tempfile::tempdir().unwrap();
    let good = base.path().join("good");
    std::fs::create_dir_all(&good).unwrap();
    let data = root().join("crates/reproj-replay/tests/data");
    std::fs::copy(data.join("tiny.wgsl"), good.join("good.wgsl")).unwrap();
    std::fs::copy(data.join("tiny_moving.json"), good.join("good.json")).unwrap();
    let (code, _, err) = run(
        &good,
        &[
            "analyze",
            "good.wgsl",
            "--session",
            "good.json",
            "--out",
            "good.profile.json",
            "--delta-n",
            "2,4",
            "--holdout",
            "3",
            "--max-nodes",
            "2",
            "--strategy",
            "3pass",
            "--no-charts",
            // The tiny shader costs less than a variant's own passes: profiled all the same,
            // for a profile with nodes to break.
            "--no-ceiling",
        ],
    );
    assert_eq!(code, 0, "{err}");
    let (code, _, err) = run(
        &good,
        &[
            "instance",
            "good.wgsl",
            "--node",
            "root",
            "--out",
            "variant",
        ],
    );
    assert_eq!(code, 0, "{err}");
    let read = |n: &str| -> serde_json::Value {
        serde_json::from_str(&std::fs::read_to_string(good.join(n)).unwrap()).unwrap()
    };
    let all = cases(&Good {
        session: read("good.json"),
        profile: read("good.profile.json"),
        manifest: read("variant/manifest.json"),
    });
    assert!(all.len() >= 50, "{} cases", all.len());
    let inputs = bad_input_dir();
    let on_disk: BTreeSet<PathBuf> = files(&inputs)
        .into_iter()
        .filter(|p| p.is_file() && p.file_name().is_some_and(|n| n != "README.md"))
        .collect();
    let unread: Vec<_> = on_disk
        .difference(&READ.lock().unwrap())
        .map(|p| p.strip_prefix(&inputs).unwrap().display().to_string())
        .collect();
    assert!(
        unread.is_empty(),
        "bad-input files no case reads: {unread:?}"
    );
    let mut failures = Vec::new();
    for (i, c) in all.iter().enumerate() {
        let dir = base.path().join(format!("case{i}"));
        copy_dir(&good, &dir);
        for (name, bytes) in &c.files {
            let p = dir.join(name);
            std::fs::create_dir_all(p.parent().unwrap()).unwrap();
            std::fs::write(p, bytes).unwrap();
        }
        let before = files(&dir);
        let (code, _, err) = run(&dir, &c.args);
        let after = files(&dir);
        let mut wrong = Vec::new();
        if code != 2 {
            wrong.push(format!("exit {code}"));
        }
        if err.contains("panicked") || err.contains("RUST_BACKTRACE") {
            wrong.push("panic".into());
        }
        if err.contains("root:x:0:0") {
            wrong.push("echoed /etc/passwd".into());
        }
        if !err.contains(c.expect) {
            wrong.push(format!("no `{}` in the message", c.expect));
        }
        let errors = err.lines().filter(|l| l.starts_with("error")).count();
        if errors != 1 {
            wrong.push(format!("{errors} `error` lines"));
        }
        for (name, bytes) in &c.files {
            if std::fs::read(dir.join(name)).ok().as_deref() != Some(bytes.as_slice()) {
                wrong.push(format!("changed {name}"));
            }
        }
        let new: Vec<_> = after.difference(&before).collect();
        if !new.is_empty() {
            wrong.push(format!("wrote {new:?}"));
        }
        if !wrong.is_empty() {
            failures.push(format!("{}: {} — stderr:\n{err}", c.name, wrong.join(", ")));
        }
    }
    assert!(
        failures.is_empty(),
        "{} of {} bad inputs misbehave:\n{}",
        failures.len(),
        all.len(),
        failures.join("\n")
    );
}
