//! reproj's last two stages as a library: `analyze` (replay, measure, fit: a profile) and `emit`
//! (select under an error budget, write the passes). The CLI's `analyze` and `emit` commands are
//! thin wrappers over [`analyze()`] and [`emit()`].

// Feature `gpu` (on by default): what replays and times (analyze, its journal and set search,
// merge's refit, verify). Without it the crate is `emit`, `motion` and `prune`: GPU-free.
#[cfg(feature = "gpu")]
pub mod analyze;
#[cfg(feature = "gpu")]
mod blocks;
pub mod emit;
#[cfg(feature = "gpu")]
mod filters;
#[cfg(feature = "gpu")]
mod input;
#[cfg(feature = "gpu")]
pub mod journal;
#[cfg(feature = "gpu")]
pub mod merge;
pub mod motion;
#[cfg(feature = "gpu")]
mod options;
#[cfg(feature = "gpu")]
mod periods;
pub mod prune;
#[cfg(feature = "gpu")]
mod replayer;
#[cfg(feature = "gpu")]
pub mod sets;
#[cfg(feature = "gpu")]
mod strategies;
#[cfg(feature = "gpu")]
pub mod verify;

use std::path::PathBuf;

#[cfg(feature = "gpu")]
pub use analyze::{
    AnalyzeInput, AnalyzeOptions, DEFAULT_PERCEPTUAL_STRIDE, DEFAULT_RACE, Extension,
    ExtensionStop, Progress, Sampling, Silent, analyze, next_extension,
};
pub use emit::{
    Contender, EMIT_REPORT_SCHEMA, EMIT_REPORT_VERSION, EmitOptions, EmitReport, Runoff,
    RunoffEntry, contenders, emit, latest_profile, load_profile, profile_shader_input,
};
#[cfg(feature = "gpu")]
pub use journal::JournalOptions;
#[cfg(feature = "gpu")]
pub use merge::merge;
pub use prune::{PruneOptions, profile_candidates};
/// The error budget and the default refresh periods, as the CLI checks them at its edge.
pub use reproj_select::{Budget, DELTA_N_RANGE, EXTENDED_MAX_DELTA_N};
#[cfg(feature = "gpu")]
pub use sets::{SetCandidate, SetContext, SetSearchOptions, search_sets};
#[cfg(feature = "gpu")]
pub use verify::{runoff, verify};

/// What can go wrong in `analyze` or `emit`.
#[derive(Debug, thiserror::Error)]
pub enum AnalyzeError {
    #[error(transparent)]
    Front(#[from] reproj_front::FrontError),
    #[error(transparent)]
    Instance(#[from] reproj_instance::InstanceError),
    /// A replay failed (the `gpu` feature: only it renders).
    #[cfg(feature = "gpu")]
    #[error(transparent)]
    Replay(#[from] reproj_replay::ReplayError),
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

impl AnalyzeError {
    /// True when the error comes from the user's input rather than a bug or the machine.
    pub fn is_user_error(&self) -> bool {
        match self {
            AnalyzeError::Front(e) => e.is_user_error(),
            AnalyzeError::Instance(e) => e.is_user_error(),
            #[cfg(feature = "gpu")]
            AnalyzeError::Replay(e) => e.is_user_error(),
            _ => true,
        }
    }

    /// The source diagnostic of a front-end error about a place in the shader.
    pub fn diagnostic(&self) -> Option<&reproj_front::SourceDiagnostic> {
        match self {
            AnalyzeError::Front(e) => e.diagnostic(),
            AnalyzeError::Instance(e) => e.diagnostic(),
            _ => None,
        }
    }
}
