#!/usr/bin/env bash
# The figures docs/notebook/gpu-h200.md gives for a real GPU, in one run of about seven minutes: for marble
# and ambient occlusion at 1920×1080, the A/A check, analyze (periods extended where they can
# pay), emit at 0.002 / 0.01 / 0.03 / 0.1 (verified at 0.01), the variants benched together
# interleaved, and compare at 2× (3× where time is left). Each step has its own time limit and a
# failed step does not stop the others; the whole run stops starting steps after BUDGET_S
# seconds. Everything lands in OUT (logs, profiles, JSON), and OUT/figures.tgz is refreshed after
# every step so a run cut short still leaves what it measured.
#
#   bash scripts/figures-gpu.sh [OUT]
#
# REPROJ names the binary (default target/release/reproj); BUDGET_S (default 420) the seconds
# after which no step starts; SKIP_ANALYZE=1 reuses OUT's profiles. The sessions are the 1080p
# ones (sessions/*_1080p.json): at 256×256 a GPU only measures overheads.
set -uo pipefail
cd "$(dirname "$0")/.."
R="${REPROJ:-target/release/reproj}"
OUT="${1:-out/gpu}"
BUDGET_S="${BUDGET_S:-420}"
W="$OUT/work"
mkdir -p "$W"
T0=$(date +%s)
pack() { tar czf "$OUT/figures.tgz.tmp" -C "$W" . && mv "$OUT/figures.tgz.tmp" "$OUT/figures.tgz"; }
step() { # step NAME LIMIT_S COMMAND...: run, log, time, pack (skipped past the budget)
    local name="$1" limit="$2"
    shift 2
    local t0 rc left
    left=$((BUDGET_S - ($(date +%s) - T0)))
    if [ "$left" -le 5 ]; then
        printf '%-16s skipped: the run budget (%s s) is spent\n' "$name" "$BUDGET_S" | tee -a "$W/steps.txt"
        return
    fi
    [ "$limit" -gt "$left" ] && limit=$left
    t0=$(date +%s%N)
    timeout "$limit" "$@" >"$W/$name.out" 2>"$W/$name.err"
    rc=$?
    printf '%-16s rc=%-3s %7.1f s (limit %s)  %s\n' "$name" "$rc" \
        "$((($(date +%s%N) - t0) / 1000000))e-3" "$limit" "$*" | tee -a "$W/steps.txt"
    tail -n 3 "$W/$name.err" | sed 's/^/    /'
    pack
}
{
    echo "date: $(date -u +%FT%TZ)"
    echo "nproc: $(nproc); LP_NUM_THREADS=${LP_NUM_THREADS:-unset}"
    nvidia-smi --query-gpu=name,driver_version,clocks.sm,clocks.max.sm --format=csv 2>/dev/null
    "$R" --version
    git rev-parse --short HEAD 2>/dev/null
} | tee "$W/machine.txt"
: >"$W/steps.txt"

# shader-stem session-stem analyze-limit: analyze one shader at 1080p (ꟻLIP/SSIM on every 50th
# frame: the L2 error is reduced on the GPU for every frame, the perceptual frames are read back).
analyze() {
    [ -n "${SKIP_ANALYZE:-}" ] && return
    step "analyze-$1" "$3" "$R" analyze "shaders/$1.wgsl" --session "sessions/$2.json" \
        --out "$W/$1.profile.json" --metric-stride 50 --no-charts --fresh --json ${ANALYZE_ARGS:-}
}
# shader-stem session-stem budget verify?: emit one budget (verified where asked).
emit() {
    local v=()
    [ "$4" = verify ] && v=(--verify)
    step "emit-$1-$3" 45 "$R" emit --profile "$W/$1.profile.json" --session "sessions/$2.json" \
        --max-error "$3" --out "$W/$1-$3" --json "${v[@]}"
}

M=marble S=marble_1080p
step aa-marble 25 "$R" bench shaders/marble.wgsl --session sessions/$S.json shaders/marble.wgsl --max-time 10 --json
analyze $M $S "${MARBLE_ANALYZE_S:-200}"
for b in 0.002 0.03 0.1; do emit $M $S $b no; done
emit $M $S 0.01 verify
step bench-marble 40 "$R" bench shaders/marble.wgsl --session sessions/$S.json \
    "$W/$M-0.002" "$W/$M-0.01" "$W/$M-0.03" "$W/$M-0.1" --max-time 20 --json

[ -n "${ONLY_MARBLE:-}" ] && { step compare-marble-2x 75 "$R" compare shaders/marble.wgsl --session sessions/$S.json --profile "$W/$M.profile.json" --speedup 2 --out "$W/compare-2x" --json; cat "$W/steps.txt"; exit 0; }
A=ambient_occlusion SA=ambient_occlusion_1080p
analyze $A $SA 90
emit $A $SA 0.002 verify
emit $A $SA 0.01 no
step bench-ao 35 "$R" bench shaders/$A.wgsl --session sessions/$SA.json \
    "$W/$A-0.002" "$W/$A-0.01" --max-time 15 --json

step compare-marble-2x 75 "$R" compare shaders/marble.wgsl --session sessions/$S.json \
    --profile "$W/$M.profile.json" --speedup 2 --out "$W/compare-2x" --json
step compare-marble-3x 75 "$R" compare shaders/marble.wgsl --session sessions/$S.json \
    --profile "$W/$M.profile.json" --speedup 3 --out "$W/compare-3x" --json
cat "$W/steps.txt"
