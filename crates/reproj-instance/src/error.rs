//! What can go wrong while instancing, and which of it is the user's to fix.

use super::*;

/// What can go wrong while instancing.
#[derive(Debug, thiserror::Error)]
pub enum InstanceError {
    #[error(
        "no node {id}: {shader} has node ids {min}..={max} (see `reproj nodes {shader} --all`)"
    )]
    UnknownNode {
        id: u32,
        shader: String,
        min: u32,
        max: u32,
    },
    #[error("node {id} (`{text}`, line {line}) cannot be cached: it is culled as {reason}")]
    Culled {
        id: u32,
        text: String,
        line: u32,
        reason: reproj_front::CullReason,
    },
    #[error(
        "bind group {group} cannot hold the variant's bindings: a group must be below {MAX_BIND_GROUPS}, with binding numbers to spare below 1000 past the shader's own (the shader uses groups {used:?})"
    )]
    GroupTaken { group: u32, used: Vec<u32> },
    #[error("the block size k must be 1 or even (to align with 2×2 quads), got {0}")]
    BadBlock(u32),
    #[error("the refresh period must be at least 1")]
    BadDeltaN,
    #[error(
        "nodes {ids} hold {components} floats together: a payload holds 4 (cache nodes of fewer components together)"
    )]
    PayloadTooWide { ids: String, components: u32 },
    #[error("node {id} is listed twice")]
    RepeatedNode { id: String },
    #[error("the {format} cache holds {channels} float(s) but node {id} has {components}")]
    FormatTooNarrow {
        format: &'static str,
        channels: u32,
        id: String,
        components: u32,
    },
    #[error(transparent)]
    Write(#[from] reproj_io::WriteError),
    /// A naga backend could not write a pass in another language.
    #[error("cannot write {file}: {what}")]
    Backend { file: String, what: String },
    /// A value was given for an `override` constant the shader does not declare.
    #[error("the shader has no override constant `{name}` (its overrides: {})", if known.is_empty() { "none".to_owned() } else { known.join(", ") })]
    UnknownOverride { name: String, known: Vec<String> },
    #[error(transparent)]
    Front(#[from] reproj_front::FrontError),
    /// A node cannot be replaced by a constant (code simplification).
    #[error("node {id} (`{text}`) cannot be replaced by a constant: {why}")]
    NotReplaceable { id: u32, text: String, why: String },
    /// A bug in reproj: a simplified shader did not validate or round-trip.
    #[error("internal error in a simplified shader: {what}")]
    InternalSimplified { what: String },
    /// A bug in reproj: a generated module did not validate or round-trip.
    #[error("internal error in the {pass:?} pass: {what}")]
    Internal { pass: PassKind, what: String },
}

impl InstanceError {
    /// True when the error comes from the user's input or the machine (exit code 2), false for a
    /// bug in reproj.
    pub fn is_user_error(&self) -> bool {
        match self {
            InstanceError::Internal { .. } | InstanceError::InternalSimplified { .. } => false,
            InstanceError::Front(f) => f.is_user_error(),
            _ => true,
        }
    }

    /// The source diagnostic of a front-end error about a place in the shader.
    pub fn diagnostic(&self) -> Option<&reproj_front::SourceDiagnostic> {
        match self {
            InstanceError::Front(f) => f.diagnostic(),
            _ => None,
        }
    }
}
