#!/usr/bin/env bash
# Time the two release builds of the reproj binary from clean, one after the other, each in an
# empty target directory: the light one CI needs for `emit` (no wgpu, no nv-flip) and the full
# one. docs/CI.md quotes the figures. Usage: bash scripts/build-times.sh [JOBS]
set -euo pipefail
cd "$(dirname "$0")/.."
jobs="${1:-2}"
cargo fetch --locked >/dev/null
time_build() {
    local name="$1"
    shift
    local dir
    dir="$(mktemp -d "${TMPDIR:-/tmp}/reproj-build-$name.XXXXXX")"
    local start end
    start=$(date +%s.%N)
    CARGO_TARGET_DIR="$dir" cargo build --locked --offline --release -j "$jobs" -p reproj-cli "$@" \
        >"$dir.log" 2>&1 || { tail -20 "$dir.log"; rm -rf "$dir"; exit 1; }
    end=$(date +%s.%N)
    local crates
    crates=$(grep -c '^ *Compiling ' "$dir.log" || true)
    printf '%s: %.0f s, %s crates compiled (load average at the end: %s)\n' \
        "$name" "$(echo "$end - $start" | bc)" "$crates" "$(cut -d' ' -f1-3 /proc/loadavg)"
    rm -rf "$dir" "$dir.log"
}
time_build light --no-default-features
time_build full
