//! [`RuntimeError`]: what can go wrong loading a variant, building it on a device, or recording a
//! frame. Manifest errors name the file and the field (a JSON path such as `passes[1].depth`).

use std::path::PathBuf;

/// An error of [`crate::Variant::load`], [`crate::Variant::create`] or
/// [`crate::VariantResources::record`].
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum RuntimeError {
    /// A file of the variant (its manifest or a pass) was not read: missing, not a regular
    /// file, past its [`crate::ReadLimits`] limit, or not text.
    #[error(transparent)]
    File(#[from] crate::FileError),
    /// `manifest.json` is not JSON, or a field does not have the schema's type.
    #[error("{path}: `{field}`: {message}")]
    Parse {
        path: PathBuf,
        /// JSON path of the failing field (`.` where the document itself is at fault).
        field: String,
        message: String,
    },
    /// The file is not a reproj variant manifest (`schema`).
    #[error("{path}: `schema` is {found}, expected \"{expected}\": not a reproj variant manifest", expected = crate::manifest::SCHEMA)]
    Schema { path: PathBuf, found: String },
    /// The manifest's `version` is one this runtime does not read.
    #[error(
        "{path}: manifest version {found} is not supported: this runtime reads versions {oldest} to {newest} (write the variant again, or update reproj-runtime)",
        oldest = crate::manifest::OLDEST_VERSION,
        newest = crate::manifest::VERSION
    )]
    Version { path: PathBuf, found: String },
    /// A field holds a value the runtime cannot run (an unknown format, a role no texture plays,
    /// a parameter outside the params buffer...).
    #[error("{path}: `{field}`: {message}")]
    Manifest {
        path: PathBuf,
        field: String,
        message: String,
    },
    /// The device lacks features the manifest's `required_features` lists.
    #[error(
        "the device lacks {missing} (the manifest's `required_features`): request them when opening it"
    )]
    MissingFeatures { missing: String },
    /// What the application passed does not fit the variant (a bind group index the variant owns,
    /// a target of the wrong format or size...). `what` names the argument.
    #[error("{what}: {message}")]
    Usage { what: String, message: String },
    /// wgpu refused an object built from the manifest (a pass that does not compile, a pipeline
    /// whose layout does not match the shader). `what` names the pass.
    #[error("{what}: {message}")]
    Gpu { what: String, message: String },
}

impl RuntimeError {
    pub(crate) fn usage(what: impl Into<String>, message: impl Into<String>) -> RuntimeError {
        RuntimeError::Usage {
            what: what.into(),
            message: message.into(),
        }
    }
}
