//! reproj-replay's integration tests, one binary (`--test integration`): a module per topic, each
//! in its file beside this one. A test is named `MODULE::NAME`; `cargo test -p reproj-replay --test
//! integration MODULE::` runs one module. A new file here runs only once declared below: the crate
//! sets `autotests = false`.

mod gltf;
mod invariants;
mod motion;
mod perceptual;
mod pure;
mod replay;
mod upsample;
