#!/usr/bin/env python3
"""Compare two sets of Google Benchmark JSON runs (e.g. a base and a changed binary, run
alternately on a loaded machine): the best (minimum) real time per benchmark in each set and
their ratio, as a Markdown table.

  tools/bench_compare.py --base base-*.json --new new-*.json
"""
import argparse
import json


def best_times(files):
    best = {}
    for name in files:
        with open(name) as f:
            for b in json.load(f)["benchmarks"]:
                if b.get("run_type") == "aggregate":
                    continue
                key = b["run_name"] if "run_name" in b else b["name"]
                t = b["real_time"]
                best[key] = min(best.get(key, t), t)
                unit = b.get("time_unit", "ns")
    return best, unit


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--base", nargs="+", required=True)
    parser.add_argument("--new", nargs="+", required=True)
    args = parser.parse_args()
    base, unit = best_times(args.base)
    new, _ = best_times(args.new)
    print(f"| benchmark | base ({unit}) | new ({unit}) | new / base |")
    print("|---|---|---|---|")
    for key in base:
        if key in new:
            print(f"| {key} | {base[key]:.3f} | {new[key]:.3f} | {new[key] / base[key]:.3f} |")


if __name__ == "__main__":
    main()
