#!/usr/bin/env python3
"""Turns render_points_bench JSON into the table of docs/performance.md ("Point processing"),
so that no figure there is typed by hand.

  build/bin/render_points_bench --benchmark_format=json > points.json
  python3 bench/render/points_table.py points.json

Per row: median ms per frame of each stage, the reference path's then the fast path's, and the
ratio reference / fast of the totals. With --baseline BEFORE.json (render_points_bench of an
earlier build, same filter): the fast path's stages before -> after and the ratio of the totals. One-thread figures are CPU times of the working thread,
two-thread figures wall times (see bench/render/points_bench.cpp).
"""
import json
import sys

STAGES = ["project", "cull", "occlusion", "fill", "total"]
SIZES = {(512, 512): "512²", (1920, 1080): "1080p", (3840, 2160): "4K"}


def load_rows(paths):
    rows, load = [], []
    for path in paths:
        with open(path) as f:
            data = json.load(f)
        for b in data["benchmarks"]:
            if b.get("run_type", "iteration") != "iteration" or b.get("error_occurred"):
                continue
            args = [int(a) for a in b["name"].split("/")[1:6]]
            rows.append((args, b))
        load = data.get("context", {}).get("load_avg", [])
    return rows, load


def main(paths):
    if paths and paths[0] == "--baseline":
        return compare(paths[1], paths[2:])
    rows, load = load_rows(paths)
    print("| scene | size | mode | threads | " + " | ".join(f"{s} ref → fast" for s in STAGES) + " | speed-up | points |")
    print("|---|---|---|---|" + "---|" * len(STAGES) + "---|---|")
    for args, b in rows:
        scene, mode = b["label"].split(" ")
        size = SIZES.get((args[1], args[2]), f"{args[1]}x{args[2]}")
        cells = []
        for s in STAGES:
            ref, fast = b[f"ref_{s}_ms"], b[f"{s}_ms"]
            cells.append("" if ref == 0 and fast == 0 else f"{ref:.1f} → {fast:.1f}")
        print(f"| {scene} | {size} | {mode} | {args[4]} | " + " | ".join(cells) +
              f" | {b['speedup']:.1f}x | {b['points'] / 1e3:.0f}k |")
    if load:
        print(f"\nLoad average when the run started (1, 5, 15 min): {', '.join(f'{x:.1f}' for x in load)}.")


def compare(before_path, after_paths):
    before = {b["name"]: b for _, b in load_rows([before_path])[0]}
    rows, load = load_rows(after_paths)
    print("| scene | size | mode | threads | " + " | ".join(f"{s} before → after" for s in STAGES) + " | speed-up |")
    print("|---|---|---|---|" + "---|" * len(STAGES) + "---|")
    for args, b in rows:
        old = before.get(b["name"])
        if old is None:
            continue
        scene, mode = b["label"].split(" ")
        size = SIZES.get((args[1], args[2]), f"{args[1]}x{args[2]}")
        cells = []
        for s in STAGES:
            cells.append("" if old[f"{s}_ms"] == 0 and b[f"{s}_ms"] == 0 else f"{old[f'{s}_ms']:.1f} → {b[f'{s}_ms']:.1f}")
        print(f"| {scene} | {size} | {mode} | {args[4]} | " + " | ".join(cells) +
              f" | {old['total_ms'] / max(b['total_ms'], 1e-9):.2f}x |")
    if load:
        print(f"\nLoad average when the second run started (1, 5, 15 min): {', '.join(f'{x:.1f}' for x in load)}.")


if __name__ == "__main__":
    main(sys.argv[1:])
