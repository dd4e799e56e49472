//! Arbitrary bytes as a SPIR-V module: the combined-sampler split reproj applies to glslang's
//! output (`split_combined_samplers`, on the words), then `reproj_front::parse_spirv` (naga's
//! SPIR-V front end, validation, the module's WGSL text), then normalize and enumerate as
//! `front_end` does.
#![no_main]

mod common;

use std::path::Path;

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let words: Vec<u32> = data
        .chunks_exact(4)
        .map(|w| u32::from_le_bytes([w[0], w[1], w[2], w[3]]))
        .collect();
    if let Ok((split, _)) = reproj_front::glslang::split::split_combined_samplers(&words) {
        let bytes: Vec<u8> = split.iter().flat_map(|w| w.to_le_bytes()).collect();
        common::after_parse(reproj_front::parse_spirv(Path::new("fuzz.spv"), &bytes));
    }
    common::after_parse(reproj_front::parse_spirv(Path::new("fuzz.spv"), data));
});
