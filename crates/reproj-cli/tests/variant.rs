//! Written variants through the real binary: `instance --group/--frame-load` and `render --variant`.

mod common;
use common::root;

fn reproj(args: &[&str]) -> (i32, String, String) {
    common::run(&root(), args)
}

const TINY: &str = "crates/reproj-replay/tests/data/tiny.wgsl";
const SESSION: &str = "crates/reproj-replay/tests/data/tiny_moving.json";

fn json(stdout: &str) -> serde_json::Value {
    serde_json::from_str(stdout).unwrap_or_else(|e| panic!("{e}: {stdout}"))
}

/// A group the shader uses, or one past WebGPU's four: exit 2, one message, nothing written.
#[test]
fn a_taken_group_is_a_user_error() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("v");
    for group in ["0", "4"] {
        let (code, _, err) = reproj(&[
            "instance",
            "shaders/marble.wgsl",
            "--node",
            "root",
            "--group",
            group,
            "--out",
            out.to_str().unwrap(),
        ]);
        assert_eq!(code, 2, "{err}");
        assert!(err.contains(&format!("bind group {group}")), "{err}");
        assert!(!out.exists());
    }
}

/// `render --variant DIR` renders what `instance` wrote exactly as `render --node` renders the same
/// variant, and the integration options (`--group`, `--frame-load load`) change nothing in the
/// frames.
#[test]
fn render_variant_matches_render_node() {
    let dir = tempfile::tempdir().unwrap();
    let common = ["--block", "2", "--depth-epsilon", "0.0001"];
    let by_node = {
        let mut a = vec![
            "render",
            TINY,
            "--session",
            SESSION,
            "--node",
            "35",
            "--delta-n",
            "4",
            "--max-frames",
            "6",
            "--json",
        ];
        a.extend(common);
        let (code, out, err) = reproj(&a);
        assert_eq!(code, 0, "{err}");
        json(&out)
    };
    for extra in [&[][..], &["--group", "3", "--frame-load", "load"][..]] {
        let v = dir.path().join(format!("v{}", extra.len()));
        let mut a = vec![
            "instance",
            TINY,
            "--node",
            "35",
            "--delta-n",
            "4",
            "--out",
            v.to_str().unwrap(),
        ];
        a.extend(common);
        a.extend(extra);
        let (code, _, err) = reproj(&a);
        assert_eq!(code, 0, "{err}");
        let (code, out, err) = reproj(&[
            "render",
            TINY,
            "--session",
            SESSION,
            "--variant",
            v.to_str().unwrap(),
            "--max-frames",
            "6",
            "--json",
        ]);
        assert_eq!(code, 0, "{err}");
        let by_dir = json(&out);
        assert_eq!(by_dir["delta_n"], 4, "the manifest's Δn");
        for key in ["error", "hit_rate", "psnr"] {
            let (a, b) = (
                by_node[key].as_f64().unwrap(),
                by_dir[key].as_f64().unwrap(),
            );
            assert!((a - b).abs() <= 1e-6, "{key} {extra:?}: {a} vs {b}");
        }
    }
}

#[test]
fn render_variant_of_a_missing_directory_is_a_user_error() {
    let (code, _, err) = reproj(&[
        "render",
        TINY,
        "--session",
        SESSION,
        "--variant",
        "no/such/dir",
    ]);
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("no/such/dir"), "{err}");
}
