//! reproj-analyze's integration tests, one binary (`--test integration`): a module per topic, each
//! in its file beside this one. A test is named `MODULE::NAME`; `cargo test -p reproj-analyze
//! --test integration MODULE::` runs one module. A new file here runs only once declared below: the
//! crate sets `autotests = false`.

mod analyze;
