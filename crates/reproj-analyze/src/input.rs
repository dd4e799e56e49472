//! What an analysis works on ([`AnalyzeInput`]) and reports its progress to ([`Progress`]): the
//! types the replayer and the set search share with [`crate::analyze()`], kept below all three so
//! that neither reaches up into `analyze/`.

use std::path::Path;

use reproj_front::{NodeTable, Normalized, Shader};
use reproj_scene::Session;

/// Progress of a long analysis, reported by [`crate::analyze()`] (the CLI draws a bar).
pub trait Progress {
    /// `total` replays will follow (the reference included).
    fn start(&self, total: u64);
    /// One replay is done; `what` says which.
    fn step(&self, what: &str);
    /// A line worth showing (a node set aside, ...).
    fn note(&self, line: &str);
    /// `more` replays will follow beyond those announced by `start` (the set search decides
    /// how many it replays as it goes).
    fn extend(&self, more: u64) {
        let _ = more;
    }
    fn finish(&self);
}

/// A [`Progress`] that shows nothing.
#[derive(Debug, Default)]
pub struct Silent;

impl Progress for Silent {
    fn start(&self, _: u64) {}
    fn step(&self, _: &str) {}
    fn note(&self, _: &str) {}
    fn finish(&self) {}
}

/// What [`crate::analyze()`] works on.
#[derive(Debug)]
pub struct AnalyzeInput<'a> {
    pub shader: &'a Shader,
    pub norm: &'a Normalized,
    pub table: &'a NodeTable,
    /// Session file path (recorded in the profile) and its bytes (hashed).
    pub session_path: &'a Path,
    pub session_bytes: &'a [u8],
    pub session: &'a Session,
}
