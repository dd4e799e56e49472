//! reproj-emit's integration tests, one binary (`--test integration`): a module per topic, each in
//! its file beside this one. A test is named `MODULE::NAME`; `cargo test -p reproj-emit --test
//! integration MODULE::` runs one module. A new file here runs only once declared below: the crate
//! sets `autotests = false`.

mod emit;
mod motion;
