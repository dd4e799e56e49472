//! How every command that reads a shader reads it, beyond its language: shader defs, the
//! folders its imports and includes are searched in, and loop unrolling. Flattened into each command's arguments.

use std::path::PathBuf;

use clap::Args;

/// How the shader file is read beyond its language (`reproj_front::ShaderInput`): shared by every
/// command that reads a shader; `analyze` records it in the profile, so `emit`, `report` and
/// `compare --profile` read the shader as it did.
#[derive(Debug, Clone, Default, Args)]
pub struct ShaderInputArgs {
    /// A shader def, NAME or NAME=VALUE (VALUE: true, false or an integer; no value: true), for
    /// naga_oil's `#ifdef`/`#if` in WGSL and as a macro in GLSL (a bool is 1 or 0). Repeatable; a
    /// def the shader never reads is a warning.
    #[arg(long = "def", value_name = "NAME[=VALUE]", value_parser = crate::values::shader_def)]
    pub defs: Vec<(String, reproj_front::DefValue)>,
    /// An engine's usual defs, under the --def ones: `bevy` (docs/USAGE.md lists them).
    #[arg(long, value_name = "ENGINE", value_parser = crate::values::defs_preset)]
    pub defs_preset: Option<reproj_front::DefsPreset>,
    /// A WGSL import folder only (as --include-dir, which also serves GLSL).
    #[arg(hide = true, long = "import-path", value_name = "DIR")]
    pub import_paths: Vec<PathBuf>,
    /// A folder searched for what the shader pulls in, after the shader's own; repeatable. WGSL:
    /// searched with its subfolders for `#import`ed modules, and asset-path imports
    /// (`#import "shaders/x.wgsl"`) are resolved against it (before REPROJ_WGSL_IMPORTS). GLSL:
    /// searched for `#include "x"`, as glslang's -I.
    #[arg(short = 'I', long = "include-dir", value_name = "DIR")]
    pub include_dirs: Vec<PathBuf>,
}

impl ShaderInputArgs {
    /// The front end's value.
    pub fn to_input(&self) -> reproj_front::ShaderInput {
        reproj_front::ShaderInput {
            defs: self.defs.iter().cloned().collect(),
            preset: self.defs_preset,
            import_paths: self
                .import_paths
                .iter()
                .chain(&self.include_dirs)
                .cloned()
                .collect(),
            include_dirs: self.include_dirs.clone(),
        }
    }

    /// Whether nothing was given (the shader read as by default).
    pub fn is_empty(&self) -> bool {
        self.to_input().is_default()
    }
}

/// Loop unrolling before the nodes are listed (`nodes`, `instance`, `analyze`; `emit` takes it
/// from the profile).
#[derive(Debug, Args)]
pub struct UnrollArg {
    /// Unroll loops with a constant trip count of at most N iterations (nested loops multiply)
    /// before listing nodes, so each iteration's values become nodes; 0: off. Off by default:
    /// node ids, node tables and the profiles recorded so far stay as they were, and unrolling
    /// multiplies a loop shader's nodes (ambient_occlusion: 35 cacheable → 843 at 32), which
    /// only pays when a per-iteration value is worth caching. Ids differ between values: pass
    /// the same N to `nodes`, `instance` and `analyze`.
    #[arg(long, hide = true, default_value_t = 0, value_name = "N")]
    pub unroll: u32,
}
