#!/usr/bin/env python3
"""Stage times of `epi render --stats` runs, side by side, as a Markdown table.

  bench/render/stats_stages.py [--stages points,total] LABEL=FILE[,FILE...] ...

Each LABEL names a setting; its files are runs of it (alternated with the other settings' runs
in one session). One row per label: each stage's per-frame times (the files' `stages_ms`, the
medians over the run's frames) as the range over the files, and the mean of the files' totals
over the first label's (the baseline, measured in the same session).
"""
import argparse
import json
import statistics
import sys


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--stages", default="points,total", help="stages_ms keys, comma-separated")
    parser.add_argument("runs", nargs="+", help="LABEL=FILE[,FILE...]")
    args = parser.parse_args()
    stages = args.stages.split(",")
    rows = []
    for run in args.runs:
        label, _, files = run.partition("=")
        if not files:
            sys.exit(f"stats_stages.py: {run}: expected LABEL=FILE[,FILE...]")
        times = {s: [] for s in stages}
        for name in files.split(","):
            with open(name) as f:
                measured = json.load(f)["stages_ms"]
            for s in stages:
                if s not in measured:
                    sys.exit(f"stats_stages.py: {name}: no stage '{s}' in stages_ms")
                times[s].append(measured[s])
        rows.append((label, times))
    base_total = statistics.mean(rows[0][1][stages[-1]])
    print("| setting | runs | " + " | ".join(f"{s} ms" for s in stages) + f" | {stages[-1]} / first |")
    print("|---|---|" + "---|" * len(stages) + "---|")
    for label, times in rows:
        cells = [f"{min(v):.1f}-{max(v):.1f}" if len(v) > 1 else f"{v[0]:.1f}" for v in (times[s] for s in stages)]
        ratio = statistics.mean(times[stages[-1]]) / base_total
        print(f"| {label} | {len(times[stages[0]])} | " + " | ".join(cells) + f" | {ratio:.3f} |")


if __name__ == "__main__":
    main()
