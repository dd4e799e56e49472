#!/usr/bin/env bash
# Set everything up and run reproj on the bundled marble sample.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/ensure-vulkan.sh
export LP_NUM_THREADS="${LP_NUM_THREADS:-$(nproc)}"
cargo build --release --locked -p reproj-cli
REPROJ=target/release/reproj
echo "== reproj nodes shaders/marble.wgsl"
$REPROJ nodes shaders/marble.wgsl
echo
echo "== reproj instance shaders/marble.wgsl --node root --out out/marble_root"
$REPROJ instance shaders/marble.wgsl --node root --out out/marble_root
