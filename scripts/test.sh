#!/usr/bin/env bash
# The whole test suite, from a fresh clone: installs what the tests need (a Vulkan driver for the
# rendering tests: lavapipe where there is no GPU), then runs every test of the workspace.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/ensure-vulkan.sh
# lavapipe runs shaders on the CPU: give it the machine's cores.
# Headless: keep Mesa's device-select layer from looking for a display.
export NODEVICE_SELECT="${NODEVICE_SELECT:-1}"
export LP_NUM_THREADS="${LP_NUM_THREADS:-$(nproc)}"
cargo test --workspace --locked "$@"
