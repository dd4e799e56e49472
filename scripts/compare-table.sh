#!/usr/bin/env bash
# The equal-time table of docs/notebook/upsampling-comparison.md ("Against what engines ship"): for each shader, a short
# analyze (its profile, for reproj's own choice), then `compare` at each target speedup — resize,
# easu, temporal, simplify, reproj and reproj+temporal, timed interleaved, scored against the one-sample original
# and a supersampled reference. One compare.json per shader and speedup under OUT; summarize with
# `python3 scripts/compare-table.py OUT`.
#
#   bash scripts/compare-table.sh [OUT] [SPEEDUPS] [SHADERS...]
#
# SPEEDUPS: comma-separated (default 2,3). SHADERS: name=shader.wgsl:session.json (default marble,
# envmap, ambient occlusion and the engine-style corpus' volume ray-marching, where caching pays).
# FRAMES (default 60) frames
# each, SUPERSAMPLE (default 16) samples per pixel; REPROJ names the binary (default
# target/release/reproj). ANALYZE=0 keeps a shader's profile where OUT already holds one. Record
# LP_NUM_THREADS and the core count with the figures.
set -uo pipefail
cd "$(dirname "$0")/.."
R="${REPROJ:-target/release/reproj}"
OUT="${1:-out/compare-table}"
SPEEDUPS="${2:-2,3}"
shift 2 2>/dev/null || shift $#
FRAMES="${FRAMES:-60}"
SUPERSAMPLE="${SUPERSAMPLE:-16}"
if [ $# -eq 0 ]; then
    set -- marble=shaders/marble.wgsl:sessions/marble.json \
        envmap=shaders/envmap.wgsl:sessions/envmap.json \
        ambient_occlusion=shaders/ambient_occlusion.wgsl:sessions/ambient_occlusion.json \
        volume_raymarch=tests/corpus/shaders/volume_raymarch.wgsl:tests/corpus/sessions/volume_raymarch.json
fi
mkdir -p "$OUT"
echo "machine: $(nproc) cores, LP_NUM_THREADS=${LP_NUM_THREADS:-unset}" | tee "$OUT/machine.txt"
for spec in "$@"; do
    name="${spec%%=*}"
    rest="${spec#*=}"
    shader="${rest%%:*}"
    session="${rest#*:}"
    d="$OUT/$name"
    mkdir -p "$d"
    t0=$(date +%s)
    if [ "${ANALYZE:-1}" = 0 ] && [ -f "$d/p.profile.json" ]; then
        echo "$name: profile kept"
    else
    "$R" analyze "$shader" --session "$session" --out "$d/p.profile.json" --max-frames "$FRAMES" \
        --delta-n 2,6,12,26,50 --holdout 8 --max-nodes 4 --no-sets --no-charts --fresh --quiet \
        >"$d/analyze.log" 2>&1 || echo "$name: analyze failed (exit $?), see $d/analyze.log"
    echo "$name: analyze $(($(date +%s) - t0)) s"
    fi
    for x in ${SPEEDUPS//,/ }; do
        t0=$(date +%s)
        profile=()
        [ -f "$d/p.profile.json" ] && profile=(--profile "$d/p.profile.json")
        "$R" compare "$shader" --session "$session" --speedup "$x" "${profile[@]}" \
            --max-frames "$FRAMES" --supersample "$SUPERSAMPLE" --out "$d/x$x" --quiet \
            >"$d/x$x.txt" 2>"$d/x$x.log" || echo "$name at ${x}x: compare failed (exit $?), see $d/x$x.log"
        echo "$name at ${x}x: compare $(($(date +%s) - t0)) s"
    done
done
