//! Vulkan's own rules, checked by Khronos' validation layer: every strategy draws its variant
//! without a validation error. lavapipe draws what the Vulkan spec leaves undefined as it was
//! meant (a descriptor set left bound under an incompatible pipeline layout drew right there and
//! nothing at all on NVIDIA's driver); the layer names it on any machine.

use std::path::Path;

use crate::common;

/// Where the layer's manifest is installed (Debian's `vulkan-validationlayers`).
const LAYER_JSON: &str = "/usr/share/vulkan/explicit_layer.d/VkLayer_khronos_validation.json";

/// Whether the validation layer is installed; under CI it must be (`scripts/ensure-tools.sh`
/// installs it).
fn layer() -> bool {
    let found = Path::new(LAYER_JSON).exists();
    assert!(
        found || std::env::var_os("CI").is_none(),
        "CI is set and Vulkan's validation layer is missing ({LAYER_JSON}): scripts/ensure-tools.sh installs it"
    );
    if !found {
        eprintln!("skipped: Vulkan's validation layer is not installed ({LAYER_JSON})");
    }
    found
}

/// `reproj ARGS` in `cwd` under the validation layer: the loader inserted it (its own debug
/// output says so), exit 0 and not one validation message (the layer prints them to stdout).
fn renders_clean(cwd: &Path, args: &[&str]) {
    let (code, out, err) = common::run_env(
        cwd,
        args,
        &[
            ("VK_INSTANCE_LAYERS", "VK_LAYER_KHRONOS_validation"),
            ("VK_LOADER_DEBUG", "layer"),
        ],
    );
    assert_eq!(code, 0, "{args:?}: {err}");
    assert!(
        err.contains(r#"Insert instance layer "VK_LAYER_KHRONOS_validation""#),
        "{args:?}: the validation layer was not loaded: {err}"
    );
    for text in [&out, &err] {
        let first = text.lines().find(|l| l.contains("Validation Error"));
        assert!(first.is_none(), "{args:?}: {}", first.unwrap_or_default());
    }
}

/// marble's node 680 under each strategy: the 2pass and 3pass layouts' later passes declare
/// nothing in the variant's group, which is where a gap in a pipeline layout left the vertex
/// stage's group bound under the previous pass's layout.
#[test]
fn every_strategy_draws_without_a_validation_error() {
    if !layer() {
        return;
    }
    for strategy in ["3pass", "2pass", "fused"] {
        renders_clean(
            &common::root(),
            &[
                "render",
                "shaders/marble.wgsl",
                "--session",
                "sessions/marble.json",
                "--node",
                "680",
                "--strategy",
                strategy,
                "--delta-n",
                "4",
                "--max-frames",
                "3",
                "--json",
            ],
        );
    }
}

/// Engine-style shaders on three and on all four bind groups (the variant's bindings in a
/// group of their own, or sharing the shader's group 3), 2pass.
#[test]
fn shaders_on_three_and_four_groups_draw_without_a_validation_error() {
    if !layer() {
        return;
    }
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    common::two_terms(dir, "unused.wgsl", "s.json");
    for fixture in ["three_groups.wgsl", "four_groups.wgsl"] {
        std::fs::copy(
            common::root()
                .join("crates/reproj-cli/tests/data")
                .join(fixture),
            dir.join(fixture),
        )
        .unwrap();
        renders_clean(
            dir,
            &[
                "render",
                fixture,
                "--session",
                "s.json",
                "--node",
                "root",
                "--strategy",
                "2pass",
                "--delta-n",
                "4",
                "--max-frames",
                "3",
                "--json",
            ],
        );
    }
}
