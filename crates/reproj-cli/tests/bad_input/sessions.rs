//! Bad sessions: missing, not JSON, another schema or version, fields missing, out of range or
//! unknown, the shader's resources left out; files outside the session's folder; work too large
//! for the adapter or the machine; and scenes that would score nothing (no pixel covered).

use super::{Case, Good, case, input, input_bytes, render_with};

pub(super) fn cases(good: &Good) -> Vec<Case> {
    let session = |edit: &dyn Fn(&mut serde_json::Value)| good.session(edit);
    let mut v = vec![
        // Sessions.
        case(
            "missing session",
            &[],
            &["render", "good.wgsl", "--session", "missing.json"],
            "missing.json",
        ),
        case(
            "session not JSON",
            &[("s.json", &input("sessions/not_json.json"))],
            &render_with("s.json"),
            "s.json",
        ),
        case(
            "session empty",
            &[("s.json", &input("sessions/empty.json"))],
            &render_with("s.json"),
            "s.json",
        ),
        case(
            "session of another schema",
            &[(
                "s.json",
                &session(&|v| v["schema"] = "reproj.profile".into()),
            )],
            &render_with("s.json"),
            "schema",
        ),
        case(
            "session version 99",
            &[("s.json", &session(&|v| v["version"] = 99.into()))],
            &render_with("s.json"),
            "version",
        ),
        case(
            "session without resolution",
            &[(
                "s.json",
                &session(&|v| {
                    v.as_object_mut().unwrap().remove("resolution");
                }),
            )],
            &render_with("s.json"),
            "resolution",
        ),
        case(
            "session resolution zero",
            &[(
                "s.json",
                &session(&|v| v["resolution"] = serde_json::json!([0, 64])),
            )],
            &render_with("s.json"),
            "resolution",
        ),
        case(
            "session resolution huge",
            &[(
                "s.json",
                &session(&|v| v["resolution"] = serde_json::json!([100000, 64])),
            )],
            &render_with("s.json"),
            "resolution",
        ),
        case(
            "session frames as text",
            &[("s.json", &session(&|v| v["frames"] = "ten".into()))],
            &render_with("s.json"),
            "frames",
        ),
        case(
            "session negative fps",
            &[("s.json", &session(&|v| v["fps"] = (-30).into()))],
            &render_with("s.json"),
            "fps",
        ),
        case(
            "session unknown field",
            &[("s.json", &session(&|v| v["colour"] = 1.into()))],
            &render_with("s.json"),
            "colour",
        ),
        case(
            "session without the shader's texture",
            &[(
                "s.json",
                &session(&|v| {
                    v["textures"].as_object_mut().unwrap().clear();
                }),
            )],
            &render_with("s.json"),
            "albedo_map",
        ),
        case(
            "session without the shader's uniform",
            &[(
                "s.json",
                &session(&|v| {
                    v["uniforms"].as_object_mut().unwrap().remove("gain");
                }),
            )],
            &render_with("s.json"),
            "gain",
        ),
        case(
            "session camera without keys",
            &[(
                "s.json",
                &session(&|v| v["camera"] = serde_json::json!({"keys": []})),
            )],
            &render_with("s.json"),
            "camera",
        ),
    ];
    // What a session may name: files beside it, never other files of the machine (and their
    // contents never shown).
    v.extend([
        case(
            "session mesh outside its folder",
            &[(
                "s.json",
                &session(&|v| {
                    v["geometry"]["objects"][0]["mesh"] =
                        serde_json::json!({"obj": {"path": "/etc/passwd"}})
                }),
            )],
            &render_with("s.json"),
            "outside the session's folder",
        ),
        case(
            "session texture above its folder",
            &[(
                "s.json",
                &session(&|v| {
                    v["textures"]["albedo_map"] =
                        serde_json::json!({"file": "../../../../../../etc/passwd"})
                }),
            )],
            &render_with("s.json"),
            "outside the session's folder",
        ),
    ]);
    // Work too large for the adapter or the machine: refused before allocating.
    v.extend([
        case(
            "resolution past the largest texture",
            &[(
                "s.json",
                &session(&|v| v["resolution"] = serde_json::json!([40000, 64])),
            )],
            &render_with("s.json"),
            "1..=8192",
        ),
        case(
            "frames past the machine's memory",
            &[(
                "s.json",
                &session(&|v| {
                    v["resolution"] = serde_json::json!([8192, 8192]);
                    v["frames"] = serde_json::json!(400);
                }),
            )],
            &["render", "good.wgsl", "--session", "s.json"],
            "GiB are available",
        ),
    ]);
    // Silent wrong answers: nothing on screen is an error, not PSNR 100.
    v.extend([
        case(
            "camera up along its view",
            &[(
                "s.json",
                &session(&|v| {
                    v["camera"] = serde_json::json!({"keys": [
                        {"eye": [0, 3, 0], "target": [0, 0, 0], "up": [0, 1, 0]}
                    ]})
                }),
            )],
            &render_with("s.json"),
            "covers no pixel",
        ),
        case(
            "object scaled to nothing",
            &[(
                "s.json",
                &session(&|v| {
                    v["geometry"]["objects"][0]["transform"] =
                        serde_json::json!({"keys": [{"scale": 0.0}]})
                }),
            )],
            &render_with("s.json"),
            "covers no pixel",
        ),
    ]);
    // Values a session cannot mean: refused naming the field, not silently changed.
    v.extend([
        case(
            "uniform past the largest f32",
            &[("s.json", &session(&|v| v["uniforms"]["gain"] = 1e39.into()))],
            &render_with("s.json"),
            "uniforms.gain",
        ),
        case(
            "uniform key past the largest f32",
            &[(
                "s.json",
                &session(&|v| {
                    v["uniforms"]["tint"] = serde_json::json!({"keys": [
                        {"frame": 0, "value": [1, 1, 1]},
                        {"frame": 3, "value": [1, -1e39, 1]}
                    ]})
                }),
            )],
            &render_with("s.json"),
            "uniforms.tint.keys[1].value",
        ),
        case(
            "rotation about a zero axis",
            &[(
                "s.json",
                &session(&|v| {
                    v["geometry"]["objects"][0]["transform"]["keys"][1]["rotation"]["axis_angle"]
                        ["axis"] = serde_json::json!([0, 0, 0])
                }),
            )],
            &render_with("s.json"),
            "geometry.objects[0].transform.keys[1].rotation.axis_angle.axis",
        ),
    ]);
    v.push(Case {
        name: "session not UTF-8",
        files: vec![("s.json", input_bytes("sessions/not_utf8.json"))],
        args: render_with("s.json"),
        expect: "s.json",
    });
    v
}
