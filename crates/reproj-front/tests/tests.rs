//! reproj-front's integration tests, one binary (`--test integration`): a module per topic, each in
//! its file beside this one. A test is named `MODULE::NAME`; `cargo test -p reproj-front --test
//! integration MODULE::` runs one module. A new file here runs only once declared below: the crate
//! sets `autotests = false`.

#[cfg(feature = "compose")]
mod defs;
mod fuzz_regressions;
mod glsl_corpus;
mod glsl_idioms;
#[cfg(feature = "compose")]
mod imports;
mod languages;
mod nesting;
mod rules;
mod scale;
mod shapes;
mod unroll;
