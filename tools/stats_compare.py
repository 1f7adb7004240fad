#!/usr/bin/env python3
"""Compare two sets of `epi render --stats` JSON files (e.g. a base and a changed binary, run
alternately over the same frames: `--sync` runs give the same frames for the same seed): per
scene and size, the best (minimum) of each side's per-run medians of the named stages_ms
entries, and their ratio, as a Markdown table.

  tools/stats_compare.py --base base_*.json --new new_*.json [--stage sampling --stage total]
"""
import argparse
import json
import os


def best_medians(files, stages):
    best = {}
    for name in files:
        with open(name) as f:
            stats = json.load(f)
        key = f"{os.path.basename(stats['scene'])} {stats['width']}x{stats['height']}"
        for stage in stages:
            ms = stats["stages_ms"][stage] if stage in stats["stages_ms"] else stats[f"{stage}_ms"]  # e.g. integrate_ms
            best[(key, stage)] = min(best.get((key, stage), ms), ms)
    return best


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--base", nargs="+", required=True)
    parser.add_argument("--new", nargs="+", required=True)
    parser.add_argument("--stage", action="append", help="a stages_ms entry, or X for a top-level X_ms such as integrate_ms (default: sampling, points, total)")
    args = parser.parse_args()
    stages = args.stage or ["sampling", "points", "total"]
    base, new = best_medians(args.base, stages), best_medians(args.new, stages)
    print("| run | stage | base (ms) | new (ms) | new / base | base / new |")
    print("|---|---|---|---|---|---|")
    for key, stage in sorted(base):
        if (key, stage) not in new:
            continue
        b, n = base[(key, stage)], new[(key, stage)]
        print(f"| {key} | {stage} | {b:.2f} | {n:.2f} | {n / b:.3f} | {b / n:.2f}x |")


if __name__ == "__main__":
    main()
