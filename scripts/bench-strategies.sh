#!/usr/bin/env bash
# Strategy benchmark: original vs 3pass vs 2pass vs fused for marble, envmap and ambient occlusion
# at 256×256 and 640×480, in one run on one adapter (release build). Prints a Markdown table (the
# one in docs/notebook/pass-layouts.md). Extra arguments go to the benchmark, e.g. `--delta-n 32
# --frames 90`.
#
#   bash scripts/bench-strategies.sh
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/ensure-vulkan.sh
export NODEVICE_SELECT="${NODEVICE_SELECT:-1}"
export LP_NUM_THREADS="${LP_NUM_THREADS:-$(nproc)}"
echo "nproc: $(nproc); LP_NUM_THREADS=$LP_NUM_THREADS" >&2
cargo bench --locked -p reproj-replay --bench strategies -- --markdown "$@"
