//! A shader that computes in half floats (`enable f16;`) renders, and so do its variants: the
//! directive survives every pass, and the replay asks the device for SHADER_F16 (an adapter
//! without it is refused with a message naming the feature, exit 2; lavapipe has it).

use crate::common::{root, run};

#[test]
fn an_f16_shader_and_its_variant_render() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    std::fs::copy(
        root().join("crates/reproj-instance/tests/fixtures/f16.wgsl"),
        dir.join("h.wgsl"),
    )
    .unwrap();
    std::fs::copy(
        root().join("crates/reproj-replay/tests/data/tiny_moving.json"),
        dir.join("s.json"),
    )
    .unwrap();
    let (code, _, err) = run(dir, &["render", "h.wgsl", "--session", "s.json"]);
    assert_eq!(code, 0, "{err}");
    let (code, _, err) = run(dir, &["instance", "h.wgsl", "--node", "root", "--out", "v"]);
    assert_eq!(code, 0, "{err}");
    let (code, out, err) = run(
        dir,
        &[
            "render",
            "h.wgsl",
            "--session",
            "s.json",
            "--variant",
            "v",
            "--json",
        ],
    );
    assert_eq!(code, 0, "{err}");
    let r: serde_json::Value = serde_json::from_str(out.lines().collect::<String>().as_str())
        .unwrap_or_else(|_| serde_json::from_str(&out).unwrap());
    assert!(r["error"].as_f64().unwrap().is_finite(), "{out}");
}
