//! What every shader target (`front_end`, `glsl`, `spirv`) runs once a shader is parsed:
//! normalize every fragment entry point by name, enumerate, and check the node table.
//!
//! With REPROJ_FUZZ_STRICT=1 two more things count as crashes: `FrontError::Internal`, and a
//! normalized module that does not survive a round trip through WGSL (naga's validator does not
//! check that an expression's operands are in scope; the WGSL writer and parser do).

use reproj_front::{FrontError, NormalizeOptions, Shader, enumerate, normalize};

fn strict() -> bool {
    static STRICT: std::sync::OnceLock<bool> = std::sync::OnceLock::new();
    *STRICT.get_or_init(|| std::env::var_os("REPROJ_FUZZ_STRICT").is_some_and(|v| v == "1"))
}

fn round_trip(module: &naga::Module, info: &naga::valid::ModuleInfo) {
    let text = naga::back::wgsl::write_string(module, info, naga::back::wgsl::WriterFlags::empty())
        .expect("the normalized module cannot be written as WGSL");
    let again = match naga::front::wgsl::parse_str(&text) {
        Ok(m) => m,
        // naga's writer nests single-use expressions; deep helper chains exceed its parser's
        // recursion limit. A limit of naga, not a reproj bug.
        Err(e) if e.emit_to_string(&text).contains("recursion limit") => return,
        Err(e) => panic!("normalized WGSL does not parse:\n{}\n{text}", e.emit_to_string(&text)),
    };
    if let Err(e) = reproj_front::validator().validate(&again) {
        panic!("normalized WGSL does not validate:\n{}\n{text}", e.emit_to_string(&text));
    }
}

/// A parse error is rendered as the CLI shows it (must not panic); a parsed shader goes through
/// normalize and enumerate.
pub fn after_parse(parsed: Result<Shader, FrontError>) {
    let shader = match parsed {
        Ok(shader) => shader,
        Err(e) => {
            // What the CLI shows: the diagnostic rendered from its spans (must not panic).
            if let Some(d) = e.diagnostic() {
                let _ = d.render();
            }
            let _ = e.to_string();
            return;
        }
    };
    let entries: Vec<String> = shader
        .module
        .entry_points
        .iter()
        .filter(|ep| ep.stage == naga::ShaderStage::Fragment)
        .map(|ep| ep.name.clone())
        .collect();
    for name in entries {
        let opts = NormalizeOptions { entry: Some(name), ..Default::default() };
        let norm = match normalize(&shader, &opts) {
            Ok(norm) => norm,
            // `Internal` means a reproj invariant did not hold.
            Err(e @ FrontError::Internal { .. }) if strict() => panic!("{e}"),
            Err(e) => {
                if let Some(d) = e.diagnostic() {
                    let _ = d.render();
                }
                continue;
            }
        };
        if strict() {
            round_trip(&norm.module, &norm.info);
        }
        let table = enumerate(&shader, &norm);
        // The root is always a node (`root()` panics otherwise; reproj-instance relies on it).
        let _ = table.root();
        // Every node of the table must be reachable by its id.
        for n in &table.nodes {
            assert!(table.get(n.id).is_some());
        }
    }
}
