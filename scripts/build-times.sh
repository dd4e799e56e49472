#!/usr/bin/env bash
# Time the builds of the reproj binary from clean, one after the other, each in an empty target
# directory: the full release build (`cargo install`'s default), the light release build (no
# default features: no wgpu, nv-flip, image codecs, glTF reader or naga_oil) and the light build as
# docs/CI.md's job installs it (`--profile ci`: unoptimized, no debug info). Each is timed ROUNDS
# times, the three in turn, so load on the machine falls on all of them. docs/CI.md quotes the
# figures. Usage: bash scripts/build-times.sh [JOBS] [ROUNDS]
set -euo pipefail
cd "$(dirname "$0")/.."
jobs="${1:-2}"
rounds="${2:-1}"
cargo fetch --locked >/dev/null
echo "cores: $(nproc), jobs: $jobs, rustc: $(rustc --version)"
time_build() {
    local name="$1"
    shift
    local dir
    dir="$(mktemp -d "${TMPDIR:-/tmp}/reproj-build-$name.XXXXXX")"
    local start end
    start=$(date +%s.%N)
    CARGO_INCREMENTAL=0 CARGO_TARGET_DIR="$dir" \
        cargo build --locked --offline -j "$jobs" -p reproj-cli "$@" \
        >"$dir.log" 2>&1 || { tail -20 "$dir.log"; rm -rf "$dir"; exit 1; }
    end=$(date +%s.%N)
    local crates
    crates=$(grep -c '^ *Compiling ' "$dir.log" || true)
    printf '%-28s %4.0f s, %3s crates compiled (load average at the end: %s)\n' \
        "$name:" "$(echo "$end - $start" | bc)" "$crates" "$(cut -d' ' -f1-3 /proc/loadavg)"
    rm -rf "$dir" "$dir.log"
}
for round in $(seq "$rounds"); do
    echo "round $round"
    time_build "full (release)" --release
    time_build "light (release)" --release --no-default-features
    time_build "light (--profile ci)" --profile ci --no-default-features
done
