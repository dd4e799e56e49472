#!/usr/bin/env python3
"""How well GLSL nodes are placed: over every GLSL file of the corpus (and the others' corpus when
fetched, tests/others/glsl), the nodes `reproj nodes F --all --json` lists, how many have no place
(0:0) and how many show their whole source line as text (an input at its declaration, a compound
assignment and values glslang spells in steps legitimately do).

    python3 scripts/glsl-node-places.py [REPROJ_BINARY]   # default target/debug/reproj
"""
import glob
import json
import subprocess
import sys

binary = sys.argv[1] if len(sys.argv) > 1 else "target/debug/reproj"
files = sorted(
    glob.glob("tests/others/glsl/**/*.frag", recursive=True)
    + glob.glob("tests/others/glsl/**/*.glsl", recursive=True)
    + [f for f in glob.glob("tests/**/*.frag", recursive=True) if "/others/" not in f]
)
total = unplaced = whole = read = 0
for f in files:
    r = subprocess.run([binary, "nodes", f, "--all", "--json"], capture_output=True, text=True, timeout=300)
    if r.returncode != 0:
        continue
    read += 1
    lines = open(f, errors="replace").read().split("\n")
    for n in json.loads(r.stdout)["nodes"]:
        total += 1
        if n["line"] == 0:
            unplaced += 1
            continue
        line = lines[n["line"] - 1].strip() if n["line"] <= len(lines) else ""
        line = line[:-1].rstrip() if line.endswith(";") else line
        if n["text"] == " ".join(line.split()) and any(c in line for c in "=(") and not n["text"].startswith(("vec", "mat")):
            whole += 1
print(f"{read} of {len(files)} files read, {total} nodes: {unplaced} at 0:0, {whole} with their whole line as text")
