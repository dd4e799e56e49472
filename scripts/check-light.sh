#!/usr/bin/env bash
# The light build CI uses to run `emit` (docs/CI.md): reproj-cli without its default features
# (`gpu`, `gltf`, `compose`: nodes, instance, emit, session init, completions; no wgpu, nv-flip,
# image codecs, glTF reader or naga_oil) must keep compiling, and what it refuses (a glTF session,
# a shader with `#import`s) it refuses by name. What it depends on is checked by
# `the_light_build_has_no_gpu_crates` (crates/reproj-cli/tests/layering.rs); reproj-emit's tests run
# here in that light configuration too, with the front end's and the scene's. Run by scripts/test.sh.
# Built, not only checked: with crates/reproj-workspace-hack the dependencies are the very units
# `cargo test --workspace` compiled, so only reproj's own crates are compiled here again (a
# `cargo check` would compile every dependency once more in check mode).
set -euo pipefail
cd "$(dirname "$0")/.."
cargo build --locked -p reproj-cli --no-default-features
# emit's crate built and tested on its own (no wgpu, no glTF or naga_oil: its graph is checked by
# `only_the_replay_and_its_users_depend_on_wgpu`), with the front end's and the scene's tests in the
# same light configuration (their `absent_` tests: what the light build refuses, by name). One
# invocation, so the three resolve their features once.
cargo test --locked -p reproj-emit -p reproj-scene -p reproj-front --no-default-features
