#!/usr/bin/env bash
# The light build CI uses to run `emit` (docs/CI.md): reproj-cli without its default `gpu`
# feature (nodes, instance, emit, completions; no wgpu, no nv-flip) must keep compiling.
# What it depends on is checked by `the_light_build_has_no_gpu_crates`
# (crates/reproj-cli/tests/layering.rs). Run by scripts/test.sh.
set -euo pipefail
cd "$(dirname "$0")/.."
cargo check --locked -p reproj-cli --no-default-features
