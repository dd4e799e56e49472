//! End to end, with the real binaries: `reproj instance` writes variants of the marble sample,
//! `reproj render --variant DIR --frames DIR --raw-frames` renders them, `reproj-host` renders
//! them again from their `manifest.json` alone, and the frames must agree; a session the host
//! records while drawing replays to the frames it drew.
//!
//! Frames are compared as floats: both programs write `frame_NNN.f32` (the frame target's exact
//! linear RGBA, width × height × 4 little-endian f32, top row first), and every channel of every
//! pixel of every frame must be within [`TOLERANCE`] = 1e-4 (on lavapipe they are identical: the
//! maximum difference measured is 0, printed by each test). The PNGs are written from those
//! values with the same sRGB encoding, so they agree too.
//!
//! The `reproj` binary is `REPROJ_BIN` if set, else the workspace's test build of it (the
//! runtime's tests' `common/reproj_bin.rs`, included here). The tests need a Vulkan device
//! (lavapipe without a GPU: `scripts/ensure-vulkan.sh`); set `NODEVICE_SELECT=1` and
//! `LP_NUM_THREADS` as for the other rendering tests.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

#[path = "../../../crates/reproj-runtime/tests/common/reproj_bin.rs"]
mod reproj_bin;
use reproj_bin::reproj_bin;

/// Largest allowed difference of any channel of any pixel between two renderers' frames.
const TOLERANCE: f32 = 1e-4;
/// Frames per run: enough for the cache to be reused many times at Δn = 8 (and to wrap the
/// ping-pong several times), short enough for a debug build on two CPU cores.
const FRAMES: u32 = 12;

fn workspace() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

fn host_bin() -> PathBuf {
    PathBuf::from(env!("CARGO_BIN_EXE_reproj-host"))
}

/// Run `bin` with `args` in the workspace root; panic with its output unless it succeeds.
fn run(bin: &Path, args: &[&str]) -> Output {
    let out = Command::new(bin)
        .current_dir(workspace())
        .args(args)
        .env(
            "NODEVICE_SELECT",
            std::env::var("NODEVICE_SELECT").unwrap_or_else(|_| "1".into()),
        )
        .output()
        .expect("starting a binary");
    assert!(
        out.status.success(),
        "{} {} failed ({}):\n{}\n{}",
        bin.display(),
        args.join(" "),
        out.status,
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr)
    );
    out
}

fn s(p: &Path) -> &str {
    p.to_str().expect("UTF-8 temp path")
}

/// `reproj instance shaders/marble.wgsl --node root EXTRA... --out DIR`.
fn instance(dir: &Path, extra: &[&str]) {
    let mut args = vec![
        "instance",
        "shaders/marble.wgsl",
        "--node",
        "root",
        "--out",
        s(dir),
    ];
    args.extend(extra);
    run(&reproj_bin(), &args);
}

/// `reproj render` of the marble session: the original, or the variant in `variant`.
fn reproj_render(variant: Option<&Path>, frames_dir: &Path) {
    reproj_render_session(Path::new("sessions/marble.json"), variant, frames_dir);
}

/// `reproj render` of marble over `session`: the original, or the variant in `variant`.
fn reproj_render_session(session: &Path, variant: Option<&Path>, frames_dir: &Path) {
    let max = FRAMES.to_string();
    let mut args = vec![
        "render",
        "shaders/marble.wgsl",
        "--session",
        s(session),
        "--frames",
        s(frames_dir),
        "--raw-frames",
        "--max-frames",
        &max,
    ];
    if let Some(v) = variant {
        args.extend(["--variant", s(v)]);
    }
    run(&reproj_bin(), &args);
}

/// `reproj-host` over the marble session: `--variant DIR` (with `extra`) or `--original`.
fn host(variant: Option<&Path>, out: &Path, extra: &[&str]) {
    let frames = FRAMES.to_string();
    let mut args = vec![
        "--shader",
        "shaders/marble.wgsl",
        "--session",
        "sessions/marble.json",
        "--frames",
        &frames,
        "--out",
        s(out),
        "--raw",
    ];
    match variant {
        Some(v) => args.extend(["--variant", s(v)]),
        None => args.push("--original"),
    }
    args.extend(extra);
    run(&host_bin(), &args);
    // The summary has one record per frame.
    let summary: serde_json::Value =
        serde_json::from_slice(&std::fs::read(out.join("summary.json")).unwrap()).unwrap();
    assert_eq!(summary["frames"].as_array().unwrap().len(), FRAMES as usize);
    assert!(summary["mean_ms"].as_f64().unwrap() > 0.0);
}

fn read_raw(path: &Path) -> Vec<f32> {
    let bytes = std::fs::read(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    assert!(
        !bytes.is_empty() && bytes.len().is_multiple_of(16),
        "{}",
        path.display()
    );
    bytes
        .chunks_exact(4)
        .map(|b| f32::from_le_bytes([b[0], b[1], b[2], b[3]]))
        .collect()
}

/// The largest difference between the raw frames of two directories (every frame must exist in
/// both), and that the PNGs exist too.
fn max_diff(a: &Path, b: &Path) -> f32 {
    let mut worst = 0.0f32;
    for f in 0..FRAMES {
        let name = format!("frame_{f:03}.f32");
        let (x, y) = (read_raw(&a.join(&name)), read_raw(&b.join(&name)));
        assert_eq!(x.len(), y.len(), "{name}: frame sizes differ");
        for (p, q) in x.iter().zip(&y) {
            assert!(p.is_finite() && q.is_finite(), "{name}: not finite");
            worst = worst.max((p - q).abs());
        }
        for d in [a, b] {
            assert!(d.join(format!("frame_{f:03}.png")).is_file());
        }
    }
    worst
}

fn assert_close(what: &str, a: &Path, b: &Path) {
    let d = max_diff(a, b);
    println!("{what}: max |difference| over {FRAMES} frames = {d:e}");
    assert!(d <= TOLERANCE, "{what}: frames differ by up to {d}");
}

/// The host renders every strategy (and a frame target loaded, not cleared) as `reproj render`
/// does, at the manifest's Δn (8).
#[test]
fn host_matches_reproj_render() {
    let tmp = tempfile::tempdir().unwrap();
    let cases: [(&str, &[&str]); 4] = [
        ("3pass", &["--strategy", "3pass"]),
        ("2pass", &["--strategy", "2pass"]),
        ("fused", &["--strategy", "fused"]),
        (
            "3pass-frame-load",
            &["--strategy", "3pass", "--frame-load", "load"],
        ),
    ];
    for (name, flags) in cases {
        let dir = tmp.path().join(name);
        instance(&dir, flags);
        let reference = tmp.path().join(format!("{name}-render"));
        let hosted = tmp.path().join(format!("{name}-host"));
        reproj_render(Some(&dir), &reference);
        host(Some(&dir), &hosted, &[]);
        assert_close(
            &format!("{name} Δn 8: host vs reproj render"),
            &hosted,
            &reference,
        );
    }
}

/// At Δn = 1 every pixel is refreshed every frame, so the host's variant frames are the original
/// shader's (rendered by `reproj render`, and by the host as the engine did before reproj).
#[test]
fn host_at_delta_n_1_reproduces_the_original() {
    let tmp = tempfile::tempdir().unwrap();
    let original = tmp.path().join("original-render");
    reproj_render(None, &original);
    let host_original = tmp.path().join("original-host");
    host(None, &host_original, &[]);
    assert_close("original: host vs reproj render", &host_original, &original);
    for strategy in ["3pass", "fused"] {
        let dir = tmp.path().join(strategy);
        instance(&dir, &["--strategy", strategy]);
        let hosted = tmp.path().join(format!("{strategy}-host"));
        host(Some(&dir), &hosted, &["--delta-n", "1"]);
        assert_close(
            &format!("{strategy} Δn 1 (host) vs the original (reproj render)"),
            &hosted,
            &original,
        );
    }
}

/// A session the host records while it draws (`--capture`, reproj-runtime's `SessionCapture`)
/// replays with `reproj render` to the frames the host drew: the orbiting camera, the turning
/// torus and the moving light become key frames (model matrices as they are), the rest of the
/// session stays.
#[test]
fn a_session_the_host_records_replays_to_the_frames_it_drew() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path().join("variant");
    instance(&dir, &["--strategy", "2pass"]);
    let captured = tmp.path().join("captured.json");
    let hosted = tmp.path().join("host");
    host(Some(&dir), &hosted, &["--capture", s(&captured)]);
    let session: serde_json::Value =
        serde_json::from_slice(&std::fs::read(&captured).unwrap()).unwrap();
    assert_eq!(session["frames"], FRAMES);
    assert!(
        session["camera"]["orbit"].is_null(),
        "the orbit became keys"
    );
    assert_eq!(
        session["camera"]["keys"].as_array().unwrap().len(),
        FRAMES as usize
    );
    let torus = &session["geometry"]["objects"][0];
    assert_eq!(torus["mesh"]["torus"]["segments"], 48, "the mesh stays");
    let keys = torus["transform"]["keys"].as_array().unwrap();
    assert_eq!(keys.len(), FRAMES as usize);
    assert_eq!(keys[5]["matrix"].as_array().unwrap().len(), 16);
    assert_eq!(session["uniforms"]["shininess"], 60.0);
    let schema: serde_json::Value = serde_json::from_slice(
        &std::fs::read(workspace().join("docs/session.schema.json")).unwrap(),
    )
    .unwrap();
    let errors: Vec<String> = jsonschema::validator_for(&schema)
        .unwrap()
        .iter_errors(&session)
        .map(|e| format!("{}: {e}", e.instance_path()))
        .collect();
    assert!(
        errors.is_empty(),
        "the recorded session against the schema: {errors:?}"
    );
    let replayed = tmp.path().join("replayed");
    reproj_render_session(&captured, Some(&dir), &replayed);
    assert_close(
        "recorded session: reproj render vs the host that recorded it",
        &replayed,
        &hosted,
    );
    // And the session the host played, for the other direction: the recorded motion is the
    // played one.
    let played = tmp.path().join("played");
    reproj_render(Some(&dir), &played);
    assert_close("recorded vs played session", &replayed, &played);
}

/// Nothing but `frame` is a name the host knows: a manifest whose texture names, roles and
/// sampler names are all different (and with a texture no pass uses) renders the same frames.
#[test]
fn host_follows_the_manifest_not_names() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path().join("2pass");
    instance(&dir, &["--strategy", "2pass", "--group", "3"]);
    let plain = tmp.path().join("plain");
    host(Some(&dir), &plain, &[]);

    let renamed = tmp.path().join("renamed");
    std::fs::create_dir_all(&renamed).unwrap();
    for e in std::fs::read_dir(&dir).unwrap() {
        let e = e.unwrap();
        std::fs::copy(e.path(), renamed.join(e.file_name())).unwrap();
    }
    let text = std::fs::read_to_string(dir.join("manifest.json")).unwrap();
    let mut m: serde_json::Value = serde_json::from_str(&text).unwrap();
    let names = [
        ("cur_payload", "history_write"),
        ("prev_payload", "history_read"),
        ("cur_depth", "z_write"),
        ("prev_depth", "z_read"),
        ("payload_0", "tex_a"),
        ("payload_1", "tex_b"),
        ("depth_0", "tex_c"),
        ("depth_1", "tex_d"),
        ("cur_depth_copy", "zc_write"),
        ("prev_depth_copy", "zc_read"),
        ("depth_copy_0", "tex_e"),
        ("depth_copy_1", "tex_f"),
        ("depth", "tex_g"),
        ("point", "sampler_x"),
        ("linear", "sampler_y"),
    ];
    let new_name = |old: &str| -> String {
        let (_, to) = names
            .iter()
            .find(|(from, _)| *from == old)
            .unwrap_or_else(|| panic!("unexpected name `{old}` in the manifest"));
        (*to).to_owned()
    };
    let rename = |v: &mut serde_json::Value| {
        let old = v.as_str().unwrap().to_owned();
        *v = new_name(&old).into();
    };
    // Every place a texture, role or sampler name appears (schema: textures, samplers,
    // frames.ping_pong, bindings' resources, color and depth attachments).
    for t in m["textures"].as_array_mut().unwrap() {
        rename(&mut t["name"]);
    }
    for t in m["samplers"].as_array_mut().unwrap() {
        rename(&mut t["name"]);
    }
    for plan in m["frames"]["ping_pong"].as_array_mut().unwrap() {
        let old = std::mem::take(plan.as_object_mut().unwrap());
        for (role, texture) in old {
            plan[new_name(&role)] = new_name(texture.as_str().unwrap()).into();
        }
    }
    for p in m["passes"].as_array_mut().unwrap() {
        for b in p["bindings"].as_array_mut().unwrap() {
            let r = &mut b["resource"];
            for key in ["role", "name"] {
                if r.get(key).is_some() {
                    rename(&mut r[key]);
                }
            }
        }
        for c in p["colors"].as_array_mut().unwrap() {
            if c["attachment"] != "frame" {
                rename(&mut c["attachment"]);
            }
        }
        rename(&mut p["depth"]["attachment"]);
    }
    m["textures"]
        .as_array_mut()
        .unwrap()
        .push(serde_json::json!({
            "name": "unused_extra", "format": "r32float", "size": "frame",
            "usage": ["render_attachment", "texture_binding"], "mip_levels": 1, "sample_count": 1
        }));
    let out = serde_json::to_string_pretty(&m).unwrap();
    for (from, _) in &names[..4] {
        assert!(!out.contains(&format!("\"{from}\"")), "{from} left");
    }
    std::fs::write(renamed.join("manifest.json"), out).unwrap();
    let renamed_out = tmp.path().join("renamed-out");
    host(Some(&renamed), &renamed_out, &[]);
    assert_close(
        "renamed roles vs the written manifest",
        &renamed_out,
        &plain,
    );
}

/// A manifest of another version, or one needing an unknown device feature, is refused with a
/// message saying so.
#[test]
fn host_refuses_what_it_cannot_run() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path().join("v");
    instance(&dir, &[]);
    let path = dir.join("manifest.json");
    let good = std::fs::read_to_string(&path).unwrap();
    let attempt = |manifest: &str| -> String {
        std::fs::write(&path, manifest).unwrap();
        let out = Command::new(host_bin())
            .current_dir(workspace())
            .args(["--shader", "shaders/marble.wgsl"])
            .args(["--session", "sessions/marble.json", "--frames", "1"])
            .arg("--variant")
            .arg(&dir)
            .arg("--out")
            .arg(tmp.path().join("out"))
            .output()
            .unwrap();
        assert!(!out.status.success());
        String::from_utf8_lossy(&out.stderr).into_owned()
    };
    let err = attempt(&good.replace("\"version\": 7", "\"version\": 2"));
    assert!(
        err.contains("manifest version 2 is not supported")
            && err.contains("reads versions 3 to 7"),
        "{err}"
    );
    let err = attempt(&good.replace("\"reproj.manifest\"", "\"something.else\""));
    assert!(err.contains("not a reproj variant manifest"), "{err}");
    let err = attempt(&good.replace("\"float32-filterable\"", "\"teleportation\""));
    assert!(
        err.contains("unknown device feature `teleportation`"),
        "{err}"
    );
}

/// Engine-like sessions: a shadow map rendered by a depth pass and read through a comparison
/// sampler (`shadow_pcf`), a storage buffer of per-frame lights (`deferred_lighting`), and a
/// glTF scene (`toon` over `gltf_boxes`). The host renders each original as `reproj render`
/// does, and a variant of each at Δn = 1 reproduces it.
#[test]
fn host_runs_depth_passes_storage_buffers_and_gltf_scenes() {
    let tmp = tempfile::tempdir().unwrap();
    let frames = FRAMES.to_string();
    let cases = [
        (
            "tests/corpus/shaders/shadow_pcf.wgsl",
            "tests/corpus/sessions/shadow_pcf.json",
        ),
        (
            "tests/corpus/shaders/deferred_lighting.wgsl",
            "tests/corpus/sessions/deferred_lighting.json",
        ),
        ("tests/corpus/shaders/toon.wgsl", "sessions/gltf_boxes.json"),
    ];
    for (shader, session) in cases {
        let name = Path::new(shader).file_stem().unwrap().to_str().unwrap();
        let reference = tmp.path().join(format!("{name}-render"));
        run(
            &reproj_bin(),
            &[
                "render",
                shader,
                "--session",
                session,
                "--frames",
                s(&reference),
                "--raw-frames",
                "--max-frames",
                &frames,
            ],
        );
        let host_run = |out: &Path, variant: Option<&Path>| {
            let mut args = vec![
                "--shader",
                shader,
                "--session",
                session,
                "--frames",
                &frames,
                "--out",
                s(out),
                "--raw",
            ];
            match variant {
                Some(v) => args.extend(["--variant", s(v), "--delta-n", "1"]),
                None => args.push("--original"),
            }
            run(&host_bin(), &args);
        };
        let hosted = tmp.path().join(format!("{name}-host"));
        host_run(&hosted, None);
        assert_close(
            &format!("{name} original: host vs reproj render"),
            &hosted,
            &reference,
        );
        let dir = tmp.path().join(format!("{name}-variant"));
        run(
            &reproj_bin(),
            &[
                "instance",
                shader,
                "--node",
                "root",
                "--strategy",
                "2pass",
                "--out",
                s(&dir),
            ],
        );
        let hosted_variant = tmp.path().join(format!("{name}-host-variant"));
        host_run(&hosted_variant, Some(&dir));
        assert_close(
            &format!("{name} 2pass Δn 1 (host) vs the original (reproj render)"),
            &hosted_variant,
            &reference,
        );
    }
}

/// Run-time adaptation: with a Δn schedule in the manifest, the host measures each frame's motion
/// from its own camera and transforms and sets Δn from the schedule; `reproj render --adaptive`
/// does the same from the session, and the frames agree. The schedule here splits the marble
/// session's frames at their median motion, so both periods are used.
#[test]
fn host_adapts_delta_n_by_motion_as_reproj_render_does() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path().join("adaptive");
    instance(&dir, &["--strategy", "3pass"]);
    let manifest_path = dir.join("manifest.json");
    let set_schedule = |bands: serde_json::Value| {
        let mut m: serde_json::Value =
            serde_json::from_slice(&std::fs::read(&manifest_path).unwrap()).unwrap();
        m["params"]["schedule"] = bands;
        std::fs::write(&manifest_path, serde_json::to_vec_pretty(&m).unwrap()).unwrap();
    };
    // One band first, to read each frame's motion from the host's summary.
    set_schedule(serde_json::json!([{"up_to_pixels_per_frame": null, "delta_n": 8}]));
    let probe = tmp.path().join("probe");
    host(Some(&dir), &probe, &["--adaptive"]);
    let summary: serde_json::Value =
        serde_json::from_slice(&std::fs::read(probe.join("summary.json")).unwrap()).unwrap();
    let mut motions: Vec<f64> = summary["frames"].as_array().unwrap()[1..]
        .iter()
        .map(|f| f["motion_px"].as_f64().unwrap())
        .collect();
    assert!(motions.iter().all(|m| *m > 0.0), "{motions:?}");
    motions.sort_by(f64::total_cmp);
    let median = motions[motions.len() / 2];
    set_schedule(serde_json::json!([
        {"up_to_pixels_per_frame": median, "delta_n": 8},
        {"up_to_pixels_per_frame": null, "delta_n": 3}
    ]));
    let hosted = tmp.path().join("host");
    host(Some(&dir), &hosted, &["--adaptive"]);
    let summary: serde_json::Value =
        serde_json::from_slice(&std::fs::read(hosted.join("summary.json")).unwrap()).unwrap();
    let used: std::collections::BTreeSet<u64> = summary["frames"].as_array().unwrap()[1..]
        .iter()
        .map(|f| f["delta_n"].as_u64().unwrap())
        .collect();
    assert_eq!(used, [3, 8].into(), "{summary}");
    let reference = tmp.path().join("render");
    let max = FRAMES.to_string();
    run(
        &reproj_bin(),
        &[
            "render",
            "shaders/marble.wgsl",
            "--session",
            "sessions/marble.json",
            "--frames",
            s(&reference),
            "--raw-frames",
            "--max-frames",
            &max,
            "--variant",
            s(&dir),
            "--adaptive",
        ],
    );
    assert_close("adaptive Δn: host vs reproj render", &hosted, &reference);
}
