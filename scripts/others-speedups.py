#!/usr/bin/env python3
"""The speedup table of the shaders written by others (tests/others, fetched by
scripts/fetch-others.sh): for every fragment entry point, read with its engine's options
(tests/others/options.json: defs, a defs preset, import paths, include folders), a session from
`reproj session init`, a short analyze (as scripts/corpus-speedups.sh: training Δn 2, 10, 26, 50, at
most 4 nodes, no sets), then `emit --verify` at 0.01 and 0.03. One line per entry point and budget
in OUT/corpus.tsv, in corpus-speedups.sh's columns (the shader column is FILE or FILE:ENTRY), so
that `python3 scripts/corpus-table.py OUT/corpus.tsv` summarizes it; a step that fails is a line
too (`session-failed`, `analyze-failed`, with the first error line), and so is an entry point
with nothing worth caching (`nothing-cacheable`, with analyze's reason).

    python3 scripts/others-speedups.py [OUT] [FILTER]

REPROJ names the binary (default target/release/reproj), REPROJ_OTHERS_CORPUS the set's root
(default tests/others), LIMIT_S each step's time limit (default 90), FRAMES the sessions' frames
(default 60). FILTER keeps the files whose path contains it. Entry points already in the TSV are
skipped, so a stopped run continues where it stopped.
"""
import csv
import functools
import json
import os
import re
import subprocess
import sys
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
R = os.environ.get("REPROJ", os.path.join(ROOT, "target/release/reproj"))
SET = os.environ.get("REPROJ_OTHERS_CORPUS", os.path.join(ROOT, "tests/others"))
LIMIT = int(os.environ.get("LIMIT_S", "90"))
FRAMES = os.environ.get("FRAMES", "60")
OUT = sys.argv[1] if len(sys.argv) > 1 else os.path.join(ROOT, "out/others")
FILTER = sys.argv[2] if len(sys.argv) > 2 else ""
COLUMNS = ["shader", "budget", "status", "ceiling", "node", "strategy", "delta_n", "speedup",
           "lo", "hi", "error", "psnr", "reason", "analyze_s"]


@functools.cache
def engine_options():
    """tests/others/options.json, read once."""
    return json.load(open(os.path.join(SET, "options.json")))


def options(rel, entry):
    """The reproj flags a user of the file's engine passes (tests/others/options.json)."""
    opts = engine_options()
    flags = []
    for p in opts["projects"]:
        if not any(rel.startswith(pre) for pre in p.get("prefixes", [])):
            continue
        if p.get("defs_preset"):
            flags += ["--defs-preset", p["defs_preset"]]
        for d in p.get("defs", []):
            flags += ["--def", d]
        for d in p.get("import_paths", []) + p.get("include_dirs", []):
            flags += ["-I", os.path.join(SET, d)]
    own = opts.get("files", {}).get(rel, {})
    for d in own.get("defs", []) + own.get("entries", {}).get(entry or "", []):
        flags += ["--def", d]
    return flags


def entries(path):
    """The fragment entry points of a WGSL file (None for GLSL: its `main`)."""
    if not path.endswith(".wgsl"):
        return [None]
    text = open(path, encoding="utf-8", errors="replace").read()
    names = re.findall(r"@fragment\s*(?:@[\w()., ]+\s*)*fn\s+(\w+)", text)
    # An entry point defined in two `#ifdef` branches is one entry point.
    return list(dict.fromkeys(names)) or [None]


def run(args, out_path=None):
    """Run reproj under the time limit; (exit code, stdout, stderr, seconds)."""
    t0 = time.time()
    try:
        p = subprocess.run([R] + args, capture_output=True, text=True, timeout=LIMIT)
        rc, so, se = p.returncode, p.stdout, p.stderr
    except subprocess.TimeoutExpired as e:
        rc, so, se = 124, "", f"over {LIMIT} s"
    if out_path:
        open(out_path, "w").write(so)
    return rc, so, se, round(time.time() - t0)


def first_error(text):
    for line in text.splitlines():
        if "error" in line or "panicked" in line or line.startswith("over "):
            return line.replace("\t", " ")[:200]
    return text.strip().splitlines()[-1][:200] if text.strip() else ""


def field(doc, path):
    v = doc
    for k in path.split("."):
        if isinstance(v, dict):
            v = v.get(k)
        elif isinstance(v, list) and k.isdigit() and int(k) < len(v):
            v = v[int(k)]
        else:
            return ""
        if v is None:
            return ""
    return round(v, 4) if isinstance(v, float) else v


def main():
    os.makedirs(OUT, exist_ok=True)
    tsv = os.path.join(OUT, "corpus.tsv")
    done = set()
    if os.path.exists(tsv):
        done = {r["shader"] for r in csv.DictReader(open(tsv), delimiter="\t")}
    else:
        open(tsv, "w").write("\t".join(COLUMNS) + "\n")
    files = sorted(
        os.path.join(sub, f)
        for sub in ("glsl", "wgsl")
        if os.path.isdir(os.path.join(SET, sub))
        for f in os.listdir(os.path.join(SET, sub))
        if f.endswith((".frag", ".glsl", ".wgsl"))
    )
    if not files:
        sys.exit(f"others-speedups: no shaders under {SET} (run scripts/fetch-others.sh first)")
    for rel in files:
        if FILTER not in rel:
            continue
        path = os.path.join(SET, rel)
        for entry in entries(path):
            name = rel if entry is None else f"{rel}:{entry}"
            if name in done:
                continue
            d = os.path.join(OUT, name.replace("/", "_").replace(":", "__"))
            os.makedirs(d, exist_ok=True)
            flags = options(rel, entry) + (["--entry", entry] if entry else [])
            line = dict.fromkeys(COLUMNS, "")
            line.update(shader=name, budget="all")
            session = os.path.join(d, "session.json")
            rc, _, se, _ = run(["session", "init", path, "-o", session, "--force", "--frames", FRAMES, "-q"] + flags)
            if rc != 0:
                line.update(status="session-failed", reason=f"{first_error(se)} (rc {rc})")
                write(tsv, [line], name)
                continue
            profile = os.path.join(d, "p.profile.json")
            rc, _, se, secs = run(["analyze", path, "--session", session, "--out", profile,
                                   "--delta-n", "2,10,26,50", "--holdout", "6", "--max-nodes", "4",
                                   "--no-sets", "--no-charts", "--fresh", "--json"] + flags,
                                  os.path.join(d, "analyze.json"))
            ceiling = ""
            try:
                ceiling = field(json.load(open(profile)), "ceiling.speedup")
            except (OSError, ValueError):
                pass
            if rc != 0:
                line.update(status="analyze-failed", ceiling=ceiling, analyze_s=secs,
                            reason=f"{first_error(se)} (rc {rc})")
                write(tsv, [line], name)
                continue
            if not os.path.exists(profile):
                # No cacheable node: analyze says why (`no_cacheable`) and writes no profile.
                try:
                    why = json.load(open(os.path.join(d, "analyze.json"))).get("no_cacheable", [])
                except (OSError, ValueError):
                    why = []
                line.update(status="nothing-cacheable", analyze_s=secs,
                            reason=" ".join(w.strip() for w in why[1:])[:160])
                write(tsv, [line], name)
                continue
            rows = []
            for b in ("0.01", "0.03"):
                e = os.path.join(d, f"emit{b}.json")
                erc, _, ese, _ = run(["emit", "--profile", profile, "--max-error", b, "--out",
                                      os.path.join(d, f"e{b}"), "--verify", "--session", session,
                                      "--json"], e)
                try:
                    doc = json.load(open(e))
                except (OSError, ValueError):
                    doc = {}
                status = "ok" if erc == 0 else f"emit-rc-{erc}"
                if erc == 0 and not doc.get("node"):
                    status = "original"
                reason = str(field(doc, "reason") or (first_error(ese) if erc else ""))
                rows.append(dict(
                    shader=name, budget=b, status=status, ceiling=ceiling,
                    node=field(doc, "node"), strategy=field(doc, "strategy"),
                    delta_n=field(doc, "delta_n"), speedup=field(doc, "measured_speedup"),
                    lo=field(doc, "measured_speedup_ci95.0"),
                    hi=field(doc, "measured_speedup_ci95.1"),
                    error=field(doc, "measured_error"), psnr=field(doc, "measured_psnr"),
                    reason=reason.replace("\t", " ")[:160], analyze_s=secs))
            write(tsv, rows, name)


def write(tsv, rows, name):
    with open(tsv, "a") as f:
        for r in rows:
            f.write("\t".join(str(r[c]).replace("\n", " ") for c in COLUMNS) + "\n")
    print(f"{name}: " + ", ".join(f"{r['budget']} {r['status']} {r['speedup']}" for r in rows),
          flush=True)


if __name__ == "__main__":
    main()
