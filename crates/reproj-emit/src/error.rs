//! What can go wrong in `emit`: the profile (its fields, a shader changed since), the shader it
//! names, the variant written from it, and the files written.

use std::path::PathBuf;

/// What can go wrong in [`crate::emit()`] and in reading a profile.
#[derive(Debug, thiserror::Error)]
pub enum EmitError {
    #[error(transparent)]
    Front(#[from] reproj_front::FrontError),
    #[error(transparent)]
    Instance(#[from] reproj_instance::InstanceError),
    #[error("{0}")]
    Options(String),
    #[error("{path}: not a reproj profile: {message}")]
    BadProfile { path: PathBuf, message: String },
    #[error("{path}: the {what} changed since the profile was made; run `reproj analyze` again")]
    Stale { path: PathBuf, what: String },
    #[error(transparent)]
    Write(#[from] reproj_io::WriteError),
    #[error(transparent)]
    Read(#[from] reproj_io::ReadError),
    #[error("cannot write {path}: {source}")]
    Io {
        path: PathBuf,
        #[source]
        source: std::io::Error,
    },
}

impl EmitError {
    /// True when the error comes from the user's input rather than a bug or the machine.
    pub fn is_user_error(&self) -> bool {
        match self {
            EmitError::Front(e) => e.is_user_error(),
            EmitError::Instance(e) => e.is_user_error(),
            _ => true,
        }
    }

    /// The source diagnostic of a front-end error about a place in the shader.
    pub fn diagnostic(&self) -> Option<&reproj_front::SourceDiagnostic> {
        match self {
            EmitError::Front(e) => e.diagnostic(),
            EmitError::Instance(e) => e.diagnostic(),
            _ => None,
        }
    }
}
