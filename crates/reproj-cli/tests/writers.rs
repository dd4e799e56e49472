//! Every writer keeps the previous output when a write fails mid-way: each command is run once,
//! then again with different settings and `REPROJ_IO_FAIL` naming one of the files it writes
//! late; the tree must be byte for byte what the first run left (no torn file, no mixed
//! directory, no temporary left behind).

use std::collections::BTreeMap;
use std::path::Path;

use crate::common::{root, run, run_env};

/// Every file under `dir`, by relative path, with its bytes.
fn tree(dir: &Path) -> BTreeMap<String, Vec<u8>> {
    fn walk(base: &Path, dir: &Path, out: &mut BTreeMap<String, Vec<u8>>) {
        for e in std::fs::read_dir(dir).unwrap() {
            let p = e.unwrap().path();
            if p.is_dir() {
                walk(base, &p, out);
            } else {
                let name = p.strip_prefix(base).unwrap().display().to_string();
                out.insert(name, std::fs::read(&p).unwrap());
            }
        }
    }
    let mut out = BTreeMap::new();
    walk(dir, dir, &mut out);
    out
}

fn setup() -> tempfile::TempDir {
    let tmp = tempfile::tempdir().unwrap();
    let data = root().join("crates/reproj-replay/tests/data");
    std::fs::copy(data.join("tiny.wgsl"), tmp.path().join("tiny.wgsl")).unwrap();
    std::fs::copy(data.join("tiny_moving.json"), tmp.path().join("tiny.json")).unwrap();
    tmp
}

/// Run `first` (must succeed), then `second` with the write of `fail` failing: it must fail with
/// one message naming the injected failure and leave every file as `first` left it, except those
/// whose name ends in one of `may_change`.
fn check(dir: &Path, first: &[&str], second: &[&str], fail: &str, may_change: &[&str]) {
    let (code, _, err) = run(dir, first);
    assert_eq!(code, 0, "{first:?}: {err}");
    let keep = |t: BTreeMap<String, Vec<u8>>| -> BTreeMap<String, Vec<u8>> {
        t.into_iter()
            .filter(|(k, _)| !may_change.iter().any(|m| k.ends_with(m)))
            .collect()
    };
    let before = keep(tree(dir));
    assert!(
        before.keys().any(|k| k.ends_with(fail)),
        "{fail} was not written by {first:?}: {:?}",
        before.keys().collect::<Vec<_>>()
    );
    let (code, _, err) = run_env(dir, second, &[("REPROJ_IO_FAIL", fail)]);
    assert_ne!(code, 0, "{second:?} succeeded despite the failure:\n{err}");
    assert!(err.contains("injected failure"), "{second:?}: {err}");
    let after = keep(tree(dir));
    let changed: Vec<&String> = before
        .keys()
        .chain(after.keys())
        .filter(|k| before.get(*k) != after.get(*k))
        .collect();
    assert!(changed.is_empty(), "{second:?} changed {changed:?}");
}

#[test]
fn instance_keeps_the_previous_variant_directory() {
    let tmp = setup();
    check(
        tmp.path(),
        &["instance", "tiny.wgsl", "--node", "root", "--out", "v"],
        &[
            "instance",
            "tiny.wgsl",
            "--node",
            "root",
            "--strategy",
            "2pass",
            "--out",
            "v",
        ],
        "manifest.json",
        &[],
    );
}

#[test]
fn render_keeps_the_previous_frames_directory() {
    let tmp = setup();
    let args = |dn: &'static str| {
        vec![
            "render",
            "tiny.wgsl",
            "--session",
            "tiny.json",
            "--node",
            "root",
            "--delta-n",
            dn,
            "--max-frames",
            "4",
            "--frames",
            "f",
        ]
    };
    check(tmp.path(), &args("2"), &args("3"), "errmap_002.png", &[]);
}

fn analyze<'a>(dn: &'a str, extra: &[&'a str]) -> Vec<&'a str> {
    let mut a = vec![
        "analyze",
        "tiny.wgsl",
        "--session",
        "tiny.json",
        "--out",
        "p.profile.json",
        "--delta-n",
        dn,
        "--holdout",
        "6",
        "--max-nodes",
        "2",
        "--max-frames",
        "12",
        "--fresh",
    ];
    a.extend(extra);
    a
}

#[test]
fn analyze_keeps_the_previous_profile_and_resumes_from_its_journal() {
    let tmp = setup();
    // The journal of the failed run stays (that is what resuming reads).
    check(
        tmp.path(),
        &analyze("2,4", &["--no-charts"]),
        &analyze("2,8", &["--no-charts"]),
        "p.profile.json",
        &["p.profile.journal"],
    );
    assert!(tmp.path().join("p.profile.journal").exists());
}

#[test]
fn analyze_keeps_every_previous_chart() {
    let tmp = setup();
    // The profile is written before the charts: only the charts must stay all old.
    check(
        tmp.path(),
        &analyze("2,4", &[]),
        &analyze("2,8", &[]),
        "p.models.png",
        &["p.profile.json", "p.profile.journal"],
    );
}

#[test]
fn emit_and_merge_keep_their_previous_output() {
    let tmp = setup();
    let (code, _, err) = run(tmp.path(), &analyze("2,4,8", &["--no-charts"]));
    assert_eq!(code, 0, "{err}");
    let emit = |budget: &'static str| {
        vec![
            "emit",
            "--max-error",
            budget,
            "--profile",
            "p.profile.json",
            "--out",
            "e",
        ]
    };
    check(
        tmp.path(),
        &emit("1"),
        &emit("0.000001"),
        "report.json",
        &[],
    );
    // Two sets of shards of different analyses, merged to the same place.
    for (dn, set) in [("2,4", "a"), ("2,8", "b")] {
        for i in ["0", "1"] {
            let shard = format!("{i}/2");
            let out = format!("{set}{i}.profile.json");
            let mut args = analyze(dn, &["--no-charts", "--shard", &shard]);
            args[5] = &out;
            let (code, _, err) = run(tmp.path(), &args);
            assert_eq!(code, 0, "{err}");
        }
    }
    check(
        tmp.path(),
        &[
            "merge",
            "a0.profile.json",
            "a1.profile.json",
            "--out",
            "m.profile.json",
        ],
        &[
            "merge",
            "b0.profile.json",
            "b1.profile.json",
            "--out",
            "m.profile.json",
        ],
        "m.profile.json",
        &[],
    );
}

#[test]
fn report_keeps_the_previous_page() {
    let tmp = setup();
    for (dn, out) in [("2,4", "a.profile.json"), ("2,8", "b.profile.json")] {
        let mut args = analyze(dn, &["--no-charts"]);
        args[5] = out;
        let (code, _, err) = run(tmp.path(), &args);
        assert_eq!(code, 0, "{err}");
    }
    check(
        tmp.path(),
        &[
            "report",
            "a.profile.json",
            "--out",
            "r.html",
            "--max-rendered",
            "1",
        ],
        &[
            "report",
            "b.profile.json",
            "--out",
            "r.html",
            "--max-rendered",
            "1",
        ],
        "r.html",
        &[],
    );
}
