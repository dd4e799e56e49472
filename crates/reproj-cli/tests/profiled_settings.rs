//! What `emit` writes is what `analyze` measured: a profile records its variants' reconstruction
//! and cache format, and the emitted manifest uses them (`--cache-format` overrides the format).

mod common;
use common::run;

#[test]
fn emit_writes_the_reconstruction_and_format_the_profile_measured() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    common::two_terms(dir, "t.wgsl", "t.json");
    let (code, _, err) = run(
        dir,
        &[
            "analyze",
            "t.wgsl",
            "--session",
            "t.json",
            "--out",
            "t.profile.json",
            "--delta-n",
            "2,8,16,24",
            "--holdout",
            "4",
            "--max-nodes",
            "3",
            "--strategy",
            "3pass",
            "--no-sets",
            "--no-charts",
            "--reconstruct",
            "catmull-rom",
            "--cache-format",
            "f16",
        ],
    );
    assert_eq!(code, 0, "{err}");
    let read = |p: &str| -> serde_json::Value {
        serde_json::from_str(&std::fs::read_to_string(dir.join(p)).unwrap()).unwrap()
    };
    let profile = read("t.profile.json");
    assert_eq!(profile["reconstruct"], "catmull-rom");
    assert_eq!(profile["cache_format"], "f16");
    let emit = |out: &str, extra: &[&str]| {
        let mut a = vec![
            "emit",
            "--profile",
            "t.profile.json",
            "--max-error",
            "0.05",
            "--out",
            out,
        ];
        a.extend_from_slice(extra);
        run(dir, &a)
    };
    let (code, _, err) = emit("v", &[]);
    assert_eq!(code, 0, "{err}");
    let manifest = read("v/manifest.json");
    assert_eq!(manifest["reconstruct"], "catmull-rom", "{manifest}");
    assert!(
        manifest["cache_format"]
            .as_str()
            .unwrap()
            .contains("16float"),
        "{manifest}"
    );
    // --cache-format overrides the profile's.
    let (code, _, err) = emit("w", &["--cache-format", "f32"]);
    assert_eq!(code, 0, "{err}");
    let manifest = read("w/manifest.json");
    assert!(
        manifest["cache_format"]
            .as_str()
            .unwrap()
            .contains("32float"),
        "{manifest}"
    );
    assert_eq!(manifest["reconstruct"], "catmull-rom");
}
