//! reproj image metrics: how far a frame is from its reference, and the images that show it.
//! GPU-free: the replay renders and reduces on the GPU, and hands its sums and frames here.
//!
//! Layered bottom-up, each module importing only from those above it in this list:
//!
//! - [`l2`]: the paper's error (mean L2 distance over all pixels), MSE and PSNR over the covered
//!   pixels ([`l2::compare`] on the CPU; the replay's GPU reduction computes the same sums).
//! - [`report`]: the render report (`reproj render --json`): per-frame records, session means,
//!   the per-metric summary (mean, worst frame).
//! - [`srgb`]: what a viewer sees of a linear frame (sRGB, 8 bits), shared by the PNGs and the
//!   perceptual metrics.
//! - `perceptual` (feature `flip`, on by default): ꟻLIP (NVIDIA's C++ reference through
//!   `nv-flip`) and SSIM over the covered pixels.
//! - `output` (feature `png`, on by default): PNG frames, hit maps, error maps with a colour bar,
//!   ꟻLIP maps (feature `flip`), raw f32 frames.
//!
//! Definitions of every metric: `docs/SCHEMAS.md`. The light build (`reproj-cli` without `gpu`)
//! uses this crate without `flip` or `png`, so it compiles no C++ and no image codecs.

pub mod l2;
#[cfg(feature = "png")]
pub mod output;
#[cfg(feature = "flip")]
pub mod perceptual;
pub mod report;
pub mod srgb;

pub use l2::{FrameError, PSNR_CAP, psnr};
pub use report::{
    AdapterReport, FrameRecord, FrameValue, MetricSummary, RENDER_REPORT_SCHEMA,
    RENDER_REPORT_VERSION, RenderReport, TimingMethod,
};
