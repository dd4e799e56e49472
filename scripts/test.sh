#!/usr/bin/env bash
# The whole test suite, from a fresh clone: installs what the tests need (a Vulkan driver for the
# rendering tests: lavapipe where there is no GPU; the shader compilers of the portability check,
# when they can be installed), then runs every test of the workspace and closes with one line that
# adds up every test binary's results.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/ensure-vulkan.sh
bash scripts/ensure-tools.sh || true
# Headless: keep Mesa's device-select layer from looking for a display.
export NODEVICE_SELECT="${NODEVICE_SELECT:-1}"
# Non-incremental, as CI builds: with incremental codegen units reproj-metrics (opt-level 3, the
# CPU scorers) is most likely what is optimized badly: the replay's tests took 327 s instead of 68 s.
export CARGO_INCREMENTAL="${CARGO_INCREMENTAL:-0}"
# lavapipe runs shaders on the CPU: give it the machine's cores.
export LP_NUM_THREADS="${LP_NUM_THREADS:-$(nproc)}"
log=$(mktemp)
trap 'rm -f "$log"' EXIT
status=0
start=$SECONDS
cargo test --workspace --locked "$@" 2>&1 | tee "$log" || status=$?
workspace=$((SECONDS - start))
# The light build (no GPU crates) still compiles: docs/CI.md's `emit` job installs it.
bash scripts/check-light.sh || status=$?
light=$((SECONDS - start - workspace))
passed=$(grep -Eo 'test result: [A-Za-z]+\. [0-9]+ passed' "$log" | awk '{s += $4} END {print s + 0}')
failed=$(grep -Eo '[0-9]+ failed' "$log" | awk '{s += $1} END {print s + 0}')
echo
echo "reproj: $passed passed, $failed failed"
mmss() { printf '%dm%02ds' $(($1 / 60)) $(($1 % 60)); }
echo "wall time: $(mmss $((workspace + light))) (the workspace build and its tests $(mmss $workspace), the light build $(mmss $light)), $(nproc) cores"
exit "$status"
