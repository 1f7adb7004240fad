#!/usr/bin/env python3
"""Turns epi_bench JSON (Google Benchmark, --benchmark_format=json, any --benchmark_repetitions)
into the Markdown tables of docs/performance.md ("Reconstruction filters"), so that no figure
there is typed by hand.

  build/bin/epi_bench --benchmark_filter='BM_StreamingFloor|BM_Filters|BM_Reconstruct/|BM_RenderCache|BM_ReachReuse' \\
      --benchmark_repetitions=3 --benchmark_min_time=0.05 --benchmark_format=json > filters.json
  python3 bench/perf_tables.py filters.json
  python3 bench/perf_tables.py --ab base-*.json --new new-*.json   # stage by stage, two binaries

Each figure is the best of the repetitions (the machine is shared; the best run is the least
disturbed one). One-thread figures are CPU times of the thread doing the work (robust under
load); two-thread figures are wall times. x_floor = time / the streaming floor of the same run
(BM_StreamingFloor, CPU time), the time to read and write the EPI's 10 bytes per pixel once.
"""
import json
import sys
from collections import defaultdict

STAGES = ["classify", "decode", "reachability", "interpolate", "fill", "antialias", "complex"]
SIZE_NAMES = {(512, 512): "512²", (1920, 1080): "1080p", (3840, 2160): "4K"}


def load(paths):
    runs, context = [], None
    for path in paths:
        with open(path) as f:
            data = json.load(f)
        context = context or data.get("context", {})
        runs += [b for b in data["benchmarks"] if b.get("run_type", "iteration") == "iteration" and not b.get("error_occurred")]
    return runs, context


def args(name):
    parts = name.split("/")
    return parts[0], [int(p) for p in parts[1:] if p.lstrip("-").isdigit()]


def best(values):
    return min(values) if values else None


def fmt(v, digits=1):
    if v is None:
        return "-"
    return f"{v:.{digits}f}" if v < 100 else f"{v:.0f}"


def main(paths):
    runs, context = load(paths)
    floor = defaultdict(list)         # (w, h) -> floor CPU ms
    filters = defaultdict(lambda: defaultdict(list))  # (w, h, edges, threads, kernel) -> stage -> [ms]
    whole = defaultdict(list)         # (w, h, edges, label) -> [ms]
    reuse = defaultdict(list)         # (w, h, reuse level 0-2) -> reachability CPU ms
    rendercache = defaultdict(list)   # (w, h, kernel label) -> (filter, decode) CPU ms
    rendercache_order = {}            # kernel label -> kernel argument (0 oracle, then best target first)
    kernels = {}
    for r in runs:
        bench, a = args(r["name"])
        if bench == "BM_StreamingFloor":
            floor[(a[0], a[1])].append(r["cpu_time"])
        elif bench == "BM_Filters":
            w, h, k, threads, edges = a[:5]
            kernels[k] = r["label"].split()[0]
            for s in STAGES:
                key = f"{s}_cpu_ms" if threads == 1 else f"{s}_ms"
                filters[(w, h, edges, threads, k)][s].append(r[key])
        elif bench == "BM_RenderCacheFilter":
            rendercache[(a[0], a[1], r["label"])].append((r["filter_cpu_ms"], r["decode_cpu_ms"]))
            rendercache_order[r["label"]] = a[2]
        elif bench == "BM_ReachReuse":
            reuse[(a[0], a[1], a[2])].append(r["reachability_cpu_ms"])
        elif bench == "BM_Reconstruct":
            w, h, k, threads, edges = a[:5]
            label = r["label"].replace(" few", "").replace(" many", "")
            # One thread: the CPU time of the thread doing the work; two: wall time.
            whole[(w, h, edges, label)].append(r["cpu_time"] if threads == 1 else r["real_time"])
    order = sorted(kernels)
    out = []
    out.append(f"Run {context.get('date', '?')}, {context.get('num_cpus', '?')} CPUs, "
               f"load average {', '.join(f'{x:.1f}' for x in context.get('load_avg', []))}.\n")
    out.append("Streaming floor (memcpy of the three planes, one thread, CPU ms): " +
               ", ".join(f"{SIZE_NAMES.get(s, s)} {fmt(best(v), 3)}" for s, v in sorted(floor.items())) + ".\n")
    for threads in sorted({k[3] for k in filters}):
        what = "CPU ms, one thread" if threads == 1 else f"wall ms, {threads} threads"
        out.append(f"\n**Per filter, {what}** (speed-up of the best target over the oracle; x_floor of the best target)\n")
        out.append("| size | edges | stage | " + " | ".join(kernels[k] for k in order) + " | speed-up | x_floor |")
        out.append("|---|---|---|" + "---|" * (len(order) + 2))
        for (w, h) in sorted({(k[0], k[1]) for k in filters}):
            for edges in (0, 1):
                for s in STAGES:
                    row = [best(filters.get((w, h, edges, threads, k), {}).get(s, [])) for k in order]
                    if all(v is None for v in row):
                        continue
                    oracle, fast = row[0], min((v for v in row[1:] if v is not None), default=None)
                    speedup = f"{oracle / fast:.1f}x" if oracle and fast and s != "decode" else "-"
                    fl = best(floor.get((w, h), []))
                    xf = fmt(fast / fl) if fast is not None and fl else "-"
                    out.append(f"| {SIZE_NAMES.get((w, h))} | {'many' if edges else 'few'} | {s} | " +
                               " | ".join(fmt(v, 2) for v in row) + f" | {speedup} | {xf} |")
    out.append("\n**Whole reconstruction** (ms: one thread CPU, two threads wall; in brackets x_floor)\n")
    labels = sorted({k[3] for k in whole}, key=lambda l: (l != "oracle", "SCALAR" in l, l))
    out.append("| size | edges | " + " | ".join(labels) + " |")
    out.append("|---|---|" + "---|" * len(labels))
    for (w, h) in sorted({(k[0], k[1]) for k in whole}):
        fl = best(floor.get((w, h), []))
        for edges in (0, 1):
            cells = []
            for l in labels:
                v = best(whole.get((w, h, edges, l), []))
                cells.append("-" if v is None else f"{fmt(v)} ({fmt(v / fl) if fl else '-'})")
            out.append(f"| {SIZE_NAMES.get((w, h))} | {'many' if edges else 'few'} | " + " | ".join(cells) + " |")
    if rendercache:
        out.append("\n**Render cache filter** (one thread, CPU ms: the 3x3 filter with its 7x7 prefilter, "
                   "+ decoding for the vector kernels; speed-up and x_floor of the two together)\n")
        labels = sorted({k[2] for k in rendercache}, key=lambda l: rendercache_order[l])
        out.append("| size | " + " | ".join(labels) + " | speed-up | x_floor |")
        out.append("|---|" + "---|" * (len(labels) + 2))
        for (w, h) in sorted({(k[0], k[1]) for k in rendercache}):
            sums = {l: best([f + d for f, d in rendercache.get((w, h, l), [])]) for l in labels}
            cells = []
            for l in labels:
                runs_l = rendercache.get((w, h, l), [])
                if not runs_l:
                    cells.append("-")
                    continue
                f, d = min(runs_l, key=lambda t: t[0] + t[1])
                cells.append(fmt(f, 2) if l == "oracle" else f"{fmt(f, 2)} + {fmt(d, 2)}")
            fast = min((v for l, v in sums.items() if l != "oracle" and v is not None), default=None)
            oracle, fl = sums.get("oracle"), best(floor.get((w, h), []))
            speedup = f"{oracle / fast:.1f}x" if oracle and fast else "-"
            out.append(f"| {SIZE_NAMES.get((w, h))} | " + " | ".join(cells) + f" | {speedup} | "
                       f"{fmt(fast / fl) if fast and fl else '-'} |")
    if reuse:
        out.append("\n**Reachability reused across rows** (the best target, one thread, CPU ms of the reachability stage; "
                   "saved: against nothing reused)\n")
        out.append("| size | nothing reused | relation rows kept | + rows above by symmetry | saved |")
        out.append("|---|---|---|---|---|")
        for (w, h) in sorted({(k[0], k[1]) for k in reuse}):
            none, rows, sym = (best(reuse.get((w, h, level), [])) for level in (0, 1, 2))
            fast = min((v for v in (rows, sym) if v is not None), default=None)
            saved = f"{100 * (1 - fast / none):.0f} %" if none and fast else "-"
            out.append(f"| {SIZE_NAMES.get((w, h))} | {fmt(none, 2)} | {fmt(rows, 2)} | {fmt(sym, 2)} | {saved} |")
    print("\n".join(out))


def stage_ab(base_paths, new_paths):
    """Per stage, one thread: the oracle and the best target (kernel argument 1) of two sets of
    runs (a base and a changed binary, run alternately): best CPU ms of each, new / base, and the
    changed binary's speed-up over its oracle. Then the whole tiled reconstruction the same way."""
    sets = []
    for paths in (base_paths, new_paths):
        runs, context = load(paths)
        stages, whole, floor, label = defaultdict(list), defaultdict(list), defaultdict(list), {}
        for r in runs:
            bench, a = args(r["name"])
            if bench == "BM_StreamingFloor":
                floor[(a[0], a[1])].append(r["cpu_time"])
            elif bench == "BM_Filters" and a[3] == 1 and a[2] in (0, 1):
                label[a[2]] = r["label"].split()[0]
                for s in STAGES:
                    stages[(a[0], a[1], a[4], a[2], s)].append(r[f"{s}_cpu_ms"])
            elif bench == "BM_Reconstruct" and a[3] == 1 and a[2] in (0, 1):
                whole[(a[0], a[1], a[4], a[2])].append(r["cpu_time"])
        sets.append((stages, whole, floor, label, context))
    (bs, bw, bf, bl, bc), (ns, nw, nf, nl, nc) = sets
    out = []
    for name, c, fl in (("base", bc, bf), ("new", nc, nf)):
        out.append(f"{name}: runs from {c.get('date', '?')}, load average at the start "
                   f"{', '.join(f'{x:.1f}' for x in c.get('load_avg', []))}; streaming floor (CPU ms) " +
                   ", ".join(f"{SIZE_NAMES.get(k, k)} {fmt(best(v), 3)}" for k, v in sorted(fl.items())) + ".")
    t = nl.get(1, "target 1")
    out.append(f"\n| size | edges | stage | oracle base | oracle new | {t} base | {t} new | new / base | speed-up over the oracle (new) |")
    out.append("|---|---|---|---|---|---|---|---|---|")
    for (w, h, edges, k, s) in sorted(ns, key=lambda x: (x[0] * x[1], x[2], STAGES.index(x[4]), x[3])):
        if k != 1:
            continue
        ob, on = best(bs.get((w, h, edges, 0, s), [])), best(ns.get((w, h, edges, 0, s), []))
        b, n = best(bs.get((w, h, edges, 1, s), [])), best(ns.get((w, h, edges, 1, s), []))
        ratio = f"{n / b:.2f}" if b and n else "-"
        speedup = f"{on / n:.1f}x" if on and n and s != "decode" else "-"
        out.append(f"| {SIZE_NAMES.get((w, h))} | {'many' if edges else 'few'} | {s} | {fmt(ob, 2)} | {fmt(on, 2)} | "
                   f"{fmt(b, 2)} | {fmt(n, 2)} | {ratio} | {speedup} |")
    out.append(f"\n| size | edges | tiled {t} 1T base (CPU ms) | new | new / base | new, x_floor |")
    out.append("|---|---|---|---|---|---|")
    for (w, h, edges, k) in sorted(nw, key=lambda x: (x[0] * x[1], x[2])):
        if k != 1:
            continue
        b, n, fl = best(bw.get((w, h, edges, 1), [])), best(nw.get((w, h, edges, 1), [])), best(nf.get((w, h), []))
        out.append(f"| {SIZE_NAMES.get((w, h))} | {'many' if edges else 'few'} | {fmt(b)} | {fmt(n)} | "
                   f"{n / b:.2f} | {fmt(n / fl) if fl else '-'} |")
    print("\n".join(out))


if __name__ == "__main__":
    if len(sys.argv) < 2:
        sys.exit(__doc__)
    if sys.argv[1] == "--ab":  # --ab BASE.json... --new NEW.json...
        i = sys.argv.index("--new")
        stage_ab(sys.argv[2:i], sys.argv[i + 1:])
    else:
        main(sys.argv[1:])
