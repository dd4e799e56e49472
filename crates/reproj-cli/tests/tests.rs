//! reproj-cli's integration tests, one binary (`--test integration`): a module per topic, each in
//! its file beside this one. A test is named `MODULE::NAME`; `cargo test -p reproj-cli --test
//! integration MODULE::` runs one module. A new file here runs only once declared below: the crate
//! sets `autotests = false`.

mod bad_input;
mod bench;
mod ci;
mod cli;
mod common;
mod compare;
mod corpus;
mod engine_sessions;
mod f16;
mod gltf;
mod layering;
mod metric;
mod nodes;
mod nonfinite;
mod portability;
mod profiled_settings;
mod report;
mod scripting;
mod session_init;
mod sessions;
mod sets;
mod shader_defs;
mod signals;
mod test_files;
mod variant;
mod verify;
mod vulkan_validation;
mod writers;
