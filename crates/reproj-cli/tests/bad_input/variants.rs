//! Bad written variants (`render --variant`): missing, a manifest that is not JSON, of another
//! version or without passes; and a variant run with a shader that is not its own.

use super::{Case, case, input};

pub(super) fn cases() -> Vec<Case> {
    vec![
        // Written variants.
        case(
            "variant missing",
            &[],
            &[
                "render",
                "good.wgsl",
                "--session",
                "good.json",
                "--variant",
                "nowhere",
            ],
            "nowhere",
        ),
        case(
            "variant manifest not JSON",
            &[("v/manifest.json", &input("manifests/not_json.json"))],
            &[
                "render",
                "good.wgsl",
                "--session",
                "good.json",
                "--variant",
                "v",
            ],
            "manifest.json",
        ),
        case(
            "variant manifest version 2",
            &[("v/manifest.json", &input("manifests/version_2.json"))],
            &[
                "render",
                "good.wgsl",
                "--session",
                "good.json",
                "--variant",
                "v",
            ],
            "version 2",
        ),
        case(
            "variant manifest missing passes",
            &[("v/manifest.json", &input("manifests/missing_passes.json"))],
            &[
                "render",
                "good.wgsl",
                "--session",
                "good.json",
                "--variant",
                "v",
            ],
            "manifest.json",
        ),
        // A variant runs only with its own shader.
        case(
            "variant of another shader",
            &[("other.wgsl", &input("shaders/other_than_the_variants.wgsl"))],
            &[
                "render",
                "other.wgsl",
                "--session",
                "good.json",
                "--variant",
                "variant",
                "--max-frames",
                "2",
            ],
            "is a variant of good.wgsl",
        ),
        case(
            "bench a variant of another shader",
            &[("other.wgsl", &input("shaders/other_than_the_variants.wgsl"))],
            &[
                "bench",
                "other.wgsl",
                "--session",
                "good.json",
                "variant",
                "--max-frames",
                "2",
            ],
            "is a variant of good.wgsl",
        ),
    ]
}
