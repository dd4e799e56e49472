//! What the shader targets (`glsl`, `spirv`) run once a shader is parsed, as `front_end` does
//! for WGSL: normalize every fragment entry point by name, enumerate, and check the node table.

use reproj_front::{FrontError, NormalizeOptions, Shader, enumerate, normalize};

/// A parse error is rendered as the CLI shows it (must not panic); a parsed shader goes through
/// normalize and enumerate.
pub fn after_parse(parsed: Result<Shader, FrontError>) {
    let shader = match parsed {
        Ok(shader) => shader,
        Err(e) => {
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
            Err(e) => {
                if let Some(d) = e.diagnostic() {
                    let _ = d.render();
                }
                continue;
            }
        };
        let table = enumerate(&shader, &norm);
        let _ = table.root();
        for n in &table.nodes {
            assert!(table.get(n.id).is_some());
        }
    }
}
