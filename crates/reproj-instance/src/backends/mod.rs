//! The passes in other shading languages, through naga's backends.
//!
//! WGSL stays the source of truth (the manifest names the `.wgsl` files, the replay renders them);
//! `--lang` adds each pass in GLSL 4.50, HLSL (shader model 5.1), MSL 2.1 or SPIR-V beside it,
//! written from the same validated module. GLSL holds one entry point per file: the pass's
//! (entry point 0, the one the manifest names); the others hold every entry point. Every
//! resource's binding in each language is chosen here, explicitly, and listed in the manifest's
//! `languages` ([`bindings`]).
//!
//! naga's writers take no `override` constants: each module's overrides are first replaced by
//! their values ([`Outputs::overrides`], else their defaults) with naga's `process_overrides`.
//! What a writer cannot write (`texture_external` in GLSL and SPIR-V, binding arrays in GLSL) is
//! refused before it is called, with the variable's name. Push constants (naga's immediates: a
//! GLSL input's `layout(push_constant)` block, WGSL's `var<immediate>`) are listed in the manifest
//! ([`immediates`]): in HLSL the constant buffer `b0` of space [`IMMEDIATES_SPACE`]; in GLSL a
//! `layout(push_constant)` block for Vulkan and, in the same file, a std140 uniform block for
//! OpenGL (naga's writer patched for it: `vendor/naga/REPROJ-PATCH.md`).

use std::collections::BTreeMap;
use std::path::PathBuf;

use crate::{InstanceError, LanguageOutput, PassModule, pass_file};

pub mod bindings;
pub mod immediates;

pub use bindings::language_output;

/// A shading language the passes can be written in besides WGSL.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum OutputLang {
    Glsl,
    Hlsl,
    Msl,
    SpirV,
}

impl OutputLang {
    /// File extension of a pass in this language.
    pub fn extension(self) -> &'static str {
        match self {
            OutputLang::Glsl => "frag",
            OutputLang::Hlsl => "hlsl",
            OutputLang::Msl => "metal",
            OutputLang::SpirV => "spv",
        }
    }

    /// The language as `--lang` and the manifest's `languages[].lang` name it.
    pub fn key(self) -> &'static str {
        match self {
            OutputLang::Glsl => "glsl",
            OutputLang::Hlsl => "hlsl",
            OutputLang::Msl => "msl",
            OutputLang::SpirV => "spirv",
        }
    }

    /// The language's name in messages.
    pub fn name(self) -> &'static str {
        match self {
            OutputLang::Glsl => "GLSL",
            OutputLang::Hlsl => "HLSL",
            OutputLang::Msl => "MSL",
            OutputLang::SpirV => "SPIR-V",
        }
    }
}

/// The HLSL register space of the push constants (naga's immediates) of a GLSL input: `b0` there.
pub const IMMEDIATES_SPACE: u8 = 254;

/// Values of a shader's `override` constants, by name (or by `@id` number), for the passes written
/// in other languages; an override not named keeps its default.
pub type Overrides = BTreeMap<String, f64>;

/// What is written besides the WGSL: the languages, and the values of the `override` constants.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Outputs {
    pub langs: Vec<OutputLang>,
    pub overrides: Overrides,
}

impl Outputs {
    /// `langs`, every override at its default.
    pub fn langs(langs: &[OutputLang]) -> Outputs {
        Outputs {
            langs: langs.to_vec(),
            overrides: Overrides::new(),
        }
    }
}

/// Whether `module` declares the override `key` (its name, or its `@id` number).
fn declares(module: &naga::Module, key: &str) -> bool {
    let id = key.parse::<u16>().ok();
    module.overrides.iter().any(|(_, o)| match o.id {
        Some(n) if id == Some(n) => true,
        _ => o.name.as_deref() == Some(key),
    })
}

/// Refuses `overrides` naming a constant none of `modules` declares.
pub fn check_overrides<'a>(
    modules: impl IntoIterator<Item = &'a naga::Module> + Clone,
    overrides: &Overrides,
) -> Result<(), InstanceError> {
    for key in overrides.keys() {
        if !modules.clone().into_iter().any(|m| declares(m, key)) {
            let mut known: Vec<String> = modules
                .clone()
                .into_iter()
                .flat_map(|m| m.overrides.iter().filter_map(|(_, o)| o.name.clone()))
                .collect();
            known.sort();
            known.dedup();
            return Err(InstanceError::UnknownOverride {
                name: key.clone(),
                known,
            });
        }
    }
    Ok(())
}

/// Why `lang`'s writer cannot write `module`, before it is called: naga 30's GLSL and SPIR-V
/// writers panic on `texture_external`, and its GLSL writer on binding arrays (GLSL's
/// `sampler2D textures[4]`, split into arrays of textures and samplers).
pub fn unsupported_in(module: &naga::Module, lang: OutputLang) -> Option<String> {
    module.global_variables.iter().find_map(|(_, var)| {
        let name = var.name.as_deref().unwrap_or("a global");
        match module.types[var.ty].inner {
            naga::TypeInner::Image {
                class: naga::ImageClass::External,
                ..
            } if matches!(lang, OutputLang::Glsl | OutputLang::SpirV) => Some(format!(
                "`{name}` is a texture_external, which the {} output cannot hold (naga's writer has no external textures); write this shader in HLSL or MSL, or bind a texture_2d<f32>",
                lang.name()
            )),
            naga::TypeInner::BindingArray { .. } if lang == OutputLang::Glsl => Some(format!(
                "`{name}` is a binding array, which naga's GLSL writer cannot write; write this shader in HLSL, MSL or SPIR-V"
            )),
            _ => None,
        }
    })
    .or_else(|| match lang {
        OutputLang::Glsl => immediates::glsl_refusal(module),
        _ => None,
    })
}

/// File name of `pass` in `lang`: the WGSL file's name with the language's extension.
pub fn pass_file_in(pass: &PassModule, lang: OutputLang) -> String {
    PathBuf::from(pass_file(pass.kind))
        .with_extension(lang.extension())
        .display()
        .to_string()
}

/// `pass` written in `lang` with the bindings of `table` ([`language_output`] of all the passes,
/// for `lang`), after validating its module again. naga's writers can panic on
/// input they do not support (`texture_external` in GLSL or SPIR-V, in naga 30): a panic there is
/// caught and becomes [`InstanceError::Backend`] (a user error, exit 2) instead of ending the
/// process — a last line of defence; refusing known-unsupported input first is better.
pub fn write_pass(
    pass: &PassModule,
    lang: OutputLang,
    table: &LanguageOutput,
    overrides: &Overrides,
) -> Result<Vec<u8>, InstanceError> {
    guarded(|| write_pass_unguarded(pass, lang, table, overrides)).unwrap_or_else(|message| {
        Err(InstanceError::Backend {
            file: pass_file_in(pass, lang),
            what: format!(
                "naga's {} writer failed on this pass ({message}); the {} output of this shader is not supported",
                lang.name(),
                lang.name()
            ),
        })
    })
}

/// Run `f`, turning a panic into its message. The panic hook is silenced meanwhile, so nothing
/// is printed for a caught panic.
fn guarded<T>(f: impl FnOnce() -> T) -> Result<T, String> {
    let hook = std::panic::take_hook();
    std::panic::set_hook(Box::new(|_| {}));
    let result = std::panic::catch_unwind(std::panic::AssertUnwindSafe(f));
    std::panic::set_hook(hook);
    result.map_err(|payload| {
        payload
            .downcast_ref::<&str>()
            .map(|s| s.to_string())
            .or_else(|| payload.downcast_ref::<String>().cloned())
            .unwrap_or_else(|| "a panic".into())
    })
}

fn write_pass_unguarded(
    pass: &PassModule,
    lang: OutputLang,
    table: &LanguageOutput,
    overrides: &Overrides,
) -> Result<Vec<u8>, InstanceError> {
    let fail = |what: String| InstanceError::Backend {
        file: pass_file_in(pass, lang),
        what,
    };
    if let Some(what) = unsupported_in(&pass.module, lang) {
        return Err(fail(what));
    }
    let info = reproj_front::validator()
        .validate(&pass.module)
        .map_err(|e| fail(format!("the module does not validate: {e}")))?;
    // The overrides this pass declares, by name or id, with their values.
    let constants: naga::back::PipelineConstants = overrides
        .iter()
        .filter(|(key, _)| declares(&pass.module, key))
        .map(|(key, &value)| (key.clone(), value))
        .collect();
    let (module, info) =
        naga::back::pipeline_constants::process_overrides(&pass.module, &info, None, &constants)
            .map_err(|e| fail(override_message(&pass.module, &e)))?;
    let (module, info) = (module.as_ref(), info.as_ref());
    let entry = module
        .entry_points
        .first()
        .ok_or_else(|| fail("the pass has no entry point".into()))?;
    match lang {
        OutputLang::Glsl => {
            use naga::back::glsl;
            let mut text = String::new();
            let options = glsl::Options {
                version: glsl::Version::Desktop(450),
                // Push constants as a block Vulkan GLSL accepts (a reproj patch of naga).
                writer_flags: glsl::WriterFlags::IMMEDIATES_AS_BLOCK,
                binding_map: bindings::glsl_map(table),
                ..Default::default()
            };
            let pipeline = glsl::PipelineOptions {
                shader_stage: entry.stage,
                entry_point: entry.name.clone(),
                multiview: None,
            };
            glsl::Writer::new(
                &mut text,
                module,
                info,
                &options,
                &pipeline,
                naga::proc::BoundsCheckPolicies::default(),
            )
            .and_then(|mut w| w.write())
            .map_err(|e| fail(e.to_string()))?;
            Ok(text.into_bytes())
        }
        OutputLang::Hlsl => {
            use naga::back::hlsl;
            let mut text = String::new();
            // A GLSL input's push constants (naga's immediates) need a register: `b0` of
            // space 254, out of the way of the bind groups' spaces and naga's sampler heap (255).
            let (binding_map, sampler_buffer_binding_map) = bindings::hlsl_maps(table);
            let options = hlsl::Options {
                immediates_target: Some(hlsl::BindTarget {
                    space: IMMEDIATES_SPACE,
                    ..Default::default()
                }),
                binding_map,
                sampler_buffer_binding_map,
                fake_missing_bindings: false,
                ..Default::default()
            };
            let pipeline = hlsl::PipelineOptions::default();
            hlsl::Writer::new(&mut text, &options, &pipeline)
                .write(module, info, None)
                .map_err(|e| fail(e.to_string()))?;
            Ok(text.into_bytes())
        }
        OutputLang::Msl => {
            use naga::back::msl;
            let options = msl::Options {
                lang_version: (2, 1),
                per_entry_point_map: bindings::msl_map(table, module),
                fake_missing_bindings: false,
                ..Default::default()
            };
            let (text, _) =
                msl::write_string(module, info, &options, &msl::PipelineOptions::default())
                    .map_err(|e| fail(e.to_string()))?;
            Ok(text.into_bytes())
        }
        OutputLang::SpirV => {
            use naga::back::spv;
            let words = spv::write_vec(module, info, &spv::Options::default(), None)
                .map_err(|e| fail(e.to_string()))?;
            Ok(words.iter().flat_map(|w| w.to_le_bytes()).collect())
        }
    }
}

/// naga's override error, in words a shader author acts on (an override naga names by its id is
/// named by its name too).
fn override_message(
    module: &naga::Module,
    e: &naga::back::pipeline_constants::PipelineConstantError,
) -> String {
    use naga::back::pipeline_constants::PipelineConstantError as E;
    match e {
        E::MissingValue(key) => {
            let id = key.parse::<u16>().ok();
            let named = module
                .overrides
                .iter()
                .find(|(_, o)| id.is_some() && o.id == id)
                .and_then(|(_, o)| o.name.clone())
                .map_or_else(
                    || format!("`{key}`"),
                    |name| format!("`{name}` (@id({key}))"),
                );
            format!("the override {named} has no default and no value was given for it")
        }
        E::SrcNeedsToBeFinite | E::DstRangeTooSmall => {
            format!("an override value does not fit its type ({e})")
        }
        _ => format!("cannot resolve the override constants: {e}"),
    }
}
