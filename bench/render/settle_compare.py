#!/usr/bin/env python3
"""Two settings of async_along_path.py --settle side by side, in absolute terms.

async_along_path.py's settle table counts the frames until each setting comes within 1.1x of its
own still run; where a setting changes the still run too (docs/render.md, "Idle shading at rest")
those counts do not compare. This prints, per scene, the RMSE of each setting at the stop and
+1 ... +N frames after it (means over the files' runs, weighted by their run counts), the ratio
new / base at each, and the milliseconds a frame, from one or more settle outputs:

  bench/render/settle_compare.py --base SETTING --new SETTING FILE...
"""
import argparse
import collections
import sys


def rows(path):
    header = None
    for line in open(path):
        cells = [c.strip() for c in line.strip().strip("|").split("|")]
        if line.startswith("| scene | setting"):
            header = cells
        elif header and line.startswith("|") and not line.startswith("|---") and len(cells) == len(header):
            yield dict(zip(header, cells))


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--base", required=True, help="setting of the baseline rows (as printed, e.g. --rest-sample-budget=0.02)")
    ap.add_argument("--new", required=True, help="setting of the compared rows (e.g. default)")
    ap.add_argument("files", nargs="+")
    args = ap.parse_args()
    sums = collections.defaultdict(lambda: collections.defaultdict(float))
    runs = collections.defaultdict(int)
    columns = None
    for path in args.files:
        for row in rows(path):
            if row["setting"] not in (args.base, args.new):
                continue
            if columns is None:
                columns = [c for c in row if c.startswith("+")] + ["ms a frame"]
            key = (row["scene"], row["setting"])
            n = int(row["runs"])
            runs[key] += n
            for c in columns:
                sums[key][c] += n * float(row[c])
    if columns is None:
        sys.exit("no rows of either setting")
    print("| scene | runs | " + " | ".join(f"{c} base / new (ratio)" for c in columns) + " |")
    print("|---|---|" + "---|" * len(columns))
    for scene in sorted({s for s, _ in runs}):
        b, n = (scene, args.base), (scene, args.new)
        if b not in runs or n not in runs:
            continue
        cells = []
        for c in columns:
            vb, vn = sums[b][c] / runs[b], sums[n][c] / runs[n]
            digits = 1 if c == "ms a frame" else 4
            cells.append(f"{vb:.{digits}f} / {vn:.{digits}f} ({vn / vb:.2f})" if vb > 0 else f"{vb} / {vn}")
        print(f"| {scene} | {runs[n]} | " + " | ".join(cells) + " |")


if __name__ == "__main__":
    main()
