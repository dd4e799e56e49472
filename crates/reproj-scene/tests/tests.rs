//! reproj-scene's integration tests, one binary (`--test integration`): a module per topic, each in
//! its file beside this one. A test is named `MODULE::NAME`; `cargo test -p reproj-scene --test
//! integration MODULE::` runs one module. A new file here runs only once declared below: the crate
//! sets `autotests = false`.

mod engine;
mod fuzz_regressions;
#[cfg(feature = "gltf")]
mod gltf;
mod session;
