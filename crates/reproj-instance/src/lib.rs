//! The reproj instancer.
//!
//! Turns a shader and one cacheable node into a *variant*: three fragment modules (reproject,
//! recompute, shade) and a manifest that tells a host how to run them. See `docs/PASSES.md`.

pub mod manifest;

pub use manifest::*;
