//! What the front end reads a shader into, and what can go wrong: the [`Shader`] (module, info
//! and the text its spans point into), its [`Lang`], [`FrontError`] and the one [`validator`].
//! Below every pass that reads a shader, so each imports these without importing the parser.

use std::path::{Path, PathBuf};

use naga::valid::{Capabilities, ModuleInfo, ValidationFlags, Validator};

use crate::diagnostic::SourceDiagnostic;
use crate::directives::{HiddenEntries, HiddenEntry};
use crate::input::InputWarning;

/// The language of a shader file.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Lang {
    Wgsl,
    /// GLSL 4.50 for Vulkan, fragment stage (compiled by glslang).
    Glsl,
    /// A SPIR-V binary.
    SpirV,
}

impl Lang {
    /// The language a file's extension names: `.wgsl`, `.glsl`/`.frag`, `.spv`; `None` for any
    /// other extension.
    pub fn from_path(path: &Path) -> Option<Lang> {
        match path.extension()?.to_str()? {
            "wgsl" => Some(Lang::Wgsl),
            "glsl" | "frag" => Some(Lang::Glsl),
            "spv" => Some(Lang::SpirV),
            _ => None,
        }
    }

    pub fn as_str(self) -> &'static str {
        match self {
            Lang::Wgsl => "wgsl",
            Lang::Glsl => "glsl",
            Lang::SpirV => "spv",
        }
    }
}

/// A parsed and validated module with its source text, kept together so that every later
/// diagnostic can point into the text.
#[derive(Debug, Clone)]
pub struct Shader {
    /// Path used in diagnostics (`file:line:col`).
    pub path: PathBuf,
    /// The language the file was written in.
    pub lang: Lang,
    /// The text spans point into: the file itself for WGSL and GLSL, the WGSL naga writes for a
    /// SPIR-V module.
    pub source: String,
    pub module: naga::Module,
    pub info: ModuleInfo,
    /// The GLSL combined image samplers split into an image and a sampler, with the binding each
    /// half has in `module` (empty for other languages).
    pub split_samplers: Vec<SplitSampler>,
    /// What reading it warned of (a shader def nobody reads), for the CLI to print.
    pub warnings: Vec<InputWarning>,
    /// The `@fragment` entry points of the file that its preprocessor left out under the defs
    /// given, named when the entry point asked for is missing.
    pub hidden_entries: Vec<HiddenEntry>,
    /// For a GLSL shader, whether `source` and `module` are already its WGSL form
    /// ([`Shader::to_wgsl`]): spans then point into that WGSL, `to_wgsl` returns it as it is, and
    /// its IR hash is that of the GLSL shader it came from (`source` is the WGSL written of it).
    pub wgsl_form: bool,
    /// For a WGSL shader, whether reading it filled in what its text leaves to the host or to an
    /// older naga (a resource's binding, an integer varying's `flat`: `fill_in`): `module` then
    /// says more than `source`, and [`Shader::to_wgsl`] writes the module's WGSL for a device.
    pub filled_in: bool,
}

/// Everything that can go wrong in the front end. Each variant renders as one clear message; the
/// parse and validation variants carry naga's full diagnostic (file:line and a caret).
#[derive(Debug, thiserror::Error)]
pub enum FrontError {
    #[error("cannot read {path}: {source}")]
    Io {
        path: PathBuf,
        #[source]
        source: std::io::Error,
    },
    /// Not a regular file, too large or not text ([`reproj_io::read_input`]).
    #[error(transparent)]
    Input(#[from] reproj_io::InputError),
    /// A GLSL file whose extension names another stage than the fragment one (`.vert`, `.comp`...).
    #[error(
        "{path}: a `.{ext}` file is a GLSL {stage} shader; reproj optimizes fragment shaders (`.frag`, `.glsl`, `.wgsl`, `.spv`)"
    )]
    NotFragmentStage {
        path: PathBuf,
        ext: String,
        stage: &'static str,
    },
    /// The text does not parse. Kept as data: the CLI renders it with the source line and a caret.
    #[error("{0}")]
    Parse(SourceDiagnostic),
    /// The module parses but naga's validator rejects it.
    #[error("{0}")]
    Validation(SourceDiagnostic),
    #[error("{path}: the module has no @fragment entry point{hidden}")]
    NoFragmentEntry {
        path: PathBuf,
        /// The ones the preprocessor left out, and the defs that would let them in.
        hidden: HiddenEntries,
    },
    #[error("{path}: the module has several @fragment entry points ({}); choose one with --entry", names.join(", "))]
    AmbiguousEntry { path: PathBuf, names: Vec<String> },
    #[error("{path}: no @fragment entry point named `{name}` (fragment entry points: {}){hidden}", available.join(", "))]
    UnknownEntry {
        path: PathBuf,
        name: String,
        available: Vec<String>,
        /// The ones the preprocessor left out (`name` among them when it is), and the defs that
        /// would let them in.
        hidden: HiddenEntries,
    },
    /// Private, function or workgroup arrays over the GPU memory budget ([`crate::memory`]).
    #[error(transparent)]
    Memory(#[from] Box<crate::memory::OverBudget>),
    /// A construct reproj does not handle, at its place in the source ([`Shader::unsupported`]).
    #[error("{0}")]
    Unsupported(SourceDiagnostic),
    /// An unsupported construct inside the IR, before it is given a file location.
    #[error("unsupported: {what}")]
    UnsupportedAt { span: naga::Span, what: String },
    /// A bug in reproj: an invariant did not hold.
    #[error("internal error: {what}")]
    Internal { what: String },
}

impl FrontError {
    /// True when the error comes from the user's input (exit code 2), false for a bug in reproj.
    pub fn is_user_error(&self) -> bool {
        !matches!(self, FrontError::Internal { .. })
    }

    /// The source diagnostic, for errors about a place in the shader (rendered by the CLI).
    pub fn diagnostic(&self) -> Option<&SourceDiagnostic> {
        match self {
            FrontError::Parse(d) | FrontError::Validation(d) | FrontError::Unsupported(d) => {
                Some(d)
            }
            _ => None,
        }
    }
}

/// Validator used everywhere in reproj: every check on, every capability allowed.
pub fn validator() -> Validator {
    Validator::new(ValidationFlags::all(), Capabilities::all())
}

/// One combined image sampler of the GLSL shader, as the SPIR-V that reproj reads binds it.
#[derive(Debug, Clone, PartialEq, Eq, serde::Serialize)]
pub struct SplitSampler {
    /// The GLSL name (`albedo`); the image keeps it, the sampler is `NAME_sampler`.
    pub name: String,
    pub group: u32,
    /// The image's binding: the combined sampler's own.
    pub image_binding: u32,
    /// The sampler's binding: the next one the group leaves free.
    pub sampler_binding: u32,
}
