//! Bad written variants (`render --variant`): missing, a manifest that is not JSON, of another
//! version or without passes; a manifest naming a pass outside its folder; a pass whose arrays are
//! over the GPU memory budget; and a variant run with a shader that is not its own.

use super::{Case, Good, case, input};

/// `render good.wgsl` with the variant in `v/`.
const RENDER_V: [&str; 6] = [
    "render",
    "good.wgsl",
    "--session",
    "good.json",
    "--variant",
    "v",
];

/// A pass whose private array takes 64 MiB per invocation: over the GPU memory budget.
const BIG_PASS: &str = "var<private> big: array<f32, 16777216>;\n@fragment\nfn main(@builtin(position) p: vec4<f32>) -> @location(0) vec4<f32> {\n    big[u32(p.x)] = p.y;\n    return vec4<f32>(big[u32(p.y)]);\n}\n";

pub(super) fn cases(good: &Good) -> Vec<Case> {
    let manifest = |edit: &dyn Fn(&mut serde_json::Value)| good.manifest(edit);
    vec![
        // A manifest names its passes beside it: never a file elsewhere, whose text a parse
        // error would show.
        case(
            "variant pass at an absolute path",
            &[(
                "v/manifest.json",
                &manifest(&|v| v["passes"][0]["file"] = "/etc/passwd".into()),
            )],
            &RENDER_V,
            "passes[0].file`: `/etc/passwd` is outside the manifest's folder",
        ),
        case(
            "variant pass above its folder",
            &[(
                "v/manifest.json",
                &manifest(&|v| v["passes"][0]["file"] = "../good.wgsl".into()),
            )],
            &RENDER_V,
            "outside the manifest's folder",
        ),
        // A variant's pass is a shader read from a file: the same GPU memory budget as any.
        case(
            "variant pass over the GPU memory budget",
            &[
                (
                    "v/manifest.json",
                    &manifest(&|v| v["passes"][0]["file"] = "big.wgsl".into()),
                ),
                ("v/big.wgsl", BIG_PASS),
            ],
            &RENDER_V,
            "big.wgsl: `big` (private) takes 67108864 bytes per invocation",
        ),
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
