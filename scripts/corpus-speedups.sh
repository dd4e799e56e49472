#!/usr/bin/env bash
# The corpus table docs/notebook/corpus.md gives ("The corpus, end to end"): for every corpus shader that
# has a session (tests/corpus/shaders/*.wgsl and glsl/*.frag with tests/corpus/sessions/), a
# short analyze (training Δn 2, 10, 26, 50, at most 4 nodes, no sets), then emit --verify at 0.01
# and 0.03; one line per shader and budget in OUT/corpus.tsv: the ceiling the analysis measured,
# the choice, the verified speedup with its interval and error, or why the original was kept.
# Each command has its own time limit (LIMIT_S, default 120); a failure is a line too.
#
#   bash scripts/corpus-speedups.sh [OUT] [FILTER]
#
# REPROJ names the binary (default target/release/reproj); FILTER keeps the shaders whose path
# contains it. SESSIONS_DIR (default tests/corpus/sessions) is where the sessions are looked up,
# as NAME.json and glsl/NAME.json: tests/corpus/sessions/1080p holds them at 1920×1080 for a GPU.
# ANALYZE_ARGS are added to every analyze (e.g. --metric-stride 16). FIRST lists shader names
# (stems) run before the others, in that order. TOTAL_S (default 0: none) stops starting
# commands after that many seconds, so a caller with a deadline gets whole lines, not a cut.
# Summarize with `python3 scripts/corpus-table.py OUT/corpus.tsv`.
set -uo pipefail
cd "$(dirname "$0")/.." || exit 2
R="${REPROJ:-target/release/reproj}"
OUT="${1:-out/corpus}"
FILTER="${2:-}"
LIMIT_S="${LIMIT_S:-120}"
SESSIONS_DIR="${SESSIONS_DIR:-tests/corpus/sessions}"
TOTAL_S="${TOTAL_S:-0}"
read -r -a EXTRA <<<"${ANALYZE_ARGS:-}"
T_START=$(date +%s)
mkdir -p "$OUT"
T="$OUT/corpus.tsv"
printf 'shader\tbudget\tstatus\tceiling\tnode\tstrategy\tdelta_n\tspeedup\tlo\thi\terror\tpsnr\treason\tanalyze_s\n' >"$T"
field() { python3 -c "import json,sys
try: d=json.load(open(sys.argv[1]))
except Exception: print(''); sys.exit()
v=d
for k in sys.argv[2].split('.'):
    v=v.get(k) if isinstance(v,dict) else (v[int(k)] if isinstance(v,list) and len(v)>int(k) else None)
    if v is None: break
print('' if v is None else (round(v,4) if isinstance(v,float) else v))" "$@"; }
# The limit of the next command: LIMIT_S, cut to what TOTAL_S leaves (0 or less: no time left).
limit() {
    local left
    [ "$TOTAL_S" -gt 0 ] || { echo "$LIMIT_S"; return; }
    left=$((TOTAL_S - ($(date +%s) - T_START)))
    [ "$left" -lt "$LIMIT_S" ] && echo "$left" || echo "$LIMIT_S"
}
# --foreground keeps reproj in this script's process group: a caller's timeout that ends this
# script ends the reproj it is waiting on too.
run() { local l="$1"; shift; timeout --foreground -k 5 "$l" "$@"; }

all=(tests/corpus/shaders/*.wgsl tests/corpus/shaders/glsl/*.frag)
shaders=()
for name in ${FIRST:-}; do
    for s in "${all[@]}"; do [ "$(basename "${s%.*}")" = "$name" ] && shaders+=("$s"); done
done
for s in "${all[@]}"; do
    case " ${FIRST:-} " in *" $(basename "${s%.*}") "*) ;; *) shaders+=("$s") ;; esac
done
not_run=()
for shader in "${shaders[@]}"; do
    case "$shader" in *"$FILTER"*) ;; *) continue ;; esac
    stem=$(basename "${shader%.*}")
    sub=""; [[ "$shader" == */glsl/* ]] && sub="glsl/"
    session="$SESSIONS_DIR/$sub$stem.json"
    [ -f "$session" ] || continue
    if [ "$(limit)" -lt 10 ]; then
        not_run+=("$shader")
        continue
    fi
    d="$OUT/$sub$stem"
    mkdir -p "$d"
    t0=$(date +%s)
    l=$(limit)
    run "$l" "$R" analyze "$shader" --session "$session" --out "$d/p.profile.json" \
        --delta-n 2,10,26,50 --holdout 6 --max-nodes 4 --no-sets --no-charts --fresh --json \
        "${EXTRA[@]}" >"$d/analyze.json" 2>"$d/analyze.err"
    rc=$?
    secs=$(($(date +%s) - t0))
    ceiling=$(field "$d/p.profile.json" ceiling.speedup)
    if [ $rc -ne 0 ]; then
        why=$(grep -E "error|panicked" "$d/analyze.err" | head -1 | tr '\t' ' ' | cut -c1-200)
        [ $rc -eq 124 ] && why="analyze over ${l} s"
        printf '%s\tall\tanalyze-failed\t%s\t\t\t\t\t\t\t\t\t%s (rc %s)\t%s\n' "$shader" "$ceiling" "$why" "$rc" "$secs" >>"$T"
        echo "$shader: analyze rc=$rc ($secs s)"
        continue
    fi
    for b in 0.01 0.03; do
        e="$d/emit$b.json"
        l=$(limit)
        if [ "$l" -lt 3 ]; then
            printf '%s\t%s\tno-time\t%s\t\t\t\t\t\t\t\t\tTOTAL_S spent before this emit\t%s\n' "$shader" "$b" "$ceiling" "$secs" >>"$T"
            continue
        fi
        run "$l" "$R" emit --profile "$d/p.profile.json" --max-error "$b" --out "$d/e$b" \
            --verify --session "$session" --json >"$e" 2>"$d/emit$b.err"
        erc=$?
        status=ok; [ $erc -ne 0 ] && status="emit-rc-$erc"
        [ -z "$(field "$e" node)" ] && [ $erc -eq 0 ] && status=original
        printf '%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\n' "$shader" "$b" "$status" "$ceiling" \
            "$(field "$e" node)" "$(field "$e" strategy)" "$(field "$e" delta_n)" \
            "$(field "$e" measured_speedup)" "$(field "$e" measured_speedup_ci95.0)" \
            "$(field "$e" measured_speedup_ci95.1)" "$(field "$e" measured_error)" \
            "$(field "$e" measured_psnr)" "$(field "$e" reason | tr '\t' ' ' | cut -c1-160)" "$secs" >>"$T"
    done
    echo "$shader: $(tail -n 2 "$T" | cut -f3,8 | tr '\n' ' ') ($secs s)"
done
[ ${#not_run[@]} -gt 0 ] && echo "not run (TOTAL_S=$TOTAL_S spent): ${not_run[*]}"
exit 0
