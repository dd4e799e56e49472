#!/usr/bin/env python3
"""Print an analysis journal (JSON Lines) made from a profile's measurements, as `reproj analyze`
writes one: the header (key "fuzz", what the `journal` target checks against), the original's
record, the first node measurements (three: libFuzzer runs faster on small inputs), a set's, one
failure, and a torn last line."""
import json
import sys

p = json.load(open(sys.argv[1]))
lines = [{"schema": "reproj.journal", "version": 2, "key": "fuzz"}]
o = p.get("original")
if o:
    lines.append({"node": 4294967295, "strategy": "original", "block": 0, "delta_n": 1,
                  "measurement": None, "pass_ms": [], "failure": None, "original": o})
for n in p.get("nodes", []):
    for m in n.get("measurements", []):
        lines.append({"node": n["id"], "strategy": n.get("strategy", "3pass"),
                      "block": n.get("block") or p.get("block", 4), "delta_n": m["delta_n"],
                      "measurement": m, "pass_ms": [0.5, 0.25], "failure": None})
for s in p.get("sets", []):
    for m in s.get("measurements", []):
        lines.append({"node": s["members"][0], "strategy": s.get("strategy", "3pass"),
                      "block": p.get("block", 4), "delta_n": m["delta_n"], "set": s["members"],
                      "measurement": m, "pass_ms": [], "failure": None})
lines = lines[:5] + [l for l in lines[5:] if "set" in l][:1]
lines.append({"node": 1, "strategy": "fused", "block": 4, "delta_n": 2, "frames": 4,
              "measurement": None, "pass_ms": [], "failure": "the variant does not compile"})
text = "".join(json.dumps(l, separators=(",", ":")) + "\n" for l in lines)
sys.stdout.write(text + text.splitlines()[-2][:40])
