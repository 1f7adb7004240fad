#!/usr/bin/env python3
"""Compare two sets of Google Benchmark JSON runs (e.g. a base and a changed binary, run
alternately on a loaded machine): the best (minimum) real time per benchmark in each set and
their ratio, as a Markdown table. `--time cpu` compares CPU times instead (the benchmark
thread's: on a loaded machine the fairer figure for one-thread runs). `--counter NAME` compares
a user counter instead (e.g. `complex_cpu_ms`, one stage of BM_Filters), its minimum likewise;
`--label` adds each benchmark's label (BM_Filters': the kernel, edges and threads).

  tools/bench_compare.py --base base-*.json --new new-*.json [--time cpu] [--counter NAME] [--label]
"""
import argparse
import json


def best_times(files, field, labels=None):
    best, unit = {}, "ns"
    for name in files:
        with open(name) as f:
            for b in json.load(f)["benchmarks"]:
                if b.get("run_type") == "aggregate" or field not in b:
                    continue
                key = b["run_name"] if "run_name" in b else b["name"]
                t = b[field]
                best[key] = min(best.get(key, t), t)
                unit = b.get("time_unit", "ns")
                if labels is not None:
                    labels[key] = b.get("label", "")
    return best, unit


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--base", nargs="+", required=True)
    parser.add_argument("--new", nargs="+", required=True)
    parser.add_argument("--time", choices=["real", "cpu"], default="real")
    parser.add_argument("--counter", help="compare this user counter instead of a time")
    parser.add_argument("--label", action="store_true", help="a column with each benchmark's label")
    args = parser.parse_args()
    field = args.counter or args.time + "_time"
    labels = {}
    base, unit = best_times(args.base, field, labels)
    new, _ = best_times(args.new, field)
    what = args.counter or f"{args.time}, {unit}"
    label_head, label_rule = (" label |", "---|") if args.label else ("", "")
    print(f"| benchmark |{label_head} base ({what}) | new ({what}) | new / base | base / new |")
    print(f"|---|{label_rule}---|---|---|---|")
    for key in base:
        if key in new:
            label = f" {labels.get(key, '')} |" if args.label else ""
            ratio = f"{new[key] / base[key]:.3f}" if base[key] else "-"
            speedup = f"{base[key] / new[key]:.2f}x" if new[key] else "-"
            print(f"| {key} |{label} {base[key]:.3f} | {new[key]:.3f} | {ratio} | {speedup} |")


if __name__ == "__main__":
    main()
