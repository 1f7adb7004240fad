#!/usr/bin/env python3
"""The "epi, path" rows of render_motion_quality runs over several seeds (docs/render.md), before
and after a change: mean and range of the RMSE per scene, their ratio, and the mean share of
pixels off by more than 0.2, as a Markdown table. Each input line is one table row as the
program prints it (optionally after a label and a seed).

  bench/render/motion_seeds_table.py [--run still|path|rc] BEFORE.txt AFTER.txt
  bench/render/motion_seeds_table.py --targets RUNS.txt
  bench/render/motion_seeds_table.py --edges BEFORE.txt AFTER.txt

--run picks the rows ("epi, path" by default; still: "epi, still"; rc: "render cache, path").
--targets: issue 9's figures from one file holding all three runs per seed: the seed means of the
path, still and render cache RMSE, path over still (target at most 1.5), path over the render
cache (at most 0.75) and the path's share of pixels over 0.2 (at most 0.3 %).
--edges: the last column of runs made with `render_motion_quality --edges` (the share of the visible
edge length behind the ray-traced surface), mean and range over the seeds, along the path before
and after, and the still run's from BEFORE.
"""
import collections
import re
import sys

RUNS = {"path": "epi, path", "still": "epi, still", "rc": "render cache, path"}


def rows_of(name, run, fields, convert):
    """Per scene, convert(match) of each row of one run whose text after the run matches `fields`."""
    row = re.compile(r"\| (\S+) \| " + re.escape(RUNS[run]) + r" \| " + fields)
    rows = collections.defaultdict(list)
    with open(name) as f:
        for line in f:
            m = row.search(line)
            if m:
                rows[m.group(1)].append(convert(m))
    return rows


def load(name, run="path"):
    """Per scene, (RMSE, share over 0.2) of each row of one run."""
    return rows_of(name, run, r"([\d.]+) \| [\d.]+ % \| ([\d.]+) %", lambda m: (float(m.group(2)), float(m.group(3))))


def mean(values):
    return sum(values) / len(values)


def targets(name):
    path, still, rc = load(name, "path"), load(name, "still"), load(name, "rc")
    print("| scene | seeds | path RMSE | still RMSE | render cache RMSE | path / still | path / render cache | > 0.2 path |")
    print("|---|---|---|---|---|---|---|---|")
    for scene in sorted(path):
        p, st, r = [v for v, _ in path[scene]], [v for v, _ in still[scene]], [v for v, _ in rc[scene]]
        over = mean([o for _, o in path[scene]])
        print(f"| {scene} | {len(p)} | {mean(p):.4f} | {mean(st):.4f} | {mean(r):.4f} | {mean(p) / mean(st):.2f} | "
              f"{mean(p) / mean(r):.2f} | {over:.2f} % |")


def load_edges(name, run="path"):
    """Per scene, the last column (edges behind, %) of the rows of one run."""
    return rows_of(name, run, r".* ([\d.]+) % \|\s*$", lambda m: float(m.group(2)))


def edges(before_file, after_file):
    before, after, still = load_edges(before_file), load_edges(after_file), load_edges(before_file, "still")
    span = lambda v: f"{mean(v):.1f} % ({min(v):.1f}-{max(v):.1f})"
    print("| scene | seeds | edges behind, path, before | after | still, before |")
    print("|---|---|---|---|---|")
    for scene in sorted(before):
        print(f"| {scene} | {len(before[scene])} | {span(before[scene])} | {span(after[scene]) if after[scene] else '-'} | "
              f"{span(still[scene]) if still[scene] else '-'} |")


def main():
    args = sys.argv[1:]
    if len(args) == 2 and args[0] == "--targets":
        return targets(args[1])
    if len(args) == 3 and args[0] == "--edges":
        return edges(args[1], args[2])
    run = "path"
    if len(args) == 4 and args[0] == "--run" and args[1] in RUNS:
        run, args = args[1], args[2:]
    if len(args) != 2:
        sys.exit(__doc__)
    before, after = load(args[0], run), load(args[1], run)
    print("| scene | seeds | RMSE before (mean, range) | RMSE after (mean, range) | after / before | > 0.2 before | > 0.2 after |")
    print("|---|---|---|---|---|---|---|")
    for scene in sorted(before):
        if scene not in after:
            continue
        rb, ra = [r for r, _ in before[scene]], [r for r, _ in after[scene]]
        ob, oa = [o for _, o in before[scene]], [o for _, o in after[scene]]
        print(f"| {scene} | {len(rb)} | {mean(rb):.4f} ({min(rb):.4f}-{max(rb):.4f}) | {mean(ra):.4f} "
              f"({min(ra):.4f}-{max(ra):.4f}) | {mean(ra) / mean(rb):.3f} | {mean(ob):.2f} % | {mean(oa):.2f} % |")


if __name__ == "__main__":
    main()
