//! The crate layering: the GPU stays in the renderers. Reads the workspace's `Cargo.lock` (the
//! whole resolved graph, every platform) and checks which workspace crates reach `wgpu`, directly
//! or through any dependency: only reproj-replay (the renderer), the crates built on it, the
//! example host, the runtime crate engines link (which names wgpu and no other reproj crate), and
//! the scene on the device (reproj-scene-gpu), which the replay and the host draw with.
//! The scene (reproj-scene) and the metrics (reproj-metrics) the replay draws and reports are
//! GPU-free, so a host, `emit` and the light build use them without wgpu.

use std::collections::{BTreeMap, BTreeSet};
use std::path::Path;

/// Package name → names of its dependencies (every version of a name merged: over-approximate).
/// Also the workspace's own packages (those without a `source`).
fn lock_graph() -> (BTreeMap<String, BTreeSet<String>>, BTreeSet<String>) {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../Cargo.lock");
    let text = std::fs::read_to_string(&path).unwrap();
    let mut graph: BTreeMap<String, BTreeSet<String>> = BTreeMap::new();
    let mut local = BTreeSet::new();
    for block in text.split("[[package]]").skip(1) {
        let mut name = None;
        let mut has_source = false;
        let mut deps = BTreeSet::new();
        let mut in_deps = false;
        for line in block.lines() {
            let line = line.trim();
            if let Some(v) = line.strip_prefix("name = ") {
                name = Some(v.trim_matches('"').to_owned());
            } else if line.starts_with("source = ") {
                has_source = true;
            } else if line == "dependencies = [" {
                in_deps = true;
            } else if in_deps && line == "]" {
                in_deps = false;
            } else if in_deps {
                let dep = line.trim_end_matches(',').trim_matches('"');
                deps.insert(dep.split(' ').next().unwrap().to_owned());
            }
        }
        let name = name.expect("every [[package]] has a name");
        if !has_source {
            local.insert(name.clone());
        }
        graph.entry(name).or_default().extend(deps);
    }
    (graph, local)
}

fn reaches(graph: &BTreeMap<String, BTreeSet<String>>, from: &str, target: &str) -> bool {
    let mut seen = BTreeSet::new();
    let mut stack = vec![from.to_owned()];
    while let Some(p) = stack.pop() {
        if p == target {
            return true;
        }
        if seen.insert(p.clone())
            && let Some(deps) = graph.get(&p)
        {
            stack.extend(deps.iter().cloned());
        }
    }
    false
}

#[test]
fn only_the_replay_and_its_users_depend_on_wgpu() {
    let (graph, local) = lock_graph();
    let gpu_free = [
        "reproj-front",
        "reproj-instance",
        "reproj-scene",
        "reproj-metrics",
        "reproj-models",
        "reproj-select",
        "reproj-emit",
        "reproj-charts",
        "reproj-io",
    ];
    for name in gpu_free {
        assert!(local.contains(name), "{name} is not a workspace crate");
        assert!(
            !reaches(&graph, name, "wgpu"),
            "{name} depends on wgpu (directly or through a dependency): the GPU belongs to reproj-replay"
        );
    }
    let with_gpu: BTreeSet<&str> = local
        .iter()
        .filter(|p| reaches(&graph, p, "wgpu"))
        .map(String::as_str)
        .collect();
    let expected = BTreeSet::from([
        "reproj-analyze",
        "reproj-bench",
        "reproj-cli",
        "reproj-compare",
        "reproj-host",
        "reproj-replay",
        "reproj-report",
        "reproj-runtime",
        "reproj-scene-gpu",
    ]);
    assert_eq!(with_gpu, expected);
    // Of the library crates, only the replay, the runtime and the scene on the device name wgpu
    // themselves; the others reach it through the replay (the example host is a host: it renders
    // with wgpu on its own).
    for p in &with_gpu {
        if ![
            "reproj-replay",
            "reproj-host",
            "reproj-runtime",
            "reproj-scene-gpu",
        ]
        .contains(p)
        {
            assert!(
                !graph[*p].contains("wgpu"),
                "{p} depends on wgpu directly; use it through reproj-replay"
            );
            assert!(reaches(&graph, p, "reproj-replay"), "{p}");
        }
    }
}

/// One executor: the replay draws every variant through the runtime hosts ship (so every figure
/// reproj prints measures that code), and nothing else in the workspace draws manifests.
#[test]
fn the_replay_draws_variants_through_the_runtime() {
    let (graph, _) = lock_graph();
    assert!(graph["reproj-replay"].contains("reproj-runtime"));
    // One scene on the device: the replay and the example host upload and draw it alike.
    assert!(graph["reproj-replay"].contains("reproj-scene-gpu"));
    assert!(graph["reproj-host"].contains("reproj-scene-gpu"));
    let replay = Path::new(env!("CARGO_MANIFEST_DIR")).join("../reproj-replay/src");
    let mut stack = vec![replay];
    while let Some(dir) = stack.pop() {
        for e in std::fs::read_dir(&dir).unwrap() {
            let path = e.unwrap().path();
            if path.is_dir() {
                stack.push(path);
            } else if path.extension().is_some_and(|x| x == "rs") {
                let text = std::fs::read_to_string(&path).unwrap();
                // The roles of the variant's textures are the runtime's to resolve.
                for role in ["ROLE_CUR_PAYLOAD", "PREV_PAYLOAD", "ROLE_PREV_DEPTH_COPY"] {
                    assert!(
                        !text.contains(role),
                        "{} binds the variant's `{role}` itself",
                        path.display()
                    );
                }
            }
        }
    }
}

/// The runtime an engine links depends on no other reproj crate (its test app's scene comes from
/// reproj-scene as a dev-dependency only): the manifest is the interface.
#[test]
fn the_runtime_depends_on_no_reproj_crate() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../reproj-runtime/Cargo.toml");
    let text = std::fs::read_to_string(&path).unwrap();
    let mut section = "";
    let mut deps = Vec::new();
    for line in text.lines().map(str::trim) {
        if line.starts_with('[') {
            section = line;
        } else if section == "[dependencies]" && !line.is_empty() && !line.starts_with('#') {
            deps.push(
                line.split(['.', '=', ' '])
                    .next()
                    .unwrap_or_default()
                    .to_owned(),
            );
        }
    }
    assert!(deps.contains(&"wgpu".to_owned()), "{deps:?}");
    let ours: Vec<&String> = deps.iter().filter(|d| d.starts_with("reproj")).collect();
    assert!(ours.is_empty(), "reproj-runtime depends on {ours:?}");
}

/// `cargo tree --offline --locked --prefix none ARGS` in the workspace's root: its output.
fn cargo_tree(args: &[&str]) -> String {
    let cargo = std::env::var("CARGO").unwrap_or_else(|_| "cargo".into());
    let out = std::process::Command::new(&cargo)
        .current_dir(Path::new(env!("CARGO_MANIFEST_DIR")).join("../.."))
        .args(["tree", "--offline", "--locked", "--prefix", "none"])
        .args(args)
        .output()
        .expect("run cargo tree");
    assert!(
        out.status.success(),
        "cargo tree: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    String::from_utf8_lossy(&out.stdout).into_owned()
}

/// The light build CI uses to run `emit` (`reproj-cli` without its default features `gpu`, `gltf`
/// and `compose`: nodes, instance, emit) compiles neither wgpu nor nv-flip's C++ nor the charts,
/// nor the image codecs, the glTF reader or naga_oil and its regex engine: checked on the
/// resolved graph of that feature set (`cargo tree`, offline: no download, no build). That it
/// builds is `scripts/check-light.sh` (`cargo build -p reproj-cli --no-default-features`, run by
/// `scripts/test.sh`); docs/CI.md has the timings.
#[test]
fn the_light_build_has_no_gpu_crates() {
    let tree = |features: &[&str]| {
        let mut args = vec!["-p", "reproj-cli", "-e", "normal,build", "--format", "{p}"];
        args.extend_from_slice(features);
        let names: BTreeSet<String> = cargo_tree(&args)
            .lines()
            .filter_map(|l| l.split_whitespace().next().map(str::to_owned))
            .collect();
        names
    };
    let light = tree(&["--no-default-features"]);
    for heavy in [
        "wgpu",
        "nv-flip",
        "nv-flip-sys",
        "plotters",
        "reproj-replay",
        "reproj-bench",
        "reproj-analyze",
        "cc",
        "image",
        "gltf",
        "naga_oil",
        "regex",
    ] {
        assert!(
            !light.contains(heavy),
            "the light build depends on {heavy}: keep it behind one of reproj-cli's default features"
        );
    }
    for needed in [
        "reproj-emit",
        "reproj-instance",
        "reproj-scene",
        "reproj-metrics",
        "naga",
        "clap_complete",
    ] {
        assert!(
            light.contains(needed),
            "{needed} missing from the light build"
        );
    }
    let full = tree(&[]);
    for heavy in ["wgpu", "nv-flip", "reproj-replay", "reproj-bench"] {
        assert!(full.contains(heavy), "the default build has {heavy}");
    }
}

/// The light build's dependencies are compiled with the features the full build gives them, so
/// the light build (`scripts/check-light.sh`) reuses what `cargo test --workspace` compiled and
/// builds only reproj's own crates again: every package and feature set of the two light
/// invocations (`cargo tree`, offline) is one the workspace's build has. Where one is not,
/// `crates/reproj-workspace-hack/Cargo.toml` needs the features the message names.
#[test]
fn the_light_build_shares_the_full_builds_dependencies() {
    let tree = |args: &[&str]| -> BTreeMap<String, BTreeSet<String>> {
        let mut args = args.to_vec();
        args.extend(["--format", "{p}|{f}"]);
        let mut sets: BTreeMap<String, BTreeSet<String>> = BTreeMap::new();
        for line in cargo_tree(&args).lines() {
            let line = line.trim_end_matches(" (*)");
            if let Some((p, f)) = line.split_once('|')
                && (!p.contains(" (/") || p.contains("/vendor/"))
            {
                sets.entry(p.to_owned()).or_default().insert(f.to_owned());
            }
        }
        sets
    };
    let full = tree(&["--workspace", "-e", "normal,build,dev"]);
    let light_tests = [
        "-p",
        "reproj-emit",
        "-p",
        "reproj-scene",
        "-p",
        "reproj-front",
        "--no-default-features",
        "-e",
        "normal,build,dev",
    ];
    let light_cli = [
        "-p",
        "reproj-cli",
        "--no-default-features",
        "-e",
        "normal,build",
    ];
    let mut missing = Vec::new();
    for light in [tree(&light_tests), tree(&light_cli)] {
        for (p, sets) in light {
            for f in sets {
                if !full.get(&p).is_some_and(|s| s.contains(&f)) {
                    let have = full.get(&p).map(|s| s.iter().cloned().collect::<Vec<_>>());
                    missing.push(format!("{p}: light [{f}], full {have:?}"));
                }
            }
        }
    }
    assert!(
        missing.is_empty(),
        "the light build compiles these with other features than the full build (add the full \
         build's to crates/reproj-workspace-hack): {missing:#?}"
    );
}

/// Inside the crates split from the replay, a module imports only from the modules below it (no
/// import circles): each list is the crate's modules bottom-up, as its `lib.rs` documents them,
/// and every `crate::m` a module names (outside comments) must come before it in the list.
#[test]
fn modules_import_only_from_below() {
    let crates: [(&str, &[&str]); 3] = [
        (
            "reproj-scene",
            &[
                "reflect", "session", "geometry", "gltf", "mesh", "textures", "load", "uniforms",
                "vertex", "init",
            ],
        ),
        (
            "reproj-metrics",
            &["l2", "report", "srgb", "perceptual", "output"],
        ),
        (
            "reproj-replay",
            &[
                "error", "backend", "jitter", "vertex", "gpu", "readback", "assets", "reduce",
                "render",
            ],
        ),
    ];
    for (name, order) in crates {
        let src = Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("..")
            .join(name)
            .join("src");
        let mut files = vec![src.clone()];
        let mut seen = BTreeSet::new();
        while let Some(p) = files.pop() {
            if p.is_dir() {
                files.extend(std::fs::read_dir(&p).unwrap().map(|e| e.unwrap().path()));
                continue;
            }
            if p.extension().is_none_or(|x| x != "rs") || p.file_name().unwrap() == "lib.rs" {
                continue;
            }
            let rel = p.strip_prefix(&src).unwrap();
            let module = rel.iter().next().unwrap().to_str().unwrap();
            let module = module.strip_suffix(".rs").unwrap_or(module);
            let rank = |m: &str| order.iter().position(|o| *o == m);
            let own = rank(module)
                .unwrap_or_else(|| panic!("{name}: module {module} is not in the list"));
            seen.insert(module.to_owned());
            let text = std::fs::read_to_string(&p).unwrap();
            for used in crate_paths(&text, Part::Whole) {
                let Some(r) = rank(&used) else {
                    continue;
                };
                assert!(
                    r <= own,
                    "{name}: {} imports crate::{used}, which is above it ({order:?})",
                    rel.display()
                );
            }
        }
        assert_eq!(
            seen.len(),
            order.len(),
            "{name}: {seen:?} against {order:?}"
        );
    }
}

/// Which part of a file [`crate_paths`] reads.
#[derive(Clone, Copy, PartialEq)]
enum Part {
    /// All of it.
    Whole,
    /// What comes before its `#[cfg(test)]` part (whose tests may reach across).
    Code,
}

/// The `crate::` paths a file names outside comments (in `part` of it): the first segment of
/// each, `use crate::{a::X, b}` giving `a` and `b`.
fn crate_paths(text: &str, part: Part) -> Vec<String> {
    let code: String = text
        .lines()
        .take_while(|l| part == Part::Whole || l.trim() != "#[cfg(test)]")
        .filter(|l| !l.trim_start().starts_with("//"))
        .collect::<Vec<_>>()
        .join("\n");
    let ident = |s: &str| -> String {
        s.trim_start()
            .chars()
            .take_while(|c| c.is_ascii_alphanumeric() || *c == '_')
            .collect()
    };
    let mut out = Vec::new();
    for (i, _) in code.match_indices("crate::") {
        // `crate::`, not the end of another name (`$crate::` in a macro is fine).
        if code[..i]
            .chars()
            .last()
            .is_some_and(|c| c.is_ascii_alphanumeric() || c == '_' || c == '$')
        {
            continue;
        }
        let rest = &code[i + "crate::".len()..];
        let Some(group) = rest.strip_prefix('{') else {
            out.push(ident(rest));
            continue;
        };
        // The group's items at its top level.
        let (mut depth, mut start) = (0usize, 0usize);
        for (j, c) in group.char_indices() {
            match c {
                '{' => depth += 1,
                '}' if depth == 0 => {
                    out.push(ident(&group[start..j]));
                    break;
                }
                '}' => depth -= 1,
                ',' if depth == 0 => {
                    out.push(ident(&group[start..j]));
                    start = j + 1;
                }
                _ => {}
            }
        }
    }
    out
}

/// No crate's top-level modules import each other in a circle (every crate, computed from the
/// code: a module that uses another's items sits above it, so each crate reads bottom-up).
#[test]
fn no_crate_has_an_import_circle() {
    let crates = Path::new(env!("CARGO_MANIFEST_DIR")).join("..");
    let mut circles = Vec::new();
    for entry in std::fs::read_dir(&crates).unwrap() {
        let src = entry.unwrap().path().join("src");
        if !src.is_dir() {
            continue;
        }
        let name = src.parent().unwrap().file_name().unwrap().to_string_lossy();
        let module_of = |p: &Path| -> Option<String> {
            let first = p.strip_prefix(&src).ok()?.iter().next()?.to_str()?;
            let m = first.strip_suffix(".rs").unwrap_or(first);
            (m != "lib" && m != "main").then(|| m.to_owned())
        };
        let mut files = vec![src.clone()];
        let mut graph: BTreeMap<String, BTreeSet<String>> = BTreeMap::new();
        let mut sources = Vec::new();
        while let Some(p) = files.pop() {
            if p.is_dir() {
                files.extend(std::fs::read_dir(&p).unwrap().map(|e| e.unwrap().path()));
            } else if p.extension().is_some_and(|x| x == "rs")
                && let Some(m) = module_of(&p)
            {
                graph.entry(m.clone()).or_default();
                sources.push((m, p));
            }
        }
        for (m, p) in sources {
            let text = std::fs::read_to_string(&p).unwrap();
            for used in crate_paths(&text, Part::Code) {
                if used != m && graph.contains_key(&used) {
                    graph.get_mut(&m).unwrap().insert(used);
                }
            }
        }
        // A depth-first walk: a module met again while on the path closes a circle.
        fn walk(
            m: &str,
            graph: &BTreeMap<String, BTreeSet<String>>,
            path: &mut Vec<String>,
            done: &mut BTreeSet<String>,
            found: &mut Vec<String>,
        ) {
            if let Some(at) = path.iter().position(|p| p == m) {
                found.push(format!("{} → {m}", path[at..].join(" → ")));
                return;
            }
            if !done.insert(m.to_owned()) {
                return;
            }
            path.push(m.to_owned());
            for next in &graph[m] {
                walk(next, graph, path, done, found);
            }
            path.pop();
        }
        let mut done = BTreeSet::new();
        let mut found = Vec::new();
        for m in graph.keys() {
            walk(m, &graph, &mut Vec::new(), &mut done, &mut found);
        }
        circles.extend(found.into_iter().map(|c| format!("{name}: {c}")));
    }
    assert!(
        circles.is_empty(),
        "import circles:\n{}",
        circles.join("\n")
    );
}
