#!/usr/bin/env bash
# The one run a session with a borrowed GPU makes: every GPU figure of docs/notebook/gpu-h200.md
# in about eight minutes, so that one command of at most ten holds all of it. In order of value,
# at 1920×1080:
#   marble             the A/A check, analyze (8 nodes), emit at 0.002 / 0.01 / 0.03 / 0.1 with
#                      --verify once per distinct choice, the verified variants benched together
#   ambient occlusion  analyze, emit at 0.002 / 0.01 verified the same way, the bench
#   compare            marble at 2× and 3×, every method compare has (shortened searches)
#   corpus             scripts/corpus-speedups.sh over tests/corpus/sessions/1080p, then
#                      scripts/corpus-table.py; the shaders that paid on lavapipe first
#   envmap             analyze and emit 0.01 verified, only where time is left
# Each step has its own time limit and a failed step does not stop the others; no step starts
# after BUDGET_S seconds, and a step's limit is cut to what is left of it. Everything lands in
# OUT/work (steps.txt, logs, profiles, variants, JSON), and OUT/figures.tgz is refreshed after
# every step so a run cut short still leaves what it measured.
#
#   bash scripts/figures-gpu.sh [OUT]          # on the GPU machine (default OUT: out/gpu)
#   DRY=1 bash scripts/figures-gpu.sh /tmp/d   # the same steps, shrunk, on a CPU (lavapipe)
#
# REPROJ names the binary (default target/release/reproj); WORK the working folder (default
# OUT/work; outside OUT when only figures.tgz should be in OUT); BUDGET_S the seconds after which
# no step starts (480; dry 720); PARTS which parts run (default "marble ao compare corpus
# envmap"); SKIP_ANALYZE=1 reuses WORK's profiles; ANALYZE_ARGS replaces marble's and AO's extra analyze
# options; COMPARE_ARGS compare's search options; CORPUS_FIRST and CORPUS_FILTER the corpus
# shaders run first and kept. DRY=1 uses the 256×256 sessions cut to 60 frames (corpus: its
# 128×128 ones), 2-node analyses and small limits: the script checked end to end without a GPU.
set -uo pipefail
cd "$(dirname "$0")/.." || exit 2
R="${REPROJ:-target/release/reproj}"
OUT="${1:-out/gpu}"
W="${WORK:-$OUT/work}"
# ONLY_MARBLE=1, the earlier runs' knob, is PARTS="marble compare".
[ -n "${ONLY_MARBLE:-}" ] && PARTS="${PARTS:-marble compare}"
PARTS=" ${PARTS:-marble ao compare corpus envmap} "
DRY="${DRY:-}"
# g GPU DRY: the value for the GPU run, or the dry run's.
g() { if [ -n "$DRY" ]; then echo "$2"; else echo "$1"; fi; }
BUDGET_S="${BUDGET_S:-$(g 480 720)}"
mkdir -p "$W"
# sess STEM: the session of a sample shader: sessions/STEM_1080p.json on the GPU; in a dry run
# sessions/STEM.json (256×256) cut to its first 60 frames (a copy in OUT/work/sessions), so
# that verifying and benching fit a CPU rasterizer's limits.
sess() {
    if [ -z "$DRY" ]; then echo "sessions/${1}_1080p.json"; return; fi
    mkdir -p "$W/sessions"
    python3 -c "import json,sys
d=json.load(open(sys.argv[1])); d['frames']=min(d['frames'],60)
json.dump(d,open(sys.argv[2],'w'),indent=1)" "sessions/$1.json" "$W/sessions/$1.json" &&
        echo "$W/sessions/$1.json"
}
CORPUS_SESSIONS=$(g tests/corpus/sessions/1080p tests/corpus/sessions)
# ꟻLIP/SSIM on every 50th frame (the L2 error is reduced for every frame): as the earlier GPU
# runs did, so their figures compare.
read -r -a ANALYZE_COMMON <<<"--metric-stride 50 --no-charts --fresh --json"
read -r -a DRY_ANALYZE <<<"$(g "" "--max-nodes 2 --fit-delta-n 2,10,50 --holdout 6 --no-sets")"
# compare at 1080p with its default searches did not finish in 75 s (26 simplification steps of
# ~10 s); with 60 frames and a 4-sample reference not either (the reference 15 s, ~7 s a step, 31
# steps planned: ~250 s, H200 2026-11-29). 30 frames and a 2-sample reference quarter that.
read -r -a CMP <<<"${COMPARE_ARGS:-$(g "--max-frames 30 --candidates 3 --max-steps 4 --supersample 2" \
    "--max-frames 20 --candidates 2 --max-steps 2 --supersample 2 --resize-tries 2 --reproj-tries 2")}"
T0=$(date +%s)
left() { echo $((BUDGET_S - ($(date +%s) - T0))); }
pack() { mkdir -p "$OUT" && tar czf "$OUT/figures.tgz.tmp" -C "$W" . && mv "$OUT/figures.tgz.tmp" "$OUT/figures.tgz"; }
note() { printf '%-30s %s\n' "$1" "$2" | tee -a "$W/steps.txt"; }
step() { # step NAME LIMIT_S COMMAND...: run, log, time, pack (skipped past the budget)
    local name="$1" limit="$2"
    shift 2
    local t0 rc l
    l=$(left)
    if [ "$l" -le 5 ]; then
        note "$name" "skipped: the run budget ($BUDGET_S s) is spent"
        return
    fi
    [ "$limit" -gt "$l" ] && limit=$l
    t0=$(date +%s%N)
    timeout -k 5 "$limit" "$@" >"$W/$name.out" 2>"$W/$name.err"
    rc=$?
    printf '%-30s rc=%-3s %7.1f s (limit %s)  %s\n' "$name" "$rc" \
        "$((($(date +%s%N) - t0) / 1000000))e-3" "$limit" "$*" | tee -a "$W/steps.txt"
    tail -n 3 "$W/$name.err" | sed 's/^/    /'
    pack
}
has() { [[ "$PARTS" == *" $1 "* ]]; }
{
    echo "date: $(date -u +%FT%TZ)"
    echo "mode: $(g "GPU (1920×1080 sessions)" "dry run (256×256 sessions, short analyses)"); budget ${BUDGET_S} s; parts:${PARTS% }"
    echo "nproc: $(nproc); LP_NUM_THREADS=${LP_NUM_THREADS:-unset}"
    nvidia-smi --query-gpu=name,driver_version,clocks.sm,clocks.max.sm --format=csv 2>/dev/null
    "$R" --version
    git rev-parse --short HEAD 2>/dev/null
} | tee "$W/machine.txt"
: >"$W/steps.txt"

# analyze STEM SESSION LIMIT EXTRA...: profile one sample shader (EXTRA: its own options, which
# ANALYZE_ARGS, or a dry run's short analysis, replaces).
analyze() {
    local stem="$1" s="$2" limit="$3"
    shift 3
    [ -n "${SKIP_ANALYZE:-}" ] && return
    local extra=("$@")
    [ -n "$DRY" ] && extra=("${DRY_ANALYZE[@]}")
    [ -n "${ANALYZE_ARGS:-}" ] && read -r -a extra <<<"$ANALYZE_ARGS"
    step "analyze-$stem" "$limit" "$R" analyze "shaders/$stem.wgsl" --session "$s" \
        --out "$W/$stem.profile.json" "${ANALYZE_COMMON[@]}" "${extra[@]}"
}
# choice FILE: what an emit report chose, "node strategy Δn filter", "original: why", or nothing
# when the file is not a report.
choice() {
    python3 -c "import json,sys
try: d=json.load(open(sys.argv[1]))
except Exception: sys.exit()
if d.get('node') is None: print('original:', (d.get('reason') or '')[:80])
else: print(d['node'], d.get('strategy'), 'Δn', d.get('delta_n'), d.get('reconstruct'))" "$1"
}
# emits STEM SESSION BUDGET...: emit every budget as predicted (a fraction of a second each),
# then --verify each distinct choice once, at the tightest budget that made it: a looser budget
# with the same node, strategy, Δn and filter would render and time the same variant again.
# VARIANTS gets the distinct variants' directories, for the bench.
emits() {
    local stem="$1" s="$2" b c
    shift 2
    VARIANTS=()
    if [ ! -f "$W/$stem.profile.json" ]; then
        note "emit-$stem" "skipped: no profile"
        return
    fi
    local -A by=()
    for b in "$@"; do
        step "emit-$stem-$b" 15 "$R" emit --profile "$W/$stem.profile.json" --session "$s" \
            --max-error "$b" --out "$W/$stem-$b" --json
    done
    for b in "$@"; do
        c=$(choice "$W/emit-$stem-$b.out")
        if [ -z "$c" ]; then
            note "verify-$stem-$b" "skipped: emit wrote no report"
        elif [[ "$c" == original:* ]]; then
            note "verify-$stem-$b" "nothing to verify: $c"
        elif [ -n "${by[$c]:-}" ]; then
            note "verify-$stem-$b" "same choice as ${by[$c]} ($c): not rendered again"
        else
            by[$c]=$b
            step "verify-$stem-$b" "$(g 45 40)" "$R" emit --profile "$W/$stem.profile.json" \
                --session "$s" --max-error "$b" --out "$W/$stem-$b" --verify --json
            [ -f "$W/$stem-$b/manifest.json" ] && VARIANTS+=("$W/$stem-$b")
        fi
    done
}
# bench STEM SESSION MAX_TIME LIMIT: the distinct variants against the original, interleaved.
bench() {
    if [ ${#VARIANTS[@]} -eq 0 ]; then
        note "bench-$1" "skipped: no variant to bench"
        return
    fi
    step "bench-$1" "$4" "$R" bench "shaders/$1.wgsl" --session "$2" "${VARIANTS[@]}" \
        --max-time "$3" --json
}

M=marble S=$(sess marble)
if has marble; then
    step aa-marble "$(g 20 15)" "$R" bench shaders/$M.wgsl --session "$S" shaders/$M.wgsl \
        --max-time "$(g 8 3)" --json
    analyze $M "$S" "${MARBLE_ANALYZE_S:-$(g 130 45)}" --max-nodes 8
    emits $M "$S" 0.002 0.01 0.03 0.1
    bench $M "$S" "$(g 12 4)" "$(g 25 15)"
fi

A=ambient_occlusion SA=$(sess ambient_occlusion)
if has ao; then
    analyze $A "$SA" "$(g 80 60)"
    emits $A "$SA" 0.002 0.01
    bench $A "$SA" "$(g 10 4)" "$(g 20 15)"
fi

if has compare; then
    prof=()
    [ -f "$W/$M.profile.json" ] && prof=(--profile "$W/$M.profile.json")
    for x in 2 3; do
        step "compare-$M-${x}x" "$(g 110 120)" "$R" compare shaders/$M.wgsl --session "$S" "${prof[@]}" \
            --speedup $x --out "$W/compare-${x}x" --json "${CMP[@]}"
    done
fi

if has corpus; then
    # All the time left goes to the corpus (envmap comes after only where some is still left);
    # corpus-speedups.sh stops starting commands 3 s before the step's limit, so its table holds
    # whole lines. Cheap shaders answer "cannot pay" in seconds; the promising ones go first.
    cl=$(g 300 100)
    [ "$cl" -gt $(($(left) - 2)) ] && cl=$(($(left) - 2))
    [ "$cl" -lt 1 ] && cl=1
    step corpus "$cl" env TOTAL_S=$((cl - 3)) LIMIT_S="$(g 30 20)" REPROJ="$R" \
        SESSIONS_DIR="$CORPUS_SESSIONS" ANALYZE_ARGS="--metric-stride 16" \
        FIRST="${CORPUS_FIRST:-volume_raymarch heat_haze deferred_lighting pbr_ibl terrain_splat water caustics pom_search lava_flowmap carbon_clearcoat matcap triplanar}" \
        bash scripts/corpus-speedups.sh "$W/corpus" "${CORPUS_FILTER:-}"
    if [ -f "$W/corpus/corpus.tsv" ]; then
        step corpus-table 10 python3 scripts/corpus-table.py "$W/corpus/corpus.tsv"
        [ -f "$W/corpus-table.out" ] && cat "$W/corpus-table.out"
    fi
fi

E=envmap SE=$(sess envmap)
if has envmap; then
    analyze $E "$SE" "$(g 60 50)"
    emits $E "$SE" 0.01
fi
echo "total: $(($(date +%s) - T0)) s of ${BUDGET_S}" | tee -a "$W/steps.txt"
pack
cat "$W/steps.txt"
