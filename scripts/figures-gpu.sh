#!/usr/bin/env bash
# The figures docs/results.md gives for a real GPU, in one run: the A/A check, analyze (with the
# filter race), emit --verify at three budgets, the variants benched interleaved (twice), and
# compare against reduced resolution at equal time. Each step has its own time limit and a failed
# step does not stop the others; everything lands in OUT (logs, profile, JSON), and
# OUT/figures.tgz is refreshed after every step so a run cut short still leaves what it measured.
#
#   bash scripts/figures-gpu.sh [OUT] [SESSION]
#
# REPROJ names the binary (default target/release/reproj); SKIP_ANALYZE=1 reuses OUT's profile. SESSION defaults to
# sessions/marble_1080p.json (256×256 is too small to load a GPU: overheads dominate).
set -uo pipefail
cd "$(dirname "$0")/.."
R="${REPROJ:-target/release/reproj}"
OUT="${1:-out/gpu}"
S="${2:-sessions/marble_1080p.json}"
SH=shaders/marble.wgsl
W="$OUT/work"
mkdir -p "$W"
pack() { tar czf "$OUT/figures.tgz.tmp" -C "$W" . && mv "$OUT/figures.tgz.tmp" "$OUT/figures.tgz"; }
step() { # step NAME LIMIT_S COMMAND...: run, log, time, pack
    local name="$1" limit="$2"
    shift 2
    local t0 rc
    t0=$(date +%s%N)
    timeout "$limit" "$@" >"$W/$name.out" 2>"$W/$name.err"
    rc=$?
    printf '%-14s rc=%-3s %7.1f s  %s\n' "$name" "$rc" "$((($(date +%s%N) - t0) / 1000000))e-3" "$*" |
        tee -a "$W/steps.txt"
    tail -n 4 "$W/$name.err" | sed 's/^/    /'
    pack
}
{
    echo "date: $(date -u +%FT%TZ)"
    echo "nproc: $(nproc); LP_NUM_THREADS=${LP_NUM_THREADS:-unset}"
    nvidia-smi --query-gpu=name,driver_version,clocks.sm,clocks.max.sm --format=csv 2>/dev/null
    "$R" --version
    echo "session: $S; shader: $SH"
} | tee "$W/machine.txt"
: >"$W/steps.txt"

step aa 60 "$R" bench "$SH" --session "$S" "$SH" --max-time 20 --json
if [ -z "${SKIP_ANALYZE:-}" ]; then
    step analyze 240 "$R" analyze "$SH" --session "$S" --out "$W/marble.profile.json" \
        --reconstruct auto --no-charts --fresh --json
fi
for b in 0.01 0.03 0.1; do
    step "emit-$b" 60 "$R" emit --profile "$W/marble.profile.json" --session "$S" \
        --max-error "$b" --out "$W/v$b" --verify --json
done
bench() { step "bench-$1" 60 "$R" bench "$SH" --session "$S" "$W/v0.01" "$W/v0.03" "$W/v0.1" \
    --max-time 25 --json; }
bench 1
step compare 120 "$R" compare "$SH" --session "$S" --profile "$W/marble.profile.json" \
    --speedup 2 --out "$W/compare" --json
bench 2
cat "$W/steps.txt"
