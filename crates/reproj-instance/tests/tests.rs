//! reproj-instance's integration tests, one binary (`--test integration`): a module per topic, each
//! in its file beside this one. A test is named `MODULE::NAME`; `cargo test -p reproj-instance
//! --test integration MODULE::` runs one module. A new file here runs only once declared below: the
//! crate sets `autotests = false`.

mod common;
mod glsl_corpus;
mod instance;
mod languages;
mod manifest;
mod others_corpus;
mod passes;
mod round_trips;
mod simplify;
