//! Written variants through the real binary: `instance --group/--frame-load` and `render --variant`.

use crate::common;
use crate::common::root;

fn reproj(args: &[&str]) -> (i32, String, String) {
    common::run(&root(), args)
}

const TINY: &str = "crates/reproj-replay/tests/data/tiny.wgsl";
const SESSION: &str = "crates/reproj-replay/tests/data/tiny_moving.json";

fn json(stdout: &str) -> serde_json::Value {
    serde_json::from_str(stdout).unwrap_or_else(|e| panic!("{e}: {stdout}"))
}

/// A group past WebGPU's four: exit 2, one message, nothing written. (A group the shader uses is
/// shared: the variant's bindings go past the shader's own there.)
#[test]
fn a_group_past_the_four_is_a_user_error() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("v");
    let (code, _, err) = reproj(&[
        "instance",
        "shaders/marble.wgsl",
        "--node",
        "root",
        "--group",
        "4",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("bind group 4"), "{err}");
    assert!(!out.exists());
}

/// `render --variant DIR` renders what `instance` wrote exactly as `render --node` renders the same
/// variant, and the integration options (`--group`, `--load frame,depth`, and the hidden
/// `--depth-load load` it replaces) change nothing in the frames.
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
    for (i, extra) in [
        &[][..],
        &["--group", "3", "--load", "frame"][..],
        &["--load", "depth,frame", "--group", "2"][..],
        &["--depth-load", "load"][..],
    ]
    .into_iter()
    .enumerate()
    {
        let v = dir.path().join(format!("v{i}"));
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
        let by_dir = render_variant(&v);
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

/// `instance --reproject motion-vectors` writes a variant that reads the engine's motion vectors
/// (the manifest says so, and asks the vertex stage for nothing), and `render --variant` draws
/// them: the cache is reused, but never more than through the vertex path. This session turns the
/// camera 5° a frame around a sphere 3.5 radii away: a surface point's depth changes by up to ~3 %
/// a frame, more than the depth tolerance (0.01), and the motion-vector hit test, which compares
/// the previous depth with the current one (the vertex path knows the point's own previous
/// depth), misses there: 0.17 against 0.69 (docs/PASSES.md, "Reprojection").
#[test]
fn a_motion_vector_variant_renders_through_the_binary() {
    let dir = tempfile::tempdir().unwrap();
    let mut rates = Vec::new();
    for reproject in ["vertex", "motion-vectors"] {
        let v = dir.path().join(reproject);
        let (code, out, err) = reproj(&[
            "instance",
            TINY,
            "--node",
            "35",
            "--delta-n",
            "4",
            "--reproject",
            reproject,
            "--out",
            v.to_str().unwrap(),
        ]);
        assert_eq!(code, 0, "{err}");
        let manifest = json(&std::fs::read_to_string(v.join("manifest.json")).unwrap());
        let motion = reproject == "motion-vectors";
        assert_eq!(out.contains("motion vectors at binding 6"), motion, "{out}");
        assert_eq!(
            manifest["reprojection"].as_str(),
            motion.then_some("motion_vectors")
        );
        assert_eq!(manifest["vertex"]["prev_clip_location"].is_null(), motion);
        rates.push(render_variant(&v)["hit_rate"].as_f64().unwrap());
    }
    assert!(rates[1] > 0.05 && rates[1] <= rates[0] + 0.01, "{rates:?}");
}

/// `render --variant DIR --json` over the first 6 frames of the tiny session: its report.
fn render_variant(dir: &std::path::Path) -> serde_json::Value {
    let (code, out, err) = reproj(&[
        "render",
        TINY,
        "--session",
        SESSION,
        "--variant",
        dir.to_str().unwrap(),
        "--max-frames",
        "6",
        "--json",
    ]);
    assert_eq!(code, 0, "{err}");
    json(&out)
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
