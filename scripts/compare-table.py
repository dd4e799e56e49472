#!/usr/bin/env python3
"""The markdown table of scripts/compare-table.sh's runs: one row per shader, target and method.

    python3 scripts/compare-table.py OUT
"""
import glob
import json
import os
import sys


def fmt(v, spec):
    return "–" if v is None else format(v, spec)


def main(out):
    rows = []
    for path in sorted(glob.glob(os.path.join(out, "*", "x*", "compare.json"))):
        with open(path) as f:
            r = json.load(f)
        name = path.split(os.sep)[-3]
        target = r["target_speedup"]
        floor = r.get("original_vs_supersampled") or {}
        rows.append(
            f"| {name} | {target:g}× | original | 1.00× | | | "
            f"{fmt(floor.get('psnr'), '.1f')} | {fmt(floor.get('flip'), '.3f')} | "
            f"the floor: one sample against {r.get('supersample', 0)} |"
        )
        for m in r["methods"]:
            ci = m.get("speedup_ci95")
            speed = f"{m['speedup']:.2f}× [{ci[0]:.2f}, {ci[1]:.2f}]" if ci else f"{m['speedup']:.2f}×"
            if not m["reached_target"]:
                speed += " (not reached)"
            ss = m.get("supersampled") or {}
            split = ss.get("split")
            extra = f"still {split['still_psnr']:.1f} / moving {split['moving_psnr']:.1f} dB; " if split else ""
            rows.append(
                f"| {name} | {target:g}× | {m['method']} | {speed} | {m['psnr']:.1f} | "
                f"{fmt(m.get('flip'), '.3f')} | {fmt(ss.get('psnr'), '.1f')} | {fmt(ss.get('flip'), '.3f')} | "
                f"{extra}{m['setting']} |"
            )
    print("| shader | target | method | speedup [95 % CI] | PSNR dB (1 spp) | ꟻLIP (1 spp) | PSNR dB (supersampled) | ꟻLIP (supersampled) | setting |")
    print("|---|---|---|---|---|---|---|---|---|")
    print("\n".join(rows))


if __name__ == "__main__":
    main(sys.argv[1] if len(sys.argv) > 1 else "out/compare-table")
