//! reproj's measuring stage: `analyze` replays every candidate node of a shader over a session,
//! races its strategies, fits the models and writes a profile ([`analyze()`]); `verify` re-renders
//! what `emit` (reproj-emit, GPU-free) chose and times it against the original ([`verify()`],
//! [`runoff()`]); `merge` joins the shards of a split analysis. The CLI's `analyze`, `merge` and
//! `emit --verify` are thin wrappers over them.

pub mod analyze;
mod blocks;
mod filters;
mod input;
pub mod journal;
pub mod merge;
mod options;
mod periods;
pub mod prune;
mod replayer;
pub mod sets;
mod strategies;
pub mod verify;

use std::path::PathBuf;

pub use analyze::{
    AnalyzeInput, AnalyzeOptions, DEFAULT_PERCEPTUAL_STRIDE, DEFAULT_RACE, Extension,
    ExtensionStop, Progress, Sampling, Silent, analyze, next_extension,
};
pub use journal::JournalOptions;
pub use merge::merge;
pub use prune::{PruneOptions, profile_candidates};
pub use sets::{SetCandidate, SetContext, SetSearchOptions, search_sets};
pub use verify::{runoff, verify};

/// What can go wrong in `analyze`, `merge` or `verify`.
#[derive(Debug, thiserror::Error)]
pub enum AnalyzeError {
    #[error(transparent)]
    Front(#[from] reproj_front::FrontError),
    #[error(transparent)]
    Instance(#[from] reproj_instance::InstanceError),
    /// A replay failed.
    #[error(transparent)]
    Replay(#[from] reproj_replay::ReplayError),
    #[error("{0}")]
    Options(String),
    /// Reading the profile or writing the report again (`verify`).
    #[error(transparent)]
    Emit(#[from] reproj_emit::EmitError),
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

impl AnalyzeError {
    /// True when the error comes from the user's input rather than a bug or the machine.
    pub fn is_user_error(&self) -> bool {
        match self {
            AnalyzeError::Front(e) => e.is_user_error(),
            AnalyzeError::Instance(e) => e.is_user_error(),
            AnalyzeError::Replay(e) => e.is_user_error(),
            AnalyzeError::Emit(e) => e.is_user_error(),
            _ => true,
        }
    }

    /// The source diagnostic of a front-end error about a place in the shader.
    pub fn diagnostic(&self) -> Option<&reproj_front::SourceDiagnostic> {
        match self {
            AnalyzeError::Front(e) => e.diagnostic(),
            AnalyzeError::Instance(e) => e.diagnostic(),
            AnalyzeError::Emit(e) => e.diagnostic(),
            _ => None,
        }
    }
}
