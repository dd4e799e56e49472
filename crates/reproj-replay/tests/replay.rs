//! End-to-end replay tests. They need a Vulkan adapter: on machines without a GPU, Mesa's
//! lavapipe (`apt-get install mesa-vulkan-drivers`). They are small (64×64, a few frames).

use std::path::{Path, PathBuf};

use reproj_replay::{
    Reference, RenderOptions, Renderer, RendererOptions, ReplayError, VariantInput,
};
use reproj_scene::{Session, SessionError};

fn data(p: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data")
        .join(p)
}

fn renderer() -> Renderer {
    match Renderer::new(&RendererOptions::default()) {
        Ok(r) => {
            eprintln!("adapter: {} ({})", r.adapter().name, r.adapter().backend);
            r
        }
        Err(e) => panic!("{e}"),
    }
}

fn tiny_shader() -> reproj_front::Shader {
    reproj_front::load_file(&data("tiny.wgsl")).unwrap()
}

/// A renderer, the tiny shader, one of its sessions and the original's reference frames.
fn tiny_reference(session: &str) -> (Renderer, reproj_front::Shader, Session, Reference) {
    let r = renderer();
    let shader = tiny_shader();
    let entry = shader.fragment_entry(None).unwrap();
    let session = Session::load(data(session)).unwrap();
    let reference = r
        .render_original(&shader, entry, &session, &RenderOptions::default())
        .unwrap();
    (r, shader, session, reference)
}

#[test]
fn original_render_is_deterministic() {
    let r = renderer();
    let shader = tiny_shader();
    let entry = shader.fragment_entry(None).unwrap();
    let session = Session::load(data("tiny_moving.json")).unwrap();
    let a = r
        .render_original(&shader, entry, &session, &RenderOptions::default())
        .unwrap();
    let b = r
        .render_original(&shader, entry, &session, &RenderOptions::default())
        .unwrap();
    assert_eq!(a.frames.len(), 4);
    assert_eq!(a.frames, b.frames);
    // The second replay found the sphere and the checker texture already on the GPU.
    assert!(r.reused_assets() >= 2, "{} reused", r.reused_assets());
    // ... and its pipeline compiled.
    assert!(r.reused_pipelines() >= 1, "{} reused", r.reused_pipelines());
    // Coverage comes from the depth: the sphere, not the background.
    let covered = a.depth[0].iter().filter(|&&d| d < 1.0).count();
    assert_eq!(a.report.frames[0].covered, covered as u64);
    assert!(covered >= lit_pixels(&a.frames[0]) && covered < 64 * 64);
    // Something was drawn: the sphere covers part of the frame, the background is black.
    let lit = lit_pixels(&a.frames[0]);
    assert!(lit > 200 && lit < 64 * 64, "lit pixels: {lit}");
    let shaded = a.report.frames[0].shaded;
    assert!(
        shaded as usize >= lit,
        "occlusion count {shaded} < lit pixels {lit}"
    );
    assert!(a.report.frame_ms > 0.0);
    assert!(!a.report.adapter.name.is_empty());
}

fn lit_pixels(frame: &[f32]) -> usize {
    frame
        .chunks_exact(4)
        .filter(|p| p[0] + p[1] + p[2] > 0.01)
        .count()
}

/// The error of a variant reduced on the GPU equals the error computed on the CPU from the pixels
/// read back (as when PNGs are written) within 1e-5 relative; counts and maxima exactly.
#[test]
fn gpu_error_reduction_matches_the_cpu() {
    let (r, shader, session, reference) = tiny_reference("tiny_moving.json");
    let variant = VariantInput::from_dir(&data("variant_tiny"), 2).unwrap();
    let gpu = r
        .render_variant(
            &shader,
            &session,
            &variant,
            &reference,
            &RenderOptions::default(),
        )
        .unwrap();
    let dir = tempfile::tempdir().unwrap();
    let cpu_opts = RenderOptions {
        png_dir: Some(dir.path().to_owned()),
        ..Default::default()
    };
    let cpu = r
        .render_variant(&shader, &session, &variant, &reference, &cpu_opts)
        .unwrap();
    let close = |a: f64, b: f64| a == b || (a - b).abs() <= 1e-5 * a.abs().max(b.abs());
    assert!(cpu.error > 0.0, "the scene moves: the variant is not exact");
    for (g, c) in gpu.frames.iter().zip(&cpu.frames) {
        let f = g.frame;
        assert_eq!(g.covered, c.covered, "frame {f}");
        assert_eq!(g.max_abs_diff, c.max_abs_diff, "frame {f}");
        assert!(
            close(g.error, c.error),
            "frame {f}: {} vs {}",
            g.error,
            c.error
        );
        assert!(close(g.mse, c.mse), "frame {f}: {} vs {}", g.mse, c.mse);
        assert!((g.psnr - c.psnr).abs() < 1e-4, "frame {f}");
    }
    assert!(close(gpu.error, cpu.error) && close(gpu.mse, cpu.mse));
    assert!(
        gpu.frames[1..]
            .iter()
            .any(|f| f.mse > 0.0 && f.psnr < 100.0)
    );
    // The covered pixels are the reference's: identical to the original's counts.
    for (v, o) in gpu.frames.iter().zip(&reference.report.frames) {
        assert_eq!(v.covered, o.covered);
    }
}

#[test]
fn missing_texture_is_named() {
    let r = renderer();
    let shader = tiny_shader();
    let entry = shader.fragment_entry(None).unwrap();
    let mut session = Session::load(data("tiny_moving.json")).unwrap();
    session.textures.clear();
    session.uniforms.remove("gain");
    let err = r
        .render_original(&shader, entry, &session, &RenderOptions::default())
        .unwrap_err();
    let msg = err.to_string();
    assert!(matches!(err, ReplayError::MissingResources { .. }), "{msg}");
    assert!(msg.contains("albedo_map"), "{msg}");
    assert!(msg.contains("gain"), "{msg}");
}

#[test]
fn bad_session_field_names_its_path() {
    let text = std::fs::read_to_string(data("tiny_static_plane.json")).unwrap();
    let good: serde_json::Value = serde_json::from_str(&text).unwrap();
    let parse = |v: &serde_json::Value| {
        Session::from_json(&v.to_string(), Path::new("bad.json"), Path::new("."))
    };
    assert!(parse(&good).is_ok());

    let mut bad = good.clone();
    bad["camera"]["keys"][0]["eye"] = serde_json::json!([0, 2]);
    let err = parse(&bad).unwrap_err();
    let msg = err.to_string();
    assert!(
        matches!(err, SessionError::Read(reproj_io::ReadError::Field { .. })),
        "{msg}"
    );
    assert!(msg.contains("camera.keys[0].eye"), "{msg}");

    let mut bad = good.clone();
    bad["textures"]["albedo_map"]["params"]["squares"] = serde_json::json!("four");
    let msg = parse(&bad).unwrap_err().to_string();
    assert!(msg.contains("textures.albedo_map.params.squares"), "{msg}");

    let mut bad = good.clone();
    bad["resolutoin"] = bad["resolution"].clone();
    let msg = parse(&bad).unwrap_err().to_string();
    assert!(msg.contains("resolutoin"), "{msg}");

    let mut bad = good.clone();
    bad["geometry"]["objects"][0]["mesh"]["plane"]["size"] = serde_json::json!(-4.0);
    let msg = parse(&bad).unwrap_err().to_string();
    assert!(msg.contains("geometry.objects[0].mesh"), "{msg}");
}

#[test]
fn variant_at_delta_n_1_reproduces_original() {
    let (r, shader, session, reference) = tiny_reference("tiny_moving.json");
    let variant = VariantInput::from_dir(&data("variant_tiny"), 1).unwrap();
    let report = r
        .render_variant(
            &shader,
            &session,
            &variant,
            &reference,
            &RenderOptions::default(),
        )
        .unwrap();
    assert_eq!(report.frames.len(), 4);
    for f in &report.frames {
        assert!(
            f.max_abs_diff <= 1e-4,
            "frame {}: max abs diff {}",
            f.frame,
            f.max_abs_diff
        );
        assert_eq!(f.hits, 0, "frame {}: hits at Δn = 1", f.frame);
        assert_eq!(f.hit_px, Some(0));
        assert!(
            f.recomputes >= f.shaded,
            "frame {}: {} recomputes < {} shaded",
            f.frame,
            f.recomputes,
            f.shaded
        );
    }
    assert!(report.hit_rate == 0.0);
}

#[test]
fn static_variant_at_delta_n_8_hits_seven_in_eight() {
    let (r, shader, session, reference) = tiny_reference("tiny_static_plane.json");
    let variant = VariantInput::from_dir(&data("variant_tiny"), 8).unwrap();
    let dir = tempfile::tempdir().unwrap();
    let opts = RenderOptions {
        png_dir: Some(dir.path().to_owned()),
        ..Default::default()
    };
    let report = r
        .render_variant(&shader, &session, &variant, &reference, &opts)
        .unwrap();
    assert_eq!(report.frames.len(), 9);
    // The plane fills the view: every pixel is shaded.
    assert_eq!(report.frames[0].shaded, 64 * 64);
    assert_eq!(report.frames[0].hits, 0);
    for f in &report.frames[1..] {
        assert!(f.error < 1e-4, "frame {}: error {}", f.frame, f.error);
        assert!(
            (f.hit_rate - 0.875).abs() < 0.05,
            "frame {}: hit rate {}",
            f.frame,
            f.hit_rate
        );
        assert_eq!(
            f.hit_px.unwrap() + f.refresh_px.unwrap() + f.miss_px.unwrap(),
            64 * 64
        );
        assert_eq!(
            f.miss_px,
            Some(0),
            "frame {}: misses in a static scene",
            f.frame
        );
        assert_eq!(
            f.hits + f.recomputes,
            64 * 64,
            "frame {}: hits + recomputes",
            f.frame
        );
        assert_eq!(f.hits, f.hit_px.unwrap());
    }
    assert!(
        (report.hit_rate - 0.875).abs() < 0.03,
        "mean hit rate {}",
        report.hit_rate
    );
    for name in ["frame_000.png", "hitmap_008.png", "errmap_008.png"] {
        assert!(dir.path().join(name).is_file(), "{name} not written");
    }
    let json = serde_json::to_string(&report).unwrap();
    assert!(json.contains("\"hit_rate\""));
}

/// A variant is built once and kept (`reproj-runtime`'s resources: its pipelines, textures and
/// bind groups): replayed again, at another Δn and at the first, it gives what a fresh renderer
/// gives, frame for frame (the cache starts over at each replay's first frame), and the
/// renderer says it reused it.
#[test]
fn a_variant_kept_built_across_replays_renders_as_a_fresh_one() {
    let (r, shader, session, reference) = tiny_reference("tiny_moving.json");
    let at = |dn: u32| VariantInput::from_dir(&data("variant_tiny"), dn).unwrap();
    let opts = RenderOptions::default();
    let before = r.reused_pipelines();
    let first = r
        .render_variant(&shader, &session, &at(2), &reference, &opts)
        .unwrap();
    r.render_variant(&shader, &session, &at(4), &reference, &opts)
        .unwrap();
    let again = r
        .render_variant(&shader, &session, &at(2), &reference, &opts)
        .unwrap();
    assert!(
        r.reused_pipelines() >= before + 2,
        "built once, reused twice"
    );
    let (fresh_r, ..) = tiny_reference("tiny_moving.json");
    let fresh = fresh_r
        .render_variant(&shader, &session, &at(2), &reference, &opts)
        .unwrap();
    for run in [&again, &fresh] {
        for (a, b) in first.frames.iter().zip(&run.frames) {
            assert_eq!(
                (a.hits, a.recomputes, a.hit_px, a.error.to_bits()),
                (b.hits, b.recomputes, b.hit_px, b.error.to_bits()),
                "frame {}",
                a.frame
            );
        }
    }
}

/// A variant written before the depth copy (its lookup reads the previous depth buffer as a
/// `texture_depth_2d`, no depth copy target; its manifest rewritten as version 3) is refused by
/// name, with what to do: the replay draws variants as `reproj-runtime` does, and a host's one
/// depth target cannot be the previous frame's. The same variant written today renders.
#[test]
fn a_variant_reading_the_depth_buffer_is_refused_by_name() {
    let (r, shader, session, reference) = tiny_reference("tiny_moving.json");
    let old = VariantInput::from_dir(&data("variant_tiny_depth_texture"), 2).unwrap();
    assert!(old.sources[0].contains("texture_depth_2d"));
    let new = VariantInput::from_dir(&data("variant_tiny"), 2).unwrap();
    assert!(!new.sources[0].contains("texture_depth_2d"));
    let opts = RenderOptions::default();
    let e = r
        .render_variant(&shader, &session, &old, &reference, &opts)
        .unwrap_err()
        .to_string();
    assert!(e.contains("written before the depth copy"), "{e}");
    assert!(e.contains("write it again with `reproj instance`"), "{e}");
    let b = r
        .render_variant(&shader, &session, &new, &reference, &opts)
        .unwrap();
    assert!(
        b.frames[1..].iter().any(|f| f.hits > 0),
        "no hits at Δn = 2"
    );
}

/// Every session in `sessions/` loads, and each one named after a sample shader in `shaders/`
/// provides everything that shader declares (rendered at 64×64 for two frames). `test_static.json`
/// serves every sample shader.
#[test]
fn sample_sessions_fit_their_shaders() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
    let sessions_dir = root.join("sessions");
    let shaders_dir = root.join("shaders");
    let Ok(entries) = std::fs::read_dir(&sessions_dir) else {
        return;
    };
    let mut sessions: Vec<PathBuf> = entries
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|e| e == "json"))
        .collect();
    sessions.sort();
    let shaders: Vec<PathBuf> = std::fs::read_dir(&shaders_dir)
        .map(|d| {
            d.filter_map(|e| e.ok().map(|e| e.path()))
                .filter(|p| p.extension().is_some_and(|e| e == "wgsl"))
                .collect()
        })
        .unwrap_or_default();
    let r = renderer();
    let opts = RenderOptions {
        max_frames: Some(2),
        ..Default::default()
    };
    let mut failures = Vec::new();
    for sp in &sessions {
        let mut session = match Session::load(sp) {
            Ok(s) => s,
            Err(e) => {
                failures.push(e.to_string());
                continue;
            }
        };
        session.resolution = [64, 64];
        let stem = sp.file_stem().unwrap().to_string_lossy().into_owned();
        let targets: Vec<&PathBuf> = if stem == "test_static" {
            shaders.iter().collect()
        } else {
            shaders
                .iter()
                .filter(|s| s.file_stem().is_some_and(|n| n.to_string_lossy() == stem))
                .collect()
        };
        for sh in targets {
            let Ok(shader) = reproj_front::load_file(sh) else {
                continue;
            };
            let Ok(entry) = shader.fragment_entry(None) else {
                continue;
            };
            if let Err(e) = r.render_original(&shader, entry, &session, &opts) {
                failures.push(format!("{} with {}: {e}", sh.display(), sp.display()));
            }
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}
