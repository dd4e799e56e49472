//! Every file a variant writes, through every independent validator of its target: WGSL through
//! naga and tint, SPIR-V through spirv-val for Vulkan 1.0 and 1.2, GLSL through glslang for
//! Vulkan (`-V`) and for OpenGL (`-G`). HLSL and MSL are written by naga's writers; no validator
//! for them is installed here. A check is *not applicable*, counted apart and said in the cell,
//! where the file's target is not the validator's:
//!
//! - tint on WGSL of wgpu's native target (an `enable wgpu_…;` extension: a binding array; or
//!   push constants, `var<immediate>`, which WebGPU does not have), which tint, a validator of
//!   the WebGPU standard, does not know; naga validates it;
//! - tint where the shader read in already fails it (`original_fails`): naga accepts what the
//!   WGSL standard's uniformity rule refuses, and the passes keep the shader's own code;
//! - `glslang -G` on GLSL whose OpenGL branch is the writer's own `#error` (push constants that
//!   std140 cannot hold: the file says it is for Vulkan only);
//! - glslang on GLSL asking for `GL_EXT_texture_shadow_lod` (naga's GLSL of a depth cube-array
//!   lookup at level 0), which glslang 12 does not know.

use std::path::{Path, PathBuf};
use std::process::Command;

use reproj_instance::backends::{OutputLang, Outputs};
use reproj_instance::{Variant, write_variant_in};
use serde_json::{Value, json};

/// One validator: a name for the table, the tool and its arguments before the file.
pub struct Validator {
    pub name: &'static str,
    pub tool: &'static str,
    pub args: &'static [&'static str],
    /// The extension of the files it checks.
    pub ext: &'static str,
}

pub const VALIDATORS: [Validator; 6] = [
    Validator {
        name: "naga",
        tool: "naga",
        args: &[],
        ext: "wgsl",
    },
    Validator {
        name: "tint",
        tool: "tint",
        args: &["--format", "wgsl", "-o", "/dev/null"],
        ext: "wgsl",
    },
    Validator {
        name: "spirv-val vulkan1.0",
        tool: "spirv-val",
        args: &["--target-env", "vulkan1.0"],
        ext: "spv",
    },
    Validator {
        name: "spirv-val vulkan1.2",
        tool: "spirv-val",
        args: &["--target-env", "vulkan1.2"],
        ext: "spv",
    },
    Validator {
        name: "glslang -V",
        tool: "glslangValidator",
        args: &["-V", "-o", "/dev/null", "-S", "frag"],
        ext: "frag",
    },
    Validator {
        name: "glslang -G",
        tool: "glslangValidator",
        args: &["-G", "-o", "/dev/null", "-S", "frag"],
        ext: "frag",
    },
];

/// Whether `tool` can be started (tint has no `--version`: any exit status will do).
pub fn installed(tool: &str) -> bool {
    Command::new(tool).arg("--help").output().is_ok()
}

/// `validator`'s failure on `file`, as one short line, or `None` when it accepts the file.
fn rejects(validator: &Validator, file: &Path) -> Option<String> {
    let out = match Command::new(validator.tool)
        .args(validator.args)
        .arg(file)
        .output()
    {
        Ok(out) => out,
        Err(e) => return Some(format!("{} did not run: {e}", validator.name)),
    };
    if out.status.success() {
        return None;
    }
    let text =
        String::from_utf8_lossy(&out.stdout).into_owned() + &String::from_utf8_lossy(&out.stderr);
    let dir = file
        .parent()
        .map(|d| format!("{}/", d.display()))
        .unwrap_or_default();
    let first = text
        .lines()
        .map(str::trim)
        // glslang names the file on a line of its own before its errors.
        .find(|l| !l.is_empty() && !l.ends_with(".frag"))
        .unwrap_or("no message");
    // Without the temporary directory, so that the table does not change from run to run.
    Some(format!("{}: {}", validator.name, first.replace(&dir, "")))
}

/// Whether a WGSL file is of wgpu's native target: it enables one of wgpu's extensions
/// (`enable wgpu_binding_array;`) or declares push constants (`var<immediate>`).
fn native_wgsl(file: &Path) -> bool {
    std::fs::read_to_string(file).is_ok_and(|t| {
        t.lines().any(|l| {
            let l = l.trim_start();
            (l.starts_with("enable") && l.contains("wgpu_")) || l.contains("var<immediate>")
        })
    })
}

/// Whether a validator's refusal says that the file is not for it (the module docs).
fn not_applicable(failure: &str) -> bool {
    (failure.starts_with("glslang -G") && failure.contains("'#error' : push constants"))
        || failure.contains("extension not supported: GL_EXT_texture_shadow_lod")
}

/// The WGSL validators that refuse `shader` as it was read (written back as WGSL): their
/// refusal of a pass is the shader's own, not the variant's.
pub fn original_fails(shader: &reproj_front::Shader) -> Vec<&'static str> {
    let Ok(text) = reproj_front::write_wgsl(&shader.module, &shader.info) else {
        return Vec::new();
    };
    let dir = tempfile::tempdir().unwrap();
    let file = dir.path().join("original.wgsl");
    std::fs::write(&file, text).unwrap();
    VALIDATORS
        .iter()
        .filter(|v| v.ext == "wgsl" && rejects(v, &file).is_some())
        .map(|v| v.name)
        .collect()
}

/// The files in `dir`, sorted.
fn files_in(dir: &Path) -> Vec<PathBuf> {
    let mut names: Vec<PathBuf> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .collect();
    names.sort();
    names
}

/// What writing `variant` in each language and validating every file gave: per language,
/// `"validates"` with the files and validators counted, a refusal of the writer (`"refused:
/// …"`: nothing written, by name), or the failures.
pub fn write_and_validate(variant: &Variant, original_fails: &[&str]) -> Value {
    let mut row = serde_json::Map::new();
    // WGSL is written with every language; each other language on its own, so that a writer's
    // refusal (a binding array in GLSL) leaves the others written.
    let langs: [(&str, Vec<OutputLang>); 3] = [
        ("wgsl", vec![]),
        ("spirv", vec![OutputLang::SpirV]),
        ("glsl", vec![OutputLang::Glsl]),
    ];
    for (name, langs) in langs {
        let dir = tempfile::tempdir().unwrap();
        if let Err(e) = write_variant_in(variant, dir.path(), &Outputs::langs(&langs)) {
            row.insert(name.into(), json!(format!("refused: {e}")));
            continue;
        }
        let ext = match name {
            "wgsl" => "wgsl",
            "spirv" => "spv",
            _ => "frag",
        };
        let mut failures = Vec::new();
        let mut checked = 0;
        let mut skipped = 0;
        for file in files_in(dir.path()) {
            if file.extension().is_none_or(|e| e != ext) {
                continue;
            }
            let native = ext == "wgsl" && native_wgsl(&file);
            for v in VALIDATORS.iter().filter(|v| v.ext == ext) {
                if v.tool == "tint" && (native || original_fails.contains(&v.name)) {
                    skipped += 1;
                    continue;
                }
                match rejects(v, &file) {
                    Some(f) if not_applicable(&f) => skipped += 1,
                    Some(f) => {
                        checked += 1;
                        let file = file.file_name().unwrap().to_string_lossy();
                        failures.push(format!("{file}: {f}"));
                    }
                    None => checked += 1,
                }
            }
        }
        row.insert(
            name.into(),
            if failures.is_empty() && skipped > 0 {
                json!(format!(
                    "validates ({checked} checks; {skipped} not applicable)"
                ))
            } else if failures.is_empty() {
                json!(format!("validates ({checked} checks)"))
            } else {
                json!(failures)
            },
        );
    }
    Value::Object(row)
}
