//! Arbitrary text as a GLSL fragment shader: `reproj_front::parse_glsl` (the `#include` and
//! macro scan, then the compiler, the module's validation and its WGSL text), then normalize and
//! enumerate as `front_end` does.
//!
//! By default the compiler is naga's GLSL front end, the fallback reproj uses where glslang is
//! missing (`REPROJ_GLSLANG` names a program that does not exist): glslang is a subprocess, and
//! 10⁶ inputs through it would take days. `REPROJ_FUZZ_GLSLANG=1` runs the real glslang (about
//! 100 inputs a second), which fuzzes the SPIR-V it writes through the sampler split and naga's
//! SPIR-V front end.
#![no_main]

mod common;

use std::path::Path;
use std::sync::Once;

use libfuzzer_sys::fuzz_target;

fn setup() {
    static ONCE: Once = Once::new();
    ONCE.call_once(|| {
        if std::env::var_os("REPROJ_FUZZ_GLSLANG").is_none_or(|v| v != "1") {
            // SAFETY: set once, before any thread of the target reads the environment.
            unsafe { std::env::set_var("REPROJ_GLSLANG", "/nonexistent/glslangValidator") };
        }
    });
}

fuzz_target!(|data: &[u8]| {
    setup();
    let Ok(text) = std::str::from_utf8(data) else {
        return;
    };
    // A folder that holds nothing: an `#include` finds no file.
    common::after_parse(reproj_front::parse_glsl(
        Path::new("/nonexistent/fuzz.frag"),
        text.to_owned(),
    ));
});
