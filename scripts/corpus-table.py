#!/usr/bin/env python3
"""Summarize scripts/corpus-speedups.sh's TSV: per budget, how many shaders reach 1.2x (the
verified speedup), the median, and the reasons of the rest; then the table rows as Markdown."""
import csv
import statistics
import sys

rows = list(csv.DictReader(open(sys.argv[1]), delimiter="\t"))
shaders = sorted({r["shader"] for r in rows})
print(f"{len(shaders)} shaders")
if not rows:
    sys.exit(0)  # a run cut before its first shader finished: nothing to summarize
for b in ("0.01", "0.03"):
    at = [r for r in rows if r["budget"] in (b, "all")]
    speed = []
    for r in at:
        s = float(r["speedup"]) if r["speedup"] else 1.0
        speed.append(s)
    reach = sum(1 for s in speed if s >= 1.2)
    median = f"{statistics.median(speed):.2f}x" if speed else "-"
    print(f"budget {b}: {reach} of {len(at)} reach >= 1.2x; median {median}")
    kinds = {}
    for r in at:
        if r["speedup"] and float(r["speedup"]) >= 1.2:
            continue
        why = r["status"]
        if r["status"] == "original":
            why = "cannot pay (ceiling)" if "cannot pay" in r["reason"] else "original kept: " + r["reason"][:60]
        elif r["status"] == "ok":
            why = "below 1.2x"
        kinds[why] = kinds.get(why, 0) + 1
    for k, n in sorted(kinds.items(), key=lambda x: -x[1]):
        print(f"  {n:3d}  {k}")
print()
print("| shader | ceiling | 0.01: choice, verified | 0.03: choice, verified |")
print("| --- | ---: | --- | --- |")
for s in shaders:
    cells = []
    ceiling = ""
    for b in ("0.01", "0.03"):
        r = next((r for r in rows if r["shader"] == s and r["budget"] in (b, "all")), None)
        if r is None:
            cells.append("—")
            continue
        ceiling = r["ceiling"] and f"{float(r['ceiling']):.2f}x"
        if r["status"] == "ok":
            cells.append(f"{r['node']} {r['strategy']} Δn {r['delta_n']}: **{float(r['speedup']):.2f}x** [{float(r['lo']):.2f}, {float(r['hi']):.2f}], {float(r['psnr'] or 0):.1f} dB")
        elif r["status"] == "original":
            cells.append("original" + (" (cannot pay)" if "cannot pay" in r["reason"] else f" ({r['reason'][:50]})"))
        else:
            cells.append(f"{r['status']}: {r['reason'][:60]}")
    print(f"| {s.replace('tests/corpus/shaders/', '')} | {ceiling} | {cells[0]} | {cells[1]} |")
