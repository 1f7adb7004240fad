#!/usr/bin/env python3
"""Settling over seeds: reads `render_motion_quality --settle N` outputs (one file per seed) and
prints one Markdown row per scene and run: the mean display RMSE at the stop and at each
checkpoint after it, the still run's, and the frames it took to come within 1.5x and 1.1x of the
still run (mean and range over the seeds; "> N" counts as N + 1 in the mean and shows in the
range). docs/render.md, "Settling when the camera stops".

  bench/render/settle_table.py docs/data/settling/seed*.txt
"""
import re
import statistics
import sys


def rows(path):
    with open(path) as f:
        text = f.read()
    m = re.search(r"^Settling:.*?\n\n(\|.*?)(?:\n\n|\Z)", text, re.S | re.M)
    if not m:
        sys.exit(f"{path}: no settling table (run render_motion_quality with --settle N)")
    lines = [l for l in m.group(1).splitlines() if l.startswith("|")]
    header = [c.strip() for c in lines[0].strip("|").split("|")]
    for line in lines[2:]:
        cells = [c.strip() for c in line.strip("|").split("|")]
        yield header, dict(zip(header, cells))


def frames(cell, settle):
    cell = cell.strip()
    if cell.startswith(">"):
        return settle + 1, cell
    return (int(cell), cell) if cell.isdigit() else (None, cell)


def main():
    if len(sys.argv) < 2:
        sys.exit(__doc__)
    table, header = {}, None
    for path in sys.argv[1:]:
        for header, row in rows(path):
            table.setdefault((row["scene"], row["run"]), []).append(row)
    checkpoints = [h for h in header if h.startswith("+")]
    settle = int(checkpoints[-1][1:])
    print("| scene | run | seeds | " + " | ".join(checkpoints) + " | still | frames to 1.5x still | frames to 1.1x still |")
    print("|---|---|---|" + "---|" * (len(checkpoints) + 3))
    for (scene, run), found in table.items():
        means = [statistics.mean(float(r[c]) for r in found) for c in checkpoints]
        stills = [float(r["still"]) for r in found if r["still"]]
        still = f"{statistics.mean(stills):.4f}" if stills else ""
        cols = []
        for key in ("frames to 1.5x still", "frames to 1.1x still"):
            got = [frames(r[key], settle) for r in found]
            if any(v is None for v, _ in got):
                cols.append("")
                continue
            values = [v for v, _ in got]
            cols.append(f"{statistics.mean(values):.1f} ({min(got)[1]}-{max(got)[1]})")
        print(f"| {scene} | {run} | {len(found)} | " + " | ".join(f"{m:.4f}" for m in means) + f" | {still} | {cols[0]} | {cols[1]} |")


if __name__ == "__main__":
    main()
