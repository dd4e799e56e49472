//! [`ReplayError`]: everything that can go wrong replaying a session, one clear message each; the
//! scene's and the metrics' errors convert into it with their messages unchanged. The bottom of
//! the crate.

use reproj_metrics::output::OutputError;
use reproj_scene::SessionError;
use reproj_scene::reflect::Unsupported;

use std::path::PathBuf;

/// Everything that can go wrong replaying a session. Each variant renders as one clear message.
#[derive(Debug, thiserror::Error)]
pub enum ReplayError {
    #[error(
        "no GPU adapter found for backends {backends} (on a machine without a GPU driver install Mesa's software Vulkan driver: apt-get install mesa-vulkan-drivers)"
    )]
    NoAdapter { backends: String },
    /// A backend name that is not a wgpu backend, or one this build does not have.
    #[error(
        "{origin}: backend `{name}` {reason} (this reproj has: {compiled}; accepted names: {accepted})"
    )]
    Backend {
        /// Where the list came from: `--backend` or `WGPU_BACKEND`.
        origin: String,
        name: String,
        reason: String,
        compiled: String,
        accepted: String,
    },
    #[error("cannot open the GPU device on {adapter}: {message}")]
    Device { adapter: String, message: String },
    #[error(transparent)]
    Session(#[from] SessionError),
    /// The shader declares resources the session does not provide.
    #[error("the session provides no {what}: {}", names.join(", "))]
    MissingResources { what: String, names: Vec<String> },
    #[error("unsupported: {what}")]
    Unsupported { what: String },
    /// A texture or mesh of the session could not be built (file missing, bad image...).
    #[error("{message}")]
    Asset { message: String },
    /// wgpu rejected a shader module or pipeline.
    #[error("{what}: {message}")]
    Gpu { what: String, message: String },
    #[error(
        "the reference has {reference} (frames, width, height) but the session needs {session}"
    )]
    ReferenceMismatch { reference: String, session: String },
    #[error("variant: {message}")]
    Variant { message: String },
    /// A variant's pass whose arrays take more GPU memory than the budget
    /// ([`reproj_front::memory`]), refused when it is read.
    #[error(transparent)]
    Memory(#[from] Box<reproj_front::memory::OverBudget>),
    #[error(transparent)]
    Write(#[from] reproj_io::WriteError),
    #[error(transparent)]
    Read(#[from] reproj_io::ReadError),
    #[error("cannot encode {path}: {message}")]
    Image { path: PathBuf, message: String },
    /// The object covers no pixel in any frame: every error would read 0 (PSNR 100) and mean
    /// nothing.
    #[error(
        "{session}: the object covers no pixel in any of its {frames} frames (a camera looking away or whose `up` is parallel to its view, a zero scale, or the object behind the far plane); there is nothing to measure"
    )]
    NothingCovered { session: String, frames: u32 },
    /// The render would not fit the adapter or the machine's memory: refused before allocating.
    #[error("{session}: too large to render: {what}")]
    TooLarge { session: String, what: String },
}

impl ReplayError {
    /// True when the error comes from the user's input (exit code 2); false for a missing driver
    /// or a GPU failure, which are not.
    pub fn is_user_error(&self) -> bool {
        !matches!(self, ReplayError::Gpu { .. } | ReplayError::Device { .. })
    }
}

impl From<Unsupported> for ReplayError {
    fn from(Unsupported { what }: Unsupported) -> Self {
        ReplayError::Unsupported { what }
    }
}

impl From<OutputError> for ReplayError {
    fn from(e: OutputError) -> Self {
        match e {
            OutputError::Image { path, message } => ReplayError::Image { path, message },
            OutputError::Write(e) => ReplayError::Write(e),
        }
    }
}
