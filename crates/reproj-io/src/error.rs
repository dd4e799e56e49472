//! What a write that did not happen says: shared by the atomic writer and the cleanup that
//! removes partial output (below both, so neither imports the other for it).

use std::path::PathBuf;

/// A write that did not happen; the previous file or directory is untouched.
#[derive(Debug, thiserror::Error)]
pub enum WriteError {
    #[error("cannot write {path}: {source}")]
    Io {
        path: PathBuf,
        #[source]
        source: std::io::Error,
    },
    /// The output directory holds something the command did not write; replacing it would lose it.
    #[error(
        "refusing to replace {path}: {why}; reproj replaces its output directory whole, so choose a new directory or one reproj wrote"
    )]
    Refused { path: PathBuf, why: String },
    /// Another reproj process is writing this output.
    #[error(
        "another reproj ({holder}) is writing {path} (lock {lock}); wait for it to finish or stop it (a lock whose process is gone is taken over)"
    )]
    Locked {
        path: PathBuf,
        lock: PathBuf,
        /// `pid N`, with `on host H` when the lock was written on another host.
        holder: String,
    },
    /// The process is being interrupted (SIGINT/SIGTERM): its partial output was removed, and
    /// nothing more is created.
    #[error("not writing {path}: interrupted, partial output removed")]
    Interrupted { path: PathBuf },
    /// The output file exists and is not reproj's, or its place cannot take a file.
    #[error("refusing to write {path}: {why}")]
    NotOurs { path: PathBuf, why: String },
}
