//! The corpus (`tests/corpus/shaders/` at the top of the repository, sessions in
//! `tests/corpus/sessions/`; the GLSL shaders of `tests/corpus/shaders/glsl/` that have a session
//! in `tests/corpus/sessions/glsl/`): engine-style fragment shaders, each run through the real
//! binary and compared with the committed snapshot
//! `tests/corpus/snapshots/integration__corpus__table.snap`, so that a shader that stops parsing,
//! loses cacheable nodes, stops validating or rendering (or starts to) fails here. Per shader it
//! records: whether `nodes` parses it, the cacheable node count, the outcome of `instance` for the
//! root and the costliest other cacheable node in each strategy, the outcome of `render --node root
//! --delta-n 4 --max-frames 4`, and that of a short `analyze` (12 frames, two nodes, 2pass). An
//! outcome is `ok` or the one-line message of an exit-2 rejection; anything else (a panic, another
//! exit code, a message over several lines, files left behind by a rejection) fails outright.
//! Everything is written in temporary directories.
//!
//! After an intended change: `INSTA_UPDATE=always cargo test -p reproj-cli --test integration
//! corpus::` and `git diff tests/corpus` (`cargo insta review` does not look outside the crates),
//! then update `docs/CORPUS.md` (`tests/README.md`).

use std::collections::BTreeMap;
use std::path::Path;

use serde_json::{Value, json};

use crate::common::{root, run};

const STRATEGIES: [&str; 3] = ["3pass", "2pass", "fused"];

/// `ok` for exit 0; the message for a clean exit-2 rejection; panics on anything else.
fn outcome(what: &str, (code, _out, err): (i32, String, String)) -> String {
    match code {
        0 => "ok".into(),
        2 => {
            let msg = err.trim();
            assert!(
                !msg.is_empty() && !msg.contains("panicked") && msg.lines().count() == 1,
                "{what}: exit 2 without one clear line:\n{err}"
            );
            msg.to_owned()
        }
        _ => panic!("{what}: exit {code}\n{err}"),
    }
}

fn is_empty_dir(dir: &Path) -> bool {
    std::fs::read_dir(dir).unwrap().next().is_none()
}

/// The measured row of one shader.
fn measure(shader: &Path, session: &Path) -> Value {
    let name = shader.file_stem().unwrap().to_str().unwrap().to_owned();
    let sh = shader.to_str().unwrap();
    let tmp = tempfile::tempdir().unwrap();
    let (code, out, err) = run(tmp.path(), &["nodes", sh, "--json"]);
    if code != 0 {
        let msg = outcome(&format!("{name}: nodes"), (code, out, err));
        assert!(is_empty_dir(tmp.path()), "{name}: nodes wrote files");
        return json!({"parses": false, "error": msg});
    }
    let nodes: Value = serde_json::from_str(&out).expect("nodes --json");
    let nodes = nodes["nodes"].as_array().unwrap();
    let costliest = nodes
        .iter()
        .filter(|n| n["root"] == false)
        .max_by(|a, b| {
            let (ca, cb) = (a["cost"].as_f64().unwrap(), b["cost"].as_f64().unwrap());
            // Ties go to the earlier node, so the choice is stable.
            ca.total_cmp(&cb)
                .then(b["id"].as_u64().cmp(&a["id"].as_u64()))
        })
        .map(|n| n["id"].to_string());

    let mut variants = BTreeMap::new();
    let mut targets = vec![("root".to_owned(), "root".to_owned())];
    if let Some(id) = &costliest {
        targets.push((format!("costliest ({id})"), id.clone()));
    }
    for (label, node) in &targets {
        for strategy in STRATEGIES {
            let dir = tmp.path().join(format!("v-{node}-{strategy}"));
            let args = [
                "instance",
                sh,
                "--node",
                node,
                "--strategy",
                strategy,
                "--out",
                dir.to_str().unwrap(),
            ];
            let what = format!("{name}: instance {node} {strategy}");
            let o = outcome(&what, run(tmp.path(), &args));
            if o == "ok" {
                assert!(dir.join("manifest.json").is_file(), "{what}: no manifest");
                std::fs::remove_dir_all(&dir).unwrap();
            } else {
                assert!(!dir.exists(), "{what}: a rejection wrote {}", dir.display());
            }
            variants.insert(format!("{label} {strategy}"), o);
        }
    }

    let args = [
        "render",
        sh,
        "--session",
        session.to_str().unwrap(),
        "--node",
        "root",
        "--delta-n",
        "4",
        "--max-frames",
        "4",
    ];
    let render = outcome(&format!("{name}: render"), run(tmp.path(), &args));
    assert!(is_empty_dir(tmp.path()), "{name}: render wrote files");

    // A short analysis: the root and the node with the largest predicted saving, 2pass, three
    // training periods and one held out, over 12 frames. Only the outcome is recorded (which
    // nodes prove usable depends on timings).
    let profile = tmp.path().join("p.profile.json");
    let args = [
        "analyze",
        sh,
        "--session",
        session.to_str().unwrap(),
        "--max-frames",
        "12",
        "--max-nodes",
        "2",
        "--delta-n",
        "2,4,6",
        "--holdout",
        "3",
        "--probe-frames",
        "6",
        "--strategy",
        "2pass",
        "--no-charts",
        "--out",
        profile.to_str().unwrap(),
    ];
    let analyze = outcome(&format!("{name}: analyze"), run(tmp.path(), &args));
    if analyze == "ok" {
        let p: Value = serde_json::from_str(&std::fs::read_to_string(&profile).unwrap())
            .expect("the profile is JSON");
        assert!(
            !p["nodes"].as_array().unwrap().is_empty(),
            "{name}: analyze profiled no node"
        );
    } else {
        assert!(
            !profile.exists(),
            "{name}: a rejected analyze wrote its profile"
        );
    }
    json!({
        "parses": true,
        "cacheable": nodes.len(),
        "variants": variants,
        "render": render,
        "analyze": analyze,
    })
}

#[test]
fn corpus_matches_its_table() {
    let root = root();
    let dir = root.join("tests/corpus/shaders");
    let mut shaders: Vec<_> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "wgsl"))
        .collect();
    shaders.sort();
    assert!(
        shaders.len() >= 15,
        "the corpus has {} shaders",
        shaders.len()
    );
    let doc = std::fs::read_to_string(root.join("docs/CORPUS.md")).unwrap();

    let mut measured = serde_json::Map::new();
    for shader in &shaders {
        let name = shader.file_stem().unwrap().to_str().unwrap();
        let session = root.join(format!("tests/corpus/sessions/{name}.json"));
        assert!(
            session.is_file(),
            "{name}: no session {}",
            session.display()
        );
        assert!(
            doc.contains(&format!("`{name}.wgsl`")),
            "docs/CORPUS.md has no row for {name}.wgsl"
        );
        measured.insert(name.to_owned(), measure(shader, &session));
    }
    // The GLSL shaders that have a session (`tests/corpus/sessions/glsl/NAME.json`) go the same way.
    let mut glsl: Vec<_> = std::fs::read_dir(root.join("tests/corpus/sessions/glsl"))
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "json"))
        .collect();
    glsl.sort();
    assert!(glsl.len() >= 5, "{} GLSL corpus sessions", glsl.len());
    for session in &glsl {
        let name = session.file_stem().unwrap().to_str().unwrap();
        let shader = dir.join(format!("glsl/{name}.frag"));
        assert!(shader.is_file(), "{}: no shader", session.display());
        assert!(
            doc.contains(&format!("`{name}.frag`")),
            "docs/CORPUS.md has no row for {name}.frag"
        );
        measured.insert(format!("glsl/{name}"), measure(&shader, session));
    }
    let measured = Value::Object(measured);

    let table = serde_json::to_string_pretty(&measured).unwrap();
    insta::with_settings!({snapshot_path => root.join("tests/corpus/snapshots")}, {
        insta::assert_snapshot!("table", table);
    });
}
