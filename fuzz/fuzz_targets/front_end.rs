//! Arbitrary text through the front end: parse → normalize (every fragment entry, by name) →
//! enumerate (`common::after_parse`, which says what REPROJ_FUZZ_STRICT=1 adds). Errors are fine;
//! a panic is a bug.
#![no_main]

mod common;

use std::path::Path;

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let Ok(text) = std::str::from_utf8(data) else {
        return;
    };
    common::after_parse(reproj_front::parse_shader(Path::new("fuzz.wgsl"), text.to_owned()));
});
