//! The wgpu backends this build can open, and backend lists (`--backend`, `WGPU_BACKEND`) checked
//! against them.
//!
//! wgpu quietly ignores a backend name it does not know, and a backend it was built without simply
//! finds no adapter, so a typo or `gl` in a Vulkan-only build used to end in "no GPU adapter found".
//! Here either is an error that names the accepted values. Which backends are compiled in is
//! wgpu's own answer ([`wgpu::Instance::enabled_backend_features`]), decided by the wgpu features in
//! the workspace `Cargo.toml` (Vulkan only: lavapipe, Mesa's software Vulkan, runs every test; GL on
//! llvmpipe cannot render to the `rgba32float` targets the replay uses).

use crate::error::ReplayError;

/// wgpu's backends with the names `WGPU_BACKEND` accepts for each, the first one canonical.
const NAMES: &[(wgpu::Backends, &[&str])] = &[
    (wgpu::Backends::VULKAN, &["vulkan", "vk"]),
    (wgpu::Backends::GL, &["gl", "gles", "opengl"]),
    (wgpu::Backends::METAL, &["metal", "mtl"]),
    (wgpu::Backends::DX12, &["dx12", "d3d12"]),
    (wgpu::Backends::BROWSER_WEBGPU, &["webgpu"]),
];

/// The backends compiled into this build, by canonical name (`["vulkan"]`).
pub fn compiled_backends() -> Vec<&'static str> {
    let enabled = wgpu::Instance::enabled_backend_features();
    NAMES
        .iter()
        .filter(|(b, _)| enabled.contains(*b))
        .map(|(_, names)| names[0])
        .collect()
}

/// Every name that selects a compiled backend (`vulkan, vk`).
fn accepted_names() -> Vec<&'static str> {
    let enabled = wgpu::Instance::enabled_backend_features();
    NAMES
        .iter()
        .filter(|(b, _)| enabled.contains(*b))
        .flat_map(|(_, names)| names.iter().copied())
        .collect()
}

/// Parse a comma-separated backend list (case-insensitive, as `WGPU_BACKEND`); `source` names where
/// it came from in the error (`--backend`, `WGPU_BACKEND`). Every name must select a backend this
/// build has.
pub fn parse_backends(list: &str, source: &str) -> Result<wgpu::Backends, ReplayError> {
    let mut backends = wgpu::Backends::empty();
    let enabled = wgpu::Instance::enabled_backend_features();
    let error = |name: &str, reason: &str| ReplayError::Backend {
        origin: source.to_string(),
        name: name.to_string(),
        reason: reason.to_string(),
        compiled: compiled_backends().join(", "),
        accepted: accepted_names().join(", "),
    };
    for name in list.split(',').map(str::trim) {
        let lower = name.to_ascii_lowercase();
        let Some((b, _)) = NAMES
            .iter()
            .find(|(_, names)| names.contains(&lower.as_str()))
        else {
            return Err(error(name, "is not a wgpu backend"));
        };
        if !enabled.contains(*b) {
            return Err(error(name, "is not built into this reproj"));
        }
        backends |= *b;
    }
    Ok(backends)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn vulkan_and_its_alias_parse() {
        assert_eq!(
            parse_backends("vulkan", "--backend").unwrap(),
            wgpu::Backends::VULKAN
        );
        assert_eq!(
            parse_backends(" VK ", "--backend").unwrap(),
            wgpu::Backends::VULKAN
        );
        assert_eq!(compiled_backends(), ["vulkan"]);
    }

    #[test]
    fn unknown_and_missing_backends_are_named() {
        let e = parse_backends("bogus", "--backend")
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("`bogus`") && e.contains("not a wgpu backend"),
            "{e}"
        );
        assert!(e.contains("vulkan, vk"), "{e}");
        let e = parse_backends("vulkan,gl", "WGPU_BACKEND")
            .unwrap_err()
            .to_string();
        assert!(e.contains("WGPU_BACKEND") && e.contains("`gl`"), "{e}");
        assert!(e.contains("not built into this reproj"), "{e}");
        assert!(parse_backends("", "--backend").is_err());
    }
}
