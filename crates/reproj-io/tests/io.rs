//! The writer keeps the previous output on failure; the reader names what is wrong.

use std::path::Path;

use reproj_io::{
    FAIL_ENV, Kind, ReadError, Replace, StagedDir, WriteError, parse_json, write_file,
};

fn names(dir: &Path) -> Vec<String> {
    let mut v: Vec<String> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    v.sort();
    v
}

#[test]
fn writers_keep_the_previous_output_on_failure() {
    let tmp = tempfile::tempdir().unwrap();
    let file = tmp.path().join("a/report.json");
    write_file(&file, b"one").unwrap();
    write_file(&file, b"two").unwrap();
    assert_eq!(std::fs::read(&file).unwrap(), b"two");

    // (The hook is set for a child process in the next test: edition 2024's `set_var` is unsafe.)
    // A directory in place of the file: the rename fails, the temp file is gone.
    let blocked = tmp.path().join("a/blocked");
    std::fs::create_dir_all(blocked.join("x")).unwrap();
    let err = write_file(&blocked, b"x").unwrap_err();
    assert!(matches!(err, WriteError::Io { .. }), "{err}");
    assert_eq!(names(&tmp.path().join("a")), ["blocked", "report.json"]);

    // A staged directory replaces the old one whole; one dropped uncommitted leaves no trace.
    let out = tmp.path().join("out");
    let s = StagedDir::new(&out, Replace::OwnFiles(&["wgsl", "json"])).unwrap();
    s.write("a.wgsl", b"1").unwrap();
    s.write("manifest.json", b"{}").unwrap();
    s.commit().unwrap();
    let s = StagedDir::new(&out, Replace::OwnFiles(&["wgsl", "json"])).unwrap();
    s.write("b.wgsl", b"2").unwrap();
    drop(s);
    assert_eq!(names(&out), ["a.wgsl", "manifest.json"]);
    assert_eq!(names(tmp.path()), ["a", "out"], "no staging directory left");
    let s = StagedDir::new(&out, Replace::OwnFiles(&["wgsl", "json"])).unwrap();
    s.write("b.wgsl", b"2").unwrap();
    s.commit().unwrap();
    assert_eq!(
        names(&out),
        ["b.wgsl"],
        "stale files go with the old directory"
    );
    assert_eq!(
        names(tmp.path()),
        ["a", "out"],
        "the old directory is removed"
    );

    // A foreign file or a subdirectory makes it refuse, and nothing is written.
    std::fs::write(out.join("notes.txt"), b"mine").unwrap();
    let err = StagedDir::new(&out, Replace::OwnFiles(&["wgsl", "json"])).unwrap_err();
    assert!(err.to_string().contains("`notes.txt`"), "{err}");
    let err = StagedDir::new(&file, Replace::OwnFiles(&["json"])).unwrap_err();
    assert!(err.to_string().contains("not a directory"), "{err}");
    assert_eq!(names(tmp.path()), ["a", "out"]);
}

#[test]
fn the_failure_hook_fails_the_named_write_in_a_child_process() {
    // Re-run this test binary's `hook_child` with the hook set: the variable is read per write.
    if std::env::var_os("REPROJ_IO_HOOK_CHILD").is_some() {
        return;
    }
    let tmp = tempfile::tempdir().unwrap();
    let status = std::process::Command::new(std::env::current_exe().unwrap())
        .args(["hook_child", "--exact", "--nocapture"])
        .env("REPROJ_IO_HOOK_CHILD", tmp.path())
        .env(FAIL_ENV, "report.json")
        .stdout(std::process::Stdio::null())
        .status()
        .unwrap();
    assert!(status.success());
    assert_eq!(
        std::fs::read(tmp.path().join("report.json")).unwrap(),
        b"old"
    );
    assert_eq!(names(&tmp.path().join("out")), ["a.json"]);
    assert_eq!(
        names(tmp.path()),
        ["out", "report.json"],
        "no temporary left"
    );
}

#[test]
fn hook_child() {
    let Some(dir) = std::env::var_os("REPROJ_IO_HOOK_CHILD") else {
        return;
    };
    let dir = Path::new(&dir);
    let file = dir.join("report.json");
    std::fs::write(&file, b"old").unwrap();
    let err = write_file(&file, b"new").unwrap_err();
    assert!(err.to_string().contains("injected failure"), "{err}");
    // A staged directory whose third file fails keeps the previous directory.
    let out = dir.join("out");
    let s = StagedDir::new(&out, Replace::OwnFiles(&["json"])).unwrap();
    s.write("a.json", b"1").unwrap();
    s.commit().unwrap();
    let s = StagedDir::new(&out, Replace::OwnFiles(&["json"])).unwrap();
    s.write("b.json", b"2").unwrap();
    s.write("c.json", b"3").unwrap();
    assert!(s.write("report.json", b"4").is_err());
    drop(s);
}

#[derive(Debug, serde::Deserialize)]
#[allow(dead_code)]
struct Doc {
    schema: String,
    version: u32,
    items: Vec<Item>,
}

#[derive(Debug, serde::Deserialize)]
#[allow(dead_code)]
struct Item {
    name: String,
}

const KIND: Kind = Kind {
    schema: "reproj.test",
    versions: 2..=3,
    hint: "write it again",
};

fn read(text: &str) -> Result<Doc, ReadError> {
    parse_json(text, Path::new("doc.json"), &KIND)
}

#[test]
fn the_reader_names_what_is_wrong() {
    let ok = read(r#"{"schema": "reproj.test", "version": 3, "items": [{"name": "a"}]}"#).unwrap();
    assert_eq!(ok.items.len(), 1);
    let msg = |t: &str| read(t).unwrap_err().to_string();
    assert_eq!(
        msg("{\n  \"schema\": ,\n}"),
        "doc.json:2:13: not valid JSON: expected value"
    );
    assert_eq!(
        msg(r#"{"version": 3}"#),
        "doc.json: field `schema`: expected \"reproj.test\", found nothing"
    );
    assert_eq!(
        msg(r#"{"schema": "reproj.profile", "version": 3}"#),
        "doc.json: field `schema`: expected \"reproj.test\", found \"reproj.profile\""
    );
    assert_eq!(
        msg(r#"{"schema": "reproj.test", "version": 1}"#),
        "doc.json: field `version`: reproj.test version 1 is not one this reproj reads (versions 2 to 3); write it again"
    );
    assert_eq!(
        msg(r#"{"schema": "reproj.test", "version": "3"}"#),
        "doc.json: field `version`: reproj.test version \"3\" is not one this reproj reads (versions 2 to 3); write it again"
    );
    let m = msg(r#"{"schema": "reproj.test", "version": 2, "items": [{"name": 5}]}"#);
    assert!(
        m.starts_with("doc.json: field `items[0].name`: invalid type: integer `5`"),
        "{m}"
    );
}
