#!/usr/bin/env python3
"""Compare two sets of Google Benchmark JSON runs (e.g. a base and a changed binary, run
alternately on a loaded machine): the best (minimum) real time per benchmark in each set and
their ratio, as a Markdown table. `--time cpu` compares CPU times instead (the benchmark
thread's: on a loaded machine the fairer figure for one-thread runs). `--counter NAME` compares
a user counter instead (e.g. `complex_cpu_ms`, one stage of BM_Filters), its minimum likewise;
`--label` adds each benchmark's label (BM_Filters': the kernel, edges and threads).
`--last-arg B N` compares within runs: a benchmark whose last argument is B (from --base) with
the same benchmark whose last argument is N (from --new), e.g. BM_Fallback's per-pixel and
by-rows fallback measured in one run.

  tools/bench_compare.py --base base-*.json --new new-*.json [--time cpu] [--counter NAME] [--label]
                         [--last-arg B N]
"""
import argparse
import json


def best_times(files, field, labels=None, last_arg=None):
    best, unit = {}, "ns"
    for name in files:
        with open(name) as f:
            for b in json.load(f)["benchmarks"]:
                if b.get("run_type") == "aggregate" or field not in b:
                    continue
                key = b["run_name"] if "run_name" in b else b["name"]
                if last_arg is not None:  # keep this last argument only, and key without it
                    parts = key.split("/")
                    args = [i for i, p in enumerate(parts) if p.lstrip("-").isdigit()]
                    if not args or parts[args[-1]] != last_arg:
                        continue
                    key = "/".join(parts[:args[-1]] + parts[args[-1] + 1:])
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
    parser.add_argument("--last-arg", nargs=2, metavar=("B", "N"), help="base: last argument B; new: last argument N")
    args = parser.parse_args()
    field = args.counter or args.time + "_time"
    labels = {}
    base_arg, new_arg = args.last_arg if args.last_arg else (None, None)
    base, unit = best_times(args.base, field, labels, base_arg)
    new, _ = best_times(args.new, field, None, new_arg)
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
