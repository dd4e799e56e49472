#!/usr/bin/env bash
# The corpus table docs/notebook/corpus.md gives ("The corpus, end to end"): for every corpus shader that
# has a session (tests/corpus/shaders/*.wgsl and glsl/*.frag with tests/corpus/sessions/), a
# short analyze (training Δn 2, 10, 26, 50, at most 4 nodes, no sets), then emit --verify at 0.01
# and 0.03; one line per shader and budget in OUT/corpus.tsv: the ceiling the analysis measured,
# the choice, the verified speedup with its interval and error, or why the original was kept.
# Each shader has its own time limit (LIMIT_S, default 120); a failure is a line too.
#
#   bash scripts/corpus-speedups.sh [OUT] [FILTER]
#
# REPROJ names the binary (default target/release/reproj); FILTER keeps the shaders whose path
# contains it. Summarize with `python3 scripts/corpus-table.py OUT/corpus.tsv`.
set -uo pipefail
cd "$(dirname "$0")/.."
R="${REPROJ:-target/release/reproj}"
OUT="${1:-out/corpus}"
FILTER="${2:-}"
LIMIT_S="${LIMIT_S:-120}"
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
for shader in tests/corpus/shaders/*.wgsl tests/corpus/shaders/glsl/*.frag; do
    case "$shader" in *"$FILTER"*) ;; *) continue ;; esac
    stem=$(basename "${shader%.*}")
    sub=""; [[ "$shader" == */glsl/* ]] && sub="glsl/"
    session="tests/corpus/sessions/$sub$stem.json"
    [ -f "$session" ] || continue
    d="$OUT/$sub$stem"
    mkdir -p "$d"
    t0=$(date +%s)
    timeout "$LIMIT_S" "$R" analyze "$shader" --session "$session" --out "$d/p.profile.json" \
        --delta-n 2,10,26,50 --holdout 6 --max-nodes 4 --no-sets --no-charts --fresh --json \
        >"$d/analyze.json" 2>"$d/analyze.err"
    rc=$?
    secs=$(($(date +%s) - t0))
    ceiling=$(field "$d/p.profile.json" ceiling.speedup)
    if [ $rc -ne 0 ]; then
        why=$(grep -E "error|panicked" "$d/analyze.err" | head -1 | tr '\t' ' ' | cut -c1-200)
        [ $rc -eq 124 ] && why="analyze over ${LIMIT_S} s"
        printf '%s\tall\tanalyze-failed\t%s\t\t\t\t\t\t\t\t\t%s (rc %s)\t%s\n' "$shader" "$ceiling" "$why" "$rc" "$secs" >>"$T"
        echo "$shader: analyze rc=$rc ($secs s)"
        continue
    fi
    for b in 0.01 0.03; do
        timeout "$LIMIT_S" "$R" emit --profile "$d/p.profile.json" --max-error "$b" --out "$d/e$b" \
            --verify --session "$session" --json >"$d/emit$b.json" 2>"$d/emit$b.err"
        erc=$?
        e="$d/emit$b.json"
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
