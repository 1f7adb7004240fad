#!/usr/bin/env python3
"""Compare two sets of Google Benchmark JSON runs (e.g. a base and a changed binary, run
alternately on a loaded machine): the best (minimum) real time per benchmark in each set and
their ratio, as a Markdown table. `--time cpu` compares CPU times instead (the benchmark
thread's: on a loaded machine the fairer figure for one-thread runs); `--counter NAME` compares
a user counter instead (e.g. render_points_bench's project_ms), the best (least) per benchmark.

  tools/bench_compare.py --base base-*.json --new new-*.json [--time cpu | --counter NAME]
"""
import argparse
import json


def best_times(files, field):
    best, unit = {}, ""
    for name in files:
        with open(name) as f:
            for b in json.load(f)["benchmarks"]:
                if b.get("run_type") == "aggregate":
                    continue
                key = b["run_name"] if "run_name" in b else b["name"]
                if field not in b:
                    continue
                t = b[field]
                best[key] = min(best.get(key, t), t)
                unit = b.get("time_unit", "ns") if field.endswith("_time") else field
    return best, unit


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--base", nargs="+", required=True)
    parser.add_argument("--new", nargs="+", required=True)
    parser.add_argument("--time", choices=["real", "cpu"], default="real")
    parser.add_argument("--counter", help="a user counter to compare instead of a time")
    args = parser.parse_args()
    field = args.counter or args.time + "_time"
    base, unit = best_times(args.base, field)
    new, _ = best_times(args.new, field)
    what = unit if args.counter else f"{args.time}, {unit}"
    print(f"| benchmark | base ({what}) | new ({what}) | new / base |")
    print("|---|---|---|---|")
    for key in base:
        if key in new:
            print(f"| {key} | {base[key]:.3f} | {new[key]:.3f} | {new[key] / base[key]:.3f} |")


if __name__ == "__main__":
    main()
