//! Bad profiles (`emit`, `merge`): missing, not JSON, another schema or version, fields missing
//! or of the wrong type, a changed or missing shader, a file that is no shader, and numbers that
//! are not measurements (checked on read, naming the field).

use super::{Case, Good, case, emit_with, input};

/// The good shader's text (for a file of the same name elsewhere).
fn input_copy_of_good() -> String {
    std::fs::read_to_string(super::root().join("crates/reproj-replay/tests/data/tiny.wgsl"))
        .unwrap()
}

pub(super) fn cases(good: &Good) -> Vec<Case> {
    let profile = |edit: &dyn Fn(&mut serde_json::Value)| good.profile(edit);
    let mut v = vec![
        // Profiles.
        case(
            "missing profile",
            &[],
            &emit_with("missing.profile.json"),
            "missing.profile.json",
        ),
        case(
            "profile not JSON",
            &[("p.json", &input("profiles/not_json.json"))],
            &emit_with("p.json"),
            "p.json",
        ),
        case(
            "profile of another schema",
            &[(
                "p.json",
                &profile(&|v| v["schema"] = "reproj.session".into()),
            )],
            &emit_with("p.json"),
            "schema",
        ),
        case(
            "profile version 99",
            &[("p.json", &profile(&|v| v["version"] = 99.into()))],
            &emit_with("p.json"),
            "version",
        ),
        case(
            "profile without nodes",
            &[(
                "p.json",
                &profile(&|v| {
                    v.as_object_mut().unwrap().remove("nodes");
                }),
            )],
            &emit_with("p.json"),
            "nodes",
        ),
        case(
            "profile with a text frame time",
            &[(
                "p.json",
                &profile(&|v| v["original"]["frame_ms"] = "fast".into()),
            )],
            &emit_with("p.json"),
            "original.frame_ms",
        ),
        case(
            "profile of a changed shader",
            &[(
                "p.json",
                &profile(&|v| v["shader"]["ir_hash"] = "0123456789abcdef".into()),
            )],
            &emit_with("p.json"),
            "changed since",
        ),
        case(
            "profile's shader missing",
            &[(
                "p.json",
                &profile(&|v| v["shader"]["path"] = "gone.wgsl".into()),
            )],
            &emit_with("p.json"),
            "gone.wgsl",
        ),
        case(
            "merge a whole profile",
            &[],
            &["merge", "good.profile.json", "--out", "m.json"],
            "not a shard",
        ),
        case(
            "merge a shard whose index exceeds its count",
            &[(
                "p.json",
                &profile(&|v| v["shard"] = serde_json::json!({"index": 5, "count": 2})),
            )],
            &["merge", "p.json", "--out", "m.json"],
            "p.json: field `shard.index`: 5 is not below `shard.count` 2",
        ),
        case(
            "merge a shard of count 0",
            &[(
                "p.json",
                &profile(&|v| v["shard"] = serde_json::json!({"index": 0, "count": 0})),
            )],
            &["merge", "p.json", "--out", "m.json"],
            "field `shard.index`",
        ),
        case(
            "profile's shader gone, one of its name in the working folder",
            &[
                (
                    "sub/p.json",
                    &profile(&|v| v["shader"]["path"] = "gone.wgsl".into()),
                ),
                ("gone.wgsl", &input_copy_of_good()),
            ],
            &emit_with("sub/p.json"),
            "is not at sub/gone.wgsl",
        ),
        case(
            "merge a missing file",
            &[],
            &["merge", "nope.json", "--out", "m.json"],
            "nope.json",
        ),
        case(
            "profile names a file that is no shader",
            &[(
                "p.json",
                &profile(&|v| v["shader"]["path"] = "/etc/passwd".into()),
            )],
            &emit_with("p.json"),
            "not a shader file",
        ),
    ];
    // A profile's numbers are data: checked on read, naming the field.
    v.extend([
        case(
            "profile negative original time",
            &[(
                "p.json",
                &profile(&|v| v["original"]["frame_ms"] = (-1.0).into()),
            )],
            &emit_with("p.json"),
            "original.frame_ms",
        ),
        case(
            "profile zero original time",
            &[(
                "p.json",
                &profile(&|v| v["original"]["frame_ms"] = 0.0.into()),
            )],
            &emit_with("p.json"),
            "original.frame_ms",
        ),
        case(
            "profile absurd original time",
            &[(
                "p.json",
                &profile(&|v| v["original"]["frame_ms"] = 1e308.into()),
            )],
            &emit_with("p.json"),
            "original.frame_ms",
        ),
    ]);
    // A node's measurements (the good profile is analyzed with `--no-ceiling`: it has nodes).
    assert!(
        good.profile["nodes"]
            .as_array()
            .is_some_and(|n| !n.is_empty()),
        "the good profile has no node"
    );
    {
        v.extend([
            case(
                "profile negative error",
                &[(
                    "p.json",
                    &profile(&|v| v["nodes"][0]["measurements"][0]["error"] = (-0.5).into()),
                )],
                &emit_with("p.json"),
                "nodes[0].measurements[0].error",
            ),
            case(
                "profile hit rate above 1",
                &[(
                    "p.json",
                    &profile(&|v| v["nodes"][0]["measurements"][0]["hit_rate"] = 2.0.into()),
                )],
                &emit_with("p.json"),
                "hit_rate",
            ),
        ]);
    }
    v
}
