//! The front end in one call: read a shader file, normalize its fragment entry point, list its
//! nodes. Every command and stage that starts from a shader file goes through [`load`], or
//! through [`load_file_with`] where it needs the parsed shader only.

use std::path::Path;

use crate::input::ShaderInput;
use crate::nodes::{CullReason, NodeTable, enumerate};
use crate::normalize::{NormalizeOptions, Normalized, normalize};
use crate::shader::{FrontError, Lang, Shader};
use crate::unroll::UnrollOptions;

/// Options of [`load`].
#[derive(Debug, Clone, Default)]
pub struct LoadOptions {
    /// The input language; `None` chooses by the file's extension (WGSL for an unknown one).
    pub lang: Option<Lang>,
    /// Loops to unroll before the nodes are enumerated.
    pub unroll: UnrollOptions,
    /// Shader defs, import paths and include folders ([`ShaderInput`]).
    pub input: ShaderInput,
}

/// Read a shader file from disk in the language its extension names (WGSL for any other
/// extension), then parse and validate it.
pub fn load_file(path: &Path) -> Result<Shader, FrontError> {
    load_file_as(path, None)
}

/// Read a shader file in `lang`, or in the language its extension names when `None` (WGSL for any
/// other extension), then parse and validate it.
pub fn load_file_as(path: &Path, lang: Option<Lang>) -> Result<Shader, FrontError> {
    load_file_with(path, lang, &ShaderInput::default())
}

/// [`load_file_as`], read as `input` says: shader defs, import paths, include folders. A def
/// that the shader never reads is a warning in [`Shader::warnings`]. A shader whose arrays would
/// take more GPU memory than the budget is refused here, before any command renders it
/// ([`crate::memory`]).
pub fn load_file_with(
    path: &Path,
    lang: Option<Lang>,
    input: &ShaderInput,
) -> Result<Shader, FrontError> {
    let shader = read_file_with(path, lang, input)?;
    crate::memory::check_shader(path, &shader)?;
    Ok(shader)
}

fn read_file_with(
    path: &Path,
    lang: Option<Lang>,
    input: &ShaderInput,
) -> Result<Shader, FrontError> {
    use reproj_io::{InputKind, read_input, read_input_string};
    crate::parse::refuse_other_stage(path)?;
    let lang = lang.or_else(|| Lang::from_path(path)).unwrap_or(Lang::Wgsl);
    let no_reader = std::collections::BTreeSet::new();
    match lang {
        Lang::SpirV => {
            let mut shader =
                crate::parse::parse_spirv(path, &read_input(path, InputKind::Shader)?)?;
            shader.warnings = crate::input::unread_defs(path, input, &no_reader);
            Ok(shader)
        }
        Lang::Glsl => {
            let source = read_input_string(path, InputKind::Shader)?;
            crate::parse::parse_glsl_with(path, source, input)
        }
        Lang::Wgsl => {
            let source = read_input_string(path, InputKind::Shader)?;
            let source = crate::enables::enable_binding_arrays(&source).into_owned();
            crate::depth::check_chains(path, &source)?;
            if crate::parse::needs_composing(&source) {
                crate::parse::parse_composed_with(path, &source, input)
            } else {
                let mut shader = crate::parse::parse_text(path, Lang::Wgsl, source)?;
                (shader.warnings).extend(crate::input::unread_defs(path, input, &no_reader));
                Ok(shader)
            }
        }
    }
}

/// A loaded shader: the parsed module, its normalized fragment entry point and its node table.
#[derive(Debug, Clone)]
pub struct Loaded {
    pub shader: Shader,
    pub norm: Normalized,
    pub table: NodeTable,
}

/// Read `path`, normalize the fragment entry point `entry` (`None`: the only one) and enumerate
/// its nodes.
pub fn load(path: &Path, entry: Option<&str>, options: &LoadOptions) -> Result<Loaded, FrontError> {
    let shader = load_file_with(path, options.lang, &options.input)?;
    Loaded::with_unroll(shader, entry, options.unroll)
}

impl Loaded {
    /// Normalize and enumerate an already parsed shader (see [`load`]).
    pub fn new(shader: Shader, entry: Option<&str>) -> Result<Loaded, FrontError> {
        Loaded::with_unroll(shader, entry, UnrollOptions::OFF)
    }

    /// [`Loaded::new`], unrolling loops as `unroll` says before enumerating.
    pub fn with_unroll(
        shader: Shader,
        entry: Option<&str>,
        unroll: UnrollOptions,
    ) -> Result<Loaded, FrontError> {
        let norm = normalize(
            &shader,
            &NormalizeOptions {
                entry: entry.map(str::to_owned),
                unroll,
            },
        )?;
        let table = enumerate(&shader, &norm);
        Ok(Loaded {
            shader,
            norm,
            table,
        })
    }
}

/// Why a shader has no cacheable node: the culled nodes counted per reason (in [`CullReason`]
/// order, reasons with no node left out) and a hint for the most common one.
#[derive(Debug, Clone, PartialEq)]
pub struct CullSummary {
    pub counts: Vec<(CullReason, usize)>,
    pub hint: &'static str,
}

impl NodeTable {
    /// The culled nodes counted per reason, with a hint for the commonest reason.
    pub fn cull_summary(&self) -> CullSummary {
        let counts: Vec<(CullReason, usize)> = CullReason::ALL
            .iter()
            .map(|&r| (r, self.nodes.iter().filter(|n| n.reason == Some(r)).count()))
            .filter(|&(_, n)| n > 0)
            .collect();
        let top = counts
            .iter()
            .max_by_key(|&&(r, n)| (n, std::cmp::Reverse(r as u8)));
        CullSummary {
            hint: top.map_or("the shader has no float-valued expression", |&(r, _)| {
                r.hint()
            }),
            counts,
        }
    }
}
