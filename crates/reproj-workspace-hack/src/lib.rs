//! No code. This crate's dependencies turn on, in every build, the features the whole workspace's
//! build turns on for the dependencies the light build shares with it, so that the light build
//! (`scripts/check-light.sh`) reuses the full build's compiled dependencies (see its Cargo.toml).
