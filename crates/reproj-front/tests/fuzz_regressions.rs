//! Inputs found by the front-end fuzzer (`fuzz/`), plus hand-written tricky seeds: each file in
//! `tests/fuzz_regressions/` goes through parse → normalize (every fragment entry by name, and the
//! default choice) → enumerate. Errors are fine; a panic is a bug. Each normalized module must
//! also survive a round trip through WGSL (naga's validator does not check that an expression's
//! operands are in scope; its WGSL parser does).

use std::panic::{AssertUnwindSafe, catch_unwind};
use std::path::{Path, PathBuf};

use reproj_front::{NormalizeOptions, enumerate, normalize, parse_shader};

/// The normalized module written as WGSL; `Err` if that text does not parse and validate again.
fn round_trip(module: &naga::Module, info: &naga::valid::ModuleInfo) -> Result<(), String> {
    let text = naga::back::wgsl::write_string(module, info, naga::back::wgsl::WriterFlags::empty())
        .map_err(|e| format!("cannot write WGSL: {e}"))?;
    let again = match naga::front::wgsl::parse_str(&text) {
        Ok(m) => m,
        // naga's writer nests single-use expressions; a long helper chain exceeds its parser's
        // recursion limit. A naga limit, not a reproj bug.
        Err(e) if e.emit_to_string(&text).contains("recursion limit") => return Ok(()),
        Err(e) => return Err(format!("{}\n{text}", e.emit_to_string(&text))),
    };
    reproj_front::validator()
        .validate(&again)
        .map(|_| ())
        .map_err(|e| format!("{}\n{text}", e.emit_to_string(&text)))
}

/// Run one input through the front end; a one-line summary of what happened.
fn run(path: &Path, source: String) -> String {
    let shader = match parse_shader(path, source) {
        Ok(s) => s,
        Err(_) => return "parse/validation error".into(),
    };
    let names: Vec<Option<String>> = std::iter::once(None)
        .chain(
            shader
                .module
                .entry_points
                .iter()
                .filter(|ep| ep.stage == naga::ShaderStage::Fragment)
                .map(|ep| Some(ep.name.clone())),
        )
        .collect();
    let mut out = Vec::new();
    for entry in names {
        let label = entry.clone().unwrap_or_else(|| "<default>".into());
        match normalize(
            &shader,
            &NormalizeOptions {
                entry,
                ..Default::default()
            },
        ) {
            Ok(norm) => {
                if let Err(e) = round_trip(&norm.module, &norm.info) {
                    panic!("{label}: the normalized module does not round-trip through WGSL: {e}");
                }
                let table = enumerate(&shader, &norm);
                // Downstream crates rely on this (it panics when the root is not a node).
                let _ = table.root();
                out.push(format!("{label}: {} nodes", table.nodes.len()));
            }
            Err(e) => out.push(format!(
                "{label}: error: {}",
                e.to_string().lines().next().unwrap_or("")
            )),
        }
    }
    out.join("; ")
}

#[test]
fn fuzz_regressions_do_not_panic() {
    let dir = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("tests/fuzz_regressions");
    let mut files: Vec<PathBuf> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|x| x == "wgsl"))
        .collect();
    files.sort();
    assert!(!files.is_empty(), "no inputs in {}", dir.display());
    let mut panicked = Vec::new();
    for path in &files {
        // Fuzzer inputs may be any bytes; the fuzz target skips what is not UTF-8.
        let Ok(source) = String::from_utf8(std::fs::read(path).unwrap()) else {
            continue;
        };
        let name = path.file_name().unwrap().to_string_lossy().into_owned();
        match catch_unwind(AssertUnwindSafe(|| run(path, source))) {
            Ok(summary) => println!("{name}: {summary}"),
            Err(_) => {
                println!("{name}: PANIC");
                panicked.push(name);
            }
        }
    }
    assert!(
        panicked.is_empty(),
        "the front end panicked on: {}",
        panicked.join(", ")
    );
}

/// The SPIR-V inputs the `spirv` target found a crash with (`*.spv`): the sampler split
/// (`spirv_short_instruction.spv`: it indexed the operands of a too-short instruction), then
/// naga's SPIR-V front end (`spirv_phi_block.spv`: an `OpPhi` naming no block; patched,
/// vendor/naga/REPROJ-PATCH.md), must return an error or a module, never panic.
#[test]
fn spirv_fuzz_regressions_do_not_panic() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fuzz_regressions");
    let mut n = 0;
    for e in std::fs::read_dir(&dir).unwrap() {
        let path = e.unwrap().path();
        if path.extension().is_none_or(|x| x != "spv") {
            continue;
        }
        let bytes = std::fs::read(&path).unwrap();
        let words: Vec<u32> = bytes
            .chunks_exact(4)
            .map(|w| u32::from_le_bytes([w[0], w[1], w[2], w[3]]))
            .collect();
        if let Ok((split, _)) = reproj_front::glslang::split::split_combined_samplers(&words) {
            let split: Vec<u8> = split.iter().flat_map(|w| w.to_le_bytes()).collect();
            let _ = reproj_front::parse_spirv(&path, &split);
        }
        let _ = reproj_front::parse_spirv(&path, &bytes);
        n += 1;
    }
    assert!(n > 0);
}

/// The GLSL inputs the `glsl` target found a crash with (`*.frag`), through naga's GLSL front
/// end (what reproj reads GLSL with where glslang is missing): an error or a module, never a
/// panic. `glsl_layout_index.frag` (`layout(location = 1[4])`) made naga index an arena with
/// another arena's handle (patched: vendor/naga/REPROJ-PATCH.md).
#[test]
fn glsl_fuzz_regressions_do_not_panic() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fuzz_regressions");
    let mut n = 0;
    for e in std::fs::read_dir(&dir).unwrap() {
        let path = e.unwrap().path();
        if path.extension().is_none_or(|x| x != "frag") {
            continue;
        }
        let text = std::fs::read_to_string(&path).unwrap();
        let options = naga::front::glsl::Options::from(naga::ShaderStage::Fragment);
        let _ = naga::front::glsl::Frontend::default().parse(&options, &text);
        n += 1;
    }
    assert!(n > 0);
}
