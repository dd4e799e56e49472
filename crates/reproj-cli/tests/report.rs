//! `reproj report` through the real binary, and the page in a real headless browser (Debian
//! `chromium`, installed by `scripts/ensure-tools.sh`): the slider set from `#budget=X` selects
//! what `reproj emit --max-error X` selects, and every image loads. Also `render --frames` writes
//! the reference frames beside a variant's.

use std::path::{Path, PathBuf};
use std::process::Command;

use crate::common::{root, run as reproj};

/// A small profile of marble, made quickly (as the CI tests make theirs): the recorded session at
/// 160×120, 8 frames, three nodes, three training periods. (The tiny test shader is too cheap for
/// any variant to beat it, so its report would only ever keep the original.)
fn marble_profile(dir: &Path) -> PathBuf {
    std::fs::copy(root().join("shaders/marble.wgsl"), dir.join("marble.wgsl")).unwrap();
    let mut session: serde_json::Value = serde_json::from_str(
        &std::fs::read_to_string(root().join("sessions/marble.json")).unwrap(),
    )
    .unwrap();
    session["resolution"] = serde_json::json!([160, 120]);
    std::fs::write(dir.join("marble.json"), session.to_string()).unwrap();
    let (code, _, err) = reproj(
        dir,
        &[
            "analyze",
            "marble.wgsl",
            "--session",
            "marble.json",
            "--out",
            "marble.profile.json",
            "--max-frames",
            "8",
            "--delta-n",
            "2,4,8",
            "--holdout",
            "6",
            "--max-nodes",
            "3",
            "--no-charts",
        ],
    );
    assert_eq!(code, 0, "{err}");
    dir.join("marble.profile.json")
}

/// The page's embedded data.
fn page_data(html: &str) -> serde_json::Value {
    let start = html
        .find(r#"<script type="application/json" id="data">"#)
        .unwrap();
    let rest = &html[start..];
    let body = &rest[rest.find('>').unwrap() + 1..rest.find("</script>").unwrap()];
    serde_json::from_str(&body.replace("<\\/", "</")).unwrap()
}

/// The text of the element with this id in a dumped DOM.
fn text_of(dom: &str, id: &str) -> String {
    let tag = format!(r#"id="{id}""#);
    let at = dom.find(&tag).unwrap_or_else(|| panic!("no #{id}"));
    let rest = &dom[at..];
    let open = rest.find('>').unwrap() + 1;
    rest[open..open + rest[open..].find('<').unwrap()].to_string()
}

/// The selection `emit` makes at `budget`: `(node, Δn)`, `None` for the original.
fn emit_at(dir: &Path, budget: f64) -> Option<(String, u64)> {
    let b = format!("{budget}");
    let (code, out, err) = reproj(
        dir,
        &[
            "emit",
            "--max-error",
            &b,
            "--profile",
            "marble.profile.json",
            "--out",
            "emitted",
            "--json",
        ],
    );
    assert_eq!(code, 0, "{err}");
    let r: serde_json::Value = serde_json::from_str(&out).unwrap();
    r["node"]
        .as_str()
        .map(|n| (n.to_string(), r["delta_n"].as_u64().unwrap()))
}

/// The headless browser, if installed (by `scripts/ensure-tools.sh`, which `scripts/test.sh` runs
/// first; never from inside the test).
fn chromium() -> Option<PathBuf> {
    ["chromium", "chromium-browser", "google-chrome"]
        .iter()
        .find_map(|name| {
            std::env::var_os("PATH").and_then(|paths| {
                std::env::split_paths(&paths)
                    .map(|d| d.join(name))
                    .find(|p| p.is_file())
            })
        })
}

/// `chromium --headless --dump-dom` of the page at `#budget=X`.
fn dump_dom(browser: &Path, page: &Path, budget: f64) -> String {
    let url = format!("file://{}#budget={budget}", page.display());
    let out = Command::new(browser)
        .args([
            "--headless",
            "--no-sandbox",
            "--disable-gpu",
            "--virtual-time-budget=10000",
            "--dump-dom",
            &url,
        ])
        .output()
        .expect("run chromium");
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    String::from_utf8_lossy(&out.stdout).into_owned()
}

#[test]
fn the_report_page_follows_the_selector_in_a_browser() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    marble_profile(dir);
    let (code, out, err) = reproj(
        dir,
        // The page's speeds are not what is checked: timed for 5 s at most, not to ±3 %.
        &[
            "report",
            "marble.profile.json",
            "--out",
            "page.html",
            "--max-time",
            "5",
        ],
    );
    assert_eq!(code, 0, "{err}");
    assert!(out.contains("wrote page.html"), "{out}");
    assert!(
        err.contains("rendering the original"),
        "progress on stderr: {err}"
    );
    let page = dir.join("page.html");
    let html = std::fs::read_to_string(&page).unwrap();
    // Self-contained: nothing is fetched.
    for remote in ["http://", "https://", "src=\"/", "<link"] {
        let allowed = "http://www.w3.org/2000/svg";
        assert!(
            !html.replace(allowed, "").contains(remote),
            "the page refers to {remote}"
        );
    }
    let data = page_data(&html);
    assert_eq!(data["schema"], "reproj.report-page");

    // Budgets in the middle (log scale) of the widest runs of one choice: two runs that differ.
    let entries = data["entries"].as_array().unwrap();
    let hi = data["range"][1].as_f64().unwrap();
    let key = |e: &serde_json::Value| e["choice"].as_u64();
    let mut runs: Vec<(f64, f64, Option<u64>)> = Vec::new();
    for e in entries {
        let b = e["budget"].as_f64().unwrap();
        match runs.last_mut() {
            Some(r) if r.2 == key(e) => {}
            Some(r) => {
                r.1 = b;
                runs.push((b, hi, key(e)));
            }
            None => runs.push((b, hi, key(e))),
        }
    }
    runs.sort_by(|a, b| (b.1 / b.0).total_cmp(&(a.1 / a.0)));
    let first = runs[0];
    let second = *runs
        .iter()
        .find(|r| r.2 != first.2)
        .expect("the selection changes over the slider's range");
    let budgets: Vec<f64> = [first, second].iter().map(|r| (r.0 * r.1).sqrt()).collect();

    // Images: the reference, the variant, the error map and the hit map of each rendered selection
    // (at most 8 by default), and three charts.
    let choices = data["choices"].as_array().unwrap();
    let rendered = choices.iter().filter(|c| !c["measured"].is_null()).count();
    assert_eq!(rendered, choices.len().min(8));
    assert!(html.matches("<img").count() >= 4 * rendered + 3);

    let Some(browser) = chromium() else {
        // Under CI a skipped check must not pass.
        assert!(
            std::env::var_os("CI").is_none(),
            "CI is set and chromium is missing: scripts/ensure-tools.sh installs it"
        );
        eprintln!("skipped the browser part: chromium is not installed (scripts/ensure-tools.sh)");
        return;
    };
    let mut seen = Vec::new();
    for b in budgets {
        let dom = dump_dom(&browser, &page, b);
        assert!(
            dom.contains(r#"data-images-ok="true""#),
            "not every image loaded at budget {b}"
        );
        let node = text_of(&dom, "sel-node");
        let dn = text_of(&dom, "sel-dn");
        match emit_at(dir, b) {
            Some((n, d)) => {
                // emit names a set by its members (`680+697`), the page `set 680+697`.
                let want = if n == "root" {
                    " (root)".to_string()
                } else if n.contains('+') {
                    format!("set {n}")
                } else {
                    format!("node {n}")
                };
                assert!(
                    node.contains(&want),
                    "budget {b}: page {node:?}, emit node {n}"
                );
                assert_eq!(dn, format!("Δn = {d}"), "budget {b}");
            }
            None => assert_eq!(node, "original shader", "budget {b}"),
        }
        eprintln!("budget {b}: {node} {dn}");
        seen.push((node, dn));
    }
    assert_ne!(
        seen[0], seen[1],
        "the selection text changes with the budget"
    );
}

#[test]
fn bad_report_inputs_exit_2_and_write_nothing() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    std::fs::write(dir.join("bad.profile.json"), "{\"schema\": 1}").unwrap();
    for args in [
        vec!["report", "missing.profile.json"],
        vec!["report", "bad.profile.json"],
        vec!["report", "bad.profile.json", "--out", "no/such/dir/r.html"],
    ] {
        let (code, out, err) = reproj(dir, &args);
        assert_eq!(code, 2, "{args:?}: {err}");
        assert_eq!(err.trim().lines().count(), 1, "one message: {err}");
        assert!(out.is_empty(), "{out}");
    }
    let mut names: Vec<String> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    names.sort();
    assert_eq!(names, ["bad.profile.json"]);
}

#[test]
fn render_frames_writes_the_reference_beside_the_variant() {
    let tmp = tempfile::tempdir().unwrap();
    let data = root().join("crates/reproj-replay/tests/data");
    let (code, _, err) = reproj(
        tmp.path(),
        &[
            "render",
            data.join("tiny.wgsl").to_str().unwrap(),
            "--session",
            data.join("tiny_moving.json").to_str().unwrap(),
            "--node",
            "root",
            "--delta-n",
            "4",
            "--frames",
            "frames",
        ],
    );
    assert_eq!(code, 0, "{err}");
    let frames = tmp.path().join("frames");
    for name in [
        "ref_001.png",
        "frame_001.png",
        "errmap_001.png",
        "hitmap_001.png",
    ] {
        assert!(frames.join(name).is_file(), "{name}");
    }
    let size = |n: &str| image::image_dimensions(frames.join(n)).unwrap();
    assert_eq!(size("ref_001.png"), size("frame_001.png"));
    // The error map carries its colour bar under the frame.
    assert!(size("errmap_001.png").1 > size("frame_001.png").1);
}
