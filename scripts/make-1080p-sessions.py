#!/usr/bin/env python3
"""Write tests/corpus/sessions/1080p/: every corpus session (tests/corpus/sessions/*.json and
glsl/*.json) at 1920x1080, for GPU figures (at 128x128 a GPU only measures overheads). Only the
resolution and the description change: the motion, frames and inputs are the originals', and
depth passes without a size follow the new resolution. Run from the repository root:
    python3 scripts/make-1080p-sessions.py          # (re)write them
    python3 scripts/make-1080p-sessions.py --check  # exit 1 where one is missing or stale
"""
import glob
import json
import os
import sys

SRC = "tests/corpus/sessions"
DST = os.path.join(SRC, "1080p")
RESOLUTION = [1920, 1080]


def derived(path):
    with open(path, encoding="utf-8") as f:
        session = json.load(f)
    session["resolution"] = RESOLUTION
    session["description"] = (
        session.get("description", "").rstrip()
        + f" At 1920×1080 for GPU figures (slow on a CPU rasterizer): {path} with only its"
        " resolution changed, written by scripts/make-1080p-sessions.py."
    ).lstrip()
    return json.dumps(session, indent=2, ensure_ascii=False) + "\n"


def main():
    check = "--check" in sys.argv[1:]
    stale = []
    sources = sorted(glob.glob(f"{SRC}/*.json") + glob.glob(f"{SRC}/glsl/*.json"))
    for src in sources:
        dst = os.path.join(DST, os.path.relpath(src, SRC))
        text = derived(src)
        try:
            with open(dst, encoding="utf-8") as f:
                current = f.read()
        except FileNotFoundError:
            current = None
        if current == text:
            continue
        if check:
            stale.append(dst)
            continue
        os.makedirs(os.path.dirname(dst), exist_ok=True)
        with open(dst, "w", encoding="utf-8") as f:
            f.write(text)
        print(f"wrote {dst}")
    if check and stale:
        print("stale or missing (run python3 scripts/make-1080p-sessions.py):", *stale, sep="\n  ")
        sys.exit(1)
    print(f"{len(sources)} sessions at 1920x1080 in {DST}")


if __name__ == "__main__":
    main()
