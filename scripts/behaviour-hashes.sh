#!/usr/bin/env bash
# Hashes of what reproj writes without timing, for checking that a refactor changes no behaviour:
#
#   bash scripts/behaviour-hashes.sh BINARY OUT > hashes.txt   (then diff two binaries' lists)
#
# emit from every profile under out/ and the report's test profile at four budgets (the files
# written and the JSON report, with OUT taken out of the paths they name), and instance of each shader under shaders/ for every
# strategy (root and node 3). GPU-free: no render.
set -uo pipefail
bin="$(realpath "$1")"; out="$2"
cd "$(dirname "$0")/.."
rm -rf "$out"; mkdir -p "$out"
# PROFILES (a grep pattern) keeps some of them, e.g. PROFILES='^out/(t|corpus)/'.
profiles=$( (ls crates/reproj-report/tests/data/*.profile.json; find out -name '*.profile.json' 2>/dev/null) | sort | grep -E "${PROFILES:-.}")
for p in $profiles; do
    for b in 0.002 0.01 0.03 0.1; do
        d="$out/emit-$(echo "$p" | tr / _)-$b"
        "$bin" emit --profile "$p" --max-error "$b" --out "$d" --json -q > "$d.json" 2> "$d.err"
        echo "emit $p $b rc=$? $(sed -e "s#$out/[^\"]*##g" "$d.json" | sha256sum | cut -c1-16) $(cat "$d"/* 2>/dev/null | sed -e "s#$out##g" | sha256sum | cut -c1-16)"
    done
done
for s in shaders/*.wgsl; do
    for st in 3pass 2pass fused; do
        for n in root 3; do
            d="$out/inst-$(basename "$s")-$st-$n"
            "$bin" instance "$s" --node "$n" --strategy "$st" --out "$d" -q > /dev/null 2> "$d.err"
            echo "instance $s $st $n rc=$? $(cat "$d"/* 2>/dev/null | sha256sum | cut -c1-16)"
        done
    done
done
