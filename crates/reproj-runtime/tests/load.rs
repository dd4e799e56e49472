//! `Variant::load` without a GPU: a variant `reproj instance` writes loads, each broken
//! manifest is an error naming the file and the field, never a panic, and its files are read as
//! the CLI reads its inputs (no pipe waited on, no link out of the folder, a size limit).

use std::path::Path;

use reproj_runtime::{FileError, ReadLimits, RuntimeError, Variant};
use serde_json::{Value, json};

use crate::common::instance_marble;

/// A copy of `dir` in `to` whose manifest is `edit`ed.
fn edited(dir: &Path, to: &Path, edit: impl FnOnce(&mut Value)) {
    std::fs::create_dir_all(to).unwrap();
    for e in std::fs::read_dir(dir).unwrap() {
        let e = e.unwrap();
        std::fs::copy(e.path(), to.join(e.file_name())).unwrap();
    }
    let mut m: Value =
        serde_json::from_slice(&std::fs::read(dir.join("manifest.json")).unwrap()).unwrap();
    edit(&mut m);
    std::fs::write(to.join("manifest.json"), serde_json::to_string(&m).unwrap()).unwrap();
}

#[test]
fn an_emitted_variant_loads_with_its_contract() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path().join("v");
    instance_marble(&dir, &["--strategy", "3pass", "--group", "2"]);
    let v = Variant::load(&dir).unwrap();
    assert_eq!(v.pass_count(), 3);
    // Reproject and recompute draw into the cache and share a render pass; shade draws the frame.
    assert_eq!(v.render_passes(), [0..2, 2..3]);
    assert_eq!(v.render_pass_count(), 2);
    // Both passes of 2pass draw the frame and the cache: one render pass.
    let two = tmp.path().join("v2");
    instance_marble(&two, &["--strategy", "2pass"]);
    let v2 = Variant::load(&two).unwrap();
    assert_eq!(v2.pass_count(), 2);
    assert_eq!(v2.render_passes(), [std::ops::Range { start: 0, end: 2 }]);
    assert_eq!(v.group(), 2);
    // marble's `scene` uniform is the application's, in group 0.
    assert_eq!(v.own_groups().into_iter().collect::<Vec<_>>(), [0]);
    assert_eq!(v.reserved_groups().into_iter().collect::<Vec<_>>(), [0, 2]);
    assert_eq!(v.delta_n(), Some(8));
    assert!(!v.loads_frame_first());
    assert!(
        v.scheduled_delta_n(1.0).is_none(),
        "instance writes no schedule"
    );
    // Two payloads and two r32float depth copies, between 2 × 2 + 8 and 2 × 16 + 8 bytes.
    let bpp = v.bytes_per_pixel();
    assert!((12..=40).contains(&bpp), "{bpp} bytes per pixel");
    let payload = v
        .manifest()
        .textures
        .iter()
        .find(|t| t.name == "payload_0")
        .unwrap();
    let texel = match payload.format.as_str() {
        "r16float" => 2,
        "rg16float" | "r32float" => 4,
        "rgba16float" | "rg32float" => 8,
        "rgba32float" => 16,
        other => panic!("payload format {other}"),
    };
    assert_eq!(bpp, 2 * texel + 8);
}

#[test]
fn a_broken_manifest_names_the_file_and_the_field() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path().join("v");
    instance_marble(&dir, &["--strategy", "3pass"]);
    type Edit = fn(&mut Value);
    let cases: [(&str, Edit, &str); 10] = [
        (
            "schema",
            |m| m["schema"] = json!("reproj.session"),
            "`schema` is \"reproj.session\"",
        ),
        (
            "version",
            |m| m["version"] = json!(99),
            "manifest version 99 is not supported",
        ),
        (
            "format",
            |m| m["textures"][0]["format"] = json!("rgb9000"),
            "`textures[0].format`: unknown texture format `rgb9000`",
        ),
        ("type", |m| m["passes"] = json!(5), "`passes`"),
        (
            "missing",
            |m| {
                m["passes"][0]
                    .as_object_mut()
                    .unwrap()
                    .remove("entry")
                    .map(drop)
                    .unwrap()
            },
            "`passes[0]`",
        ),
        (
            "role",
            |m| m["passes"][1]["depth"]["attachment"] = json!("nobody"),
            "`passes[1].depth.attachment`: no texture plays the role `nobody`",
        ),
        (
            "offset",
            |m| m["params"]["fields"][0]["offset"] = json!(64),
            "`params.fields[0].offset`",
        ),
        (
            "blend",
            |m| m["passes"][2]["colors"][0]["blend"] = json!("add"),
            "`passes[2].colors[0].blend`",
        ),
        (
            "file",
            |m| m["passes"][0]["file"] = json!("../elsewhere.wgsl"),
            "`passes[0].file`",
        ),
        (
            "own",
            |m| m["passes"][1]["bindings"][0]["resource"] = json!({"kind": "params"}),
            "`passes[1].bindings[0].resource`",
        ),
    ];
    for (name, edit, expected) in cases {
        let to = tmp.path().join(name);
        edited(&dir, &to, edit);
        let e = Variant::load(&to).expect_err(name);
        let text = e.to_string();
        let file = to.join("manifest.json");
        assert!(
            text.starts_with(&file.display().to_string()),
            "{name}: `{text}` does not name {}",
            file.display()
        );
        assert!(
            text.contains(expected),
            "{name}: `{text}` lacks `{expected}`"
        );
    }

    // A pass file that is not there: the error names it.
    let to = tmp.path().join("no-pass");
    edited(&dir, &to, |_| {});
    let file = Variant::load(&to).unwrap().manifest().passes[1]
        .file
        .clone();
    std::fs::remove_file(to.join(&file)).unwrap();
    match Variant::load(&to) {
        Err(RuntimeError::File(e)) => assert_eq!(e.path(), to.join(&file)),
        other => panic!("a missing pass file: {other:?}"),
    }
    // Not JSON at all.
    std::fs::write(to.join("manifest.json"), "{ not json").unwrap();
    let text = Variant::load(&to).unwrap_err().to_string();
    assert!(
        text.contains("manifest.json") && text.contains("not JSON"),
        "{text}"
    );
}

/// The CLI's door rules: a pass linked out of the variant's folder is refused at its field, a
/// pass past the limit names the limit to raise (and `load_with` raises it), and a manifest that
/// is a named pipe is refused without being waited on.
#[cfg(unix)]
#[test]
fn files_are_read_as_the_cli_reads_its_inputs() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path().join("v");
    instance_marble(&dir, &["--strategy", "3pass"]);
    let passes: Vec<String> = Variant::load(&dir)
        .unwrap()
        .manifest()
        .passes
        .iter()
        .map(|p| p.file.clone())
        .collect();

    // A pass that is a link to a file elsewhere: its text is never read.
    let to = tmp.path().join("linked");
    edited(&dir, &to, |_| {});
    let outside = tmp.path().join("outside.wgsl");
    std::fs::rename(to.join(&passes[0]), &outside).unwrap();
    std::os::unix::fs::symlink(&outside, to.join(&passes[0])).unwrap();
    let text = Variant::load(&to).unwrap_err().to_string();
    assert!(
        text.contains("`passes[0].file`") && text.contains("a link out of the variant's directory"),
        "{text}"
    );

    // Past the limit: the largest pass is refused, naming it and the limit to raise.
    let (largest, size) = passes
        .iter()
        .map(|f| (f, std::fs::metadata(dir.join(f)).unwrap().len()))
        .max_by_key(|&(_, n)| n)
        .unwrap();
    let small = ReadLimits {
        shader_bytes: size - 1,
        ..ReadLimits::default()
    };
    match Variant::load_with(&dir, &small) {
        Err(RuntimeError::File(e @ FileError::TooLarge { .. })) => {
            assert_eq!(e.path(), dir.join(largest));
            assert!(e.to_string().contains("ReadLimits::shader_bytes"), "{e}");
        }
        other => panic!("a pass past the limit: {other:?}"),
    }
    let enough = ReadLimits {
        shader_bytes: size,
        ..small
    };
    assert_eq!(
        Variant::load_with(&dir, &enough).unwrap().pass_count(),
        passes.len()
    );

    // A manifest that is a named pipe: refused before it is opened (opening would block).
    let piped = tmp.path().join("piped");
    std::fs::create_dir(&piped).unwrap();
    let made = std::process::Command::new("mkfifo")
        .arg(piped.join("manifest.json"))
        .status()
        .is_ok_and(|s| s.success());
    assert!(made, "mkfifo");
    match Variant::load(&piped) {
        Err(RuntimeError::File(FileError::NotAFile { what, .. })) => {
            assert_eq!(what, "a named pipe")
        }
        other => panic!("a manifest that is a pipe: {other:?}"),
    }
}
