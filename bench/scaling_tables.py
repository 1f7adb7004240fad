#!/usr/bin/python3
"""Scaling past two cores (docs/performance.md, "Scaling past two cores"): turns Google Benchmark
JSON from a many-core machine into a Markdown table of time and speed-up against thread count,
and a PNG chart (matplotlib), so that no figure there is typed by hand.

Inputs, each given as LABEL=FILE (LABEL names the build, e.g. the commit, so that two builds
measured in one run sit side by side):
  --reconstruct LABEL=FILE   epi_bench JSON with the BM_Reconstruct rows of the tiled stream on
                             1, 2, 4, ... threads (ReconstructArgs adds them up to the cores).
  --frame LABEL=FILE         render_bench JSON of BM_FrameThreads (the loop held to 1, 2, 4, ...
                             threads by a task arena, the thread count the last argument).
  --frame LABEL@CORES=FILE   render_bench JSON of BM_Frame run under `taskset -c 0-(CORES-1)`
                             (how earlier runs held the loop: TBB sizes its arena from the affinity
                             mask, so CORES is the thread count).

  --stages LABEL=FILE        render_stages_bench JSON of BM_SparseBlend (the scalar oracle and the
                             Highway kernels on 1, 2, 4, ... threads).

  --points LABEL=FILE        render_points_bench JSON of BM_Points (the point stages, fast path, on
                             1, 2, 4, ... threads).

  --dir DIR                  everything bench/scaling_run.sh wrote there (LABEL_reconstruct.json,
                             LABEL_frame.json or LABEL_frame_sSCENE.json, LABEL_frame_cCORES.json,
                             LABEL_stages.json, LABEL_points.json).

  /usr/bin/python3 bench/scaling_tables.py --dir scaling --chart docs/images/scaling.png
"""
import argparse
import glob
import json
import os
import re
import sys
from collections import defaultdict

SCENES = ["cornell_box", "chains", "rooms", "torus_capsule", "grid_dragon"]  # render_bench's kScenes
SIZES = {(512, 512): "512²", (1920, 1080): "1080p", (3840, 2160): "4K"}


def load(path):
    try:
        with open(path) as f:
            return json.load(f)
    except (OSError, ValueError) as e:
        sys.exit(f"scaling_tables.py: {path}: {e}")


def best(rows):
    """The best (smallest) time of each benchmark name, in ms, with its counters."""
    out = {}
    for b in rows:
        if b.get("run_type") == "aggregate" or b.get("error_occurred"):
            continue
        key = re.sub(r"/(min_time|iterations|real_time|manual_time).*$", "", b["name"])
        if key not in out or b["real_time"] < out[key]["real_time"]:
            out[key] = b
    return out


def reconstruct_rows(label, path):
    """(label, size, edges, threads) -> ms, for the tiled stream with the best target (kernel 1)."""
    rows = {}
    for name, b in best(load(path)["benchmarks"]).items():
        m = re.match(r"BM_Reconstruct/(\d+)/(\d+)/1/(\d+)/(\d)$", name)
        if m:
            w, h, threads, edges = map(int, m.groups())
            rows[(label, (w, h), "many" if edges else "few", threads)] = b["real_time"]
            rows[(label, (w, h), "many" if edges else "few", "floor")] = b.get("floor_ms", 0)
    return rows


def frame_rows(label, cores, path):
    """(label, scene, size, threads) -> (loop ms, counters) for the tiled path: BM_FrameThreads, or
    BM_Frame mode 2 run on `cores` cores (cores None: BM_FrameThreads only)."""
    rows = {}
    for name, b in best(load(path)["benchmarks"]).items():
        m = re.match(r"BM_FrameThreads/(\d)/(\d+)/(\d+)/(\d+)$", name)
        if m:
            scene, w, h, threads = map(int, m.groups())
            rows[(label, SCENES[scene], (w, h), threads)] = (b["loop_ms"], b)
        m = re.match(r"BM_Frame/(\d)/(\d+)/(\d+)/2$", name)
        if m and cores:
            scene, w, h = map(int, m.groups())
            rows[(label, SCENES[scene], (w, h), cores)] = (b["loop_ms"], b)
    return rows


def stage_rows(label, path):
    """(label, size, threads, kernel) -> ms for BM_SparseBlend (kernel 0: oracle, 1: kernels)."""
    rows = {}
    for name, b in best(load(path)["benchmarks"]).items():
        m = re.match(r"BM_SparseBlend/(\d+)/(\d+)/\d+/(\d+)/(\d)$", name)
        if m:
            w, h, threads, kernel = map(int, m.groups())
            rows[(label, (w, h), threads, kernel)] = b["real_time"]
    return rows


POINT_STAGES = ["project", "cull", "occlusion", "fill", "total"]  # render_points_bench's counters


def point_rows(label, path):
    """(label, scene, size, threads) -> {stage: ms} for BM_Points in epi mode (mode 0)."""
    rows = {}
    for name, b in best(load(path)["benchmarks"]).items():
        m = re.match(r"BM_Points/(\d)/(\d+)/(\d+)/0/(\d+)$", name)
        if m:
            scene, w, h, threads = map(int, m.groups())
            rows[(label, SCENES[scene], (w, h), threads)] = {k: b[f"{k}_ms"] for k in POINT_STAGES}
    return rows


def fmt_ms(v):
    return "" if v is None else f"{v:.1f}"


def spec(text, with_cores):
    label, _, path = text.partition("=")
    if not path:
        sys.exit(f"scaling_tables.py: '{text}' is not LABEL=FILE")
    if with_cores:
        label, at, cores = label.partition("@")
        if at and not cores.isdigit():
            sys.exit(f"scaling_tables.py: '{text}' is not LABEL@CORES=FILE")
        return label, int(cores) if at else None, path
    return label, path


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--reconstruct", action="append", default=[])
    ap.add_argument("--frame", action="append", default=[])
    ap.add_argument("--stages", action="append", default=[])
    ap.add_argument("--points", action="append", default=[])
    ap.add_argument("--dir")
    ap.add_argument("--chart")
    args = ap.parse_args()
    if args.dir:
        for path in sorted(glob.glob(os.path.join(args.dir, "*.json"))):
            m = re.match(r"(.+)_(reconstruct|stages|points|frame|frame_s\d|frame_c(\d+))\.json$", os.path.basename(path))
            if m and m.group(2) == "points":
                args.points.append(f"{m.group(1)}={path}")
            elif m and m.group(2) == "reconstruct":
                args.reconstruct.append(f"{m.group(1)}={path}")
            elif m and m.group(2) == "stages":
                args.stages.append(f"{m.group(1)}={path}")
            elif m and m.group(2).startswith("frame_s"):
                args.frame.append(f"{m.group(1)}={path}")
            elif m and m.group(2) == "frame":
                args.frame.append(f"{m.group(1)}={path}")
            elif m:
                args.frame.append(f"{m.group(1)}@{m.group(3)}={path}")
    recon, frames, stage_ms, points = {}, {}, {}, {}
    for s in args.reconstruct:
        recon.update(reconstruct_rows(*spec(s, False)))
    for s in args.frame:
        frames.update(frame_rows(*spec(s, True)))
    for s in args.stages:
        stage_ms.update(stage_rows(*spec(s, False)))
    for s in args.points:
        points.update(point_rows(*spec(s, False)))
    if not recon and not frames and not stage_ms and not points:
        sys.exit("scaling_tables.py: no BM_Reconstruct, BM_Frame, BM_SparseBlend or BM_Points rows in the inputs")

    series = []  # (title, label, xs, ms) for the chart
    if recon:
        print("The whole reconstruction (epi_bench BM_Reconstruct, tiled stream, best target), ms and speed-up over 1 thread:\n")
        threads = sorted({k[3] for k in recon if k[3] != "floor"})
        print("| build | size | edges | " + " | ".join(f"{t} T" for t in threads) + " | floor ms (1 T) |")
        print("|---|---|---|" + "---|" * (len(threads) + 1))
        for label, size, edges in sorted({k[:3] for k in recon}):
            ts = sorted(t for (l, s, e, t) in recon if (l, s, e) == (label, size, edges) and t != "floor")
            one = recon.get((label, size, edges, 1))
            cells = [f"{recon[(label, size, edges, t)]:.1f}" + (f" ({one / recon[(label, size, edges, t)]:.1f}x)" if one else "") for t in ts]
            print(f"| {label} | {SIZES.get(size, size)} | {edges} | " + " | ".join(cells) + f" | {recon[(label, size, edges, 'floor')]:.2f} |")
            series.append((f"reconstruction {SIZES.get(size, size)}, {edges} edges", label, ts, [recon[(label, size, edges, t)] for t in ts]))
        print()
    if frames:
        all_cores = sorted({k[3] for k in frames})
        print("An EPI frame along the scene's path (render_bench BM_FrameThreads, or BM_Frame under taskset; tiled reconstruction, shading excluded), loop ms and speed-up over the fewest threads measured:\n")
        print("| build | scene | size | " + " | ".join(f"{c} T" for c in all_cores) + " |")
        print("|---|---|---|" + "---|" * len(all_cores))
        for label, scene, size in sorted({k[:3] for k in frames}):
            cs = sorted(c for (l, sc, s, c) in frames if (l, sc, s) == (label, scene, size))
            first = frames[(label, scene, size, cs[0])][0]
            cells = []
            for c in all_cores:
                v = frames.get((label, scene, size, c))
                cells.append("" if v is None else f"{v[0]:.1f} ({first / v[0]:.1f}x)")
            print(f"| {label} | {scene} | {SIZES.get(size, size)} | " + " | ".join(cells) + " |")
            series.append((f"frame {SIZES.get(size, size)}, {scene}", label, cs, [frames[(label, scene, size, c)][0] for c in cs]))
        print()
        # Where the frame stops scaling: each loop stage at the fewest and the most threads.
        stages = [("points", "points_ms"), ("sampling", "sampling_ms"), ("find + rasterize edges", "find_edges_ms+rasterize_edges_ms"),
                  ("reconstruction", "classify_ms+reachability_ms+interpolate_ms+antialias_ms+complex_ms"),
                  ("sparse blend", "sparse_blend_ms")]
        print("Per stage, ms at the fewest and the most threads measured (speed-up):\n")
        print("| build | scene | size | threads | " + " | ".join(n for n, _ in stages) + " | loop |")
        print("|---|---|---|---|" + "---|" * (len(stages) + 1))
        for label, scene, size in sorted({k[:3] for k in frames}):
            cs = sorted(c for (l, sc, s, c) in frames if (l, sc, s) == (label, scene, size))
            if len(cs) < 2:
                continue
            lo, hi = frames[(label, scene, size, cs[0])][1], frames[(label, scene, size, cs[-1])][1]
            cells = []
            for _, keys in stages + [("loop", "loop_ms")]:
                a, b = (sum(r.get(k, 0) for k in keys.split("+")) for r in (lo, hi))
                cells.append(f"{a:.1f} -> {b:.1f} ({a / b:.1f}x)" if b > 0 else "" if a == 0 else f"{a:.1f} -> {b:.1f}")  # "": not in that build
            print(f"| {label} | {scene} | {SIZES.get(size, size)} | {cs[0]} -> {cs[-1]} | " + " | ".join(cells) + " |")
        print()

    if stage_ms:
        print("The sparse blend (render_stages_bench BM_SparseBlend, 10 % of the pixels sampled), ms and speed-up over the scalar oracle on as many threads:\n")
        print("| build | size | threads | oracle | kernels | oracle / kernels |")
        print("|---|---|---|---|---|---|")
        for label, size, threads in sorted({k[:3] for k in stage_ms}):
            o, k = stage_ms.get((label, size, threads, 0)), stage_ms.get((label, size, threads, 1))
            ratio = f"{o / k:.2f}x" if o and k else ""
            print(f"| {label} | {SIZES.get(size, size)} | {threads} | {fmt_ms(o)} | {fmt_ms(k)} | {ratio} |")
        print()

    if points:
        for label, scene, size in sorted({k[:3] for k in points}):
            ts = sorted(t for (l, sc, sz, t) in points if (l, sc, sz) == (label, scene, size))
            series.append((f"points {SIZES.get(size, size)}, {scene}", label, ts, [points[(label, scene, size, t)]["total"] for t in ts]))
        print("The point stages (render_points_bench BM_Points, epi mode, fast path; one thread: CPU time, more: wall time), median ms and speed-up over 1 thread:\n")
        threads = sorted({k[3] for k in points})
        print("| build | scene | size | stage | " + " | ".join(f"{t} T" for t in threads) + " |")
        print("|---|---|---|---|" + "---|" * len(threads))
        for label, scene, size in sorted({k[:3] for k in points}):
            one = points.get((label, scene, size, 1))
            for stage in POINT_STAGES:
                cells = []
                for t in threads:
                    v = points.get((label, scene, size, t))
                    cells.append("" if v is None else f"{v[stage]:.1f}" + (f" ({one[stage] / v[stage]:.1f}x)" if one and v[stage] > 0 else ""))
                print(f"| {label} | {scene} | {SIZES.get(size, size)} | {stage} | " + " | ".join(cells) + " |")
        print()

    if args.chart:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
        # One panel per kind of series present: the reconstruction alone, the whole frame loop, the
        # point stages alone. In a panel the colour names the case (size and edges, or scene) and
        # the line style and marker the build, so that builds of one case read side by side.
        kinds = [k for k in ("reconstruction", "frame", "points") if any(t.startswith(k) for t, *_ in series)]
        titles = {"reconstruction": "the reconstruction (epi_bench)", "frame": "the frame loop (render_bench)",
                  "points": "the point stages alone (render_points_bench)"}
        styles = [("-", "o"), ("--", "s"), (":", "^"), ("-.", "D"), ((0, (5, 1)), "v")]
        colours = plt.rcParams["axes.prop_cycle"].by_key()["color"]
        fig, axes = plt.subplots(1, len(kinds), figsize=(6 * len(kinds), 5), sharey=True, squeeze=False)
        for ax, kind in zip(axes[0], kinds):
            mine = [x for x in series if x[0].startswith(kind) and len(x[2]) >= 2]  # one core count: no line to draw
            cases = sorted({t for t, *_ in mine})
            builds = sorted({l for _, l, *_ in mine})
            top = 1
            for title, label, xs, ms in mine:
                speedup = [ms[0] * xs[0] / m for m in ms]  # relative to one thread, extrapolated from the first point
                style, marker = styles[builds.index(label) % len(styles)]
                ax.plot(xs, speedup, linestyle=style, marker=marker, color=colours[cases.index(title) % len(colours)],
                        label=f"{label}: {title[len(kind):].lstrip()}")
                top = max(top, max(xs))
            ax.plot([1, top], [1, top], "k--", linewidth=0.8, label="linear")
            ax.set_xscale("log", base=2)
            ax.set_yscale("log", base=2)
            ax.set_xlabel("threads (cores)")
            ax.set_title(titles[kind])
            ax.legend(fontsize=6)
            ax.grid(True, which="both", alpha=0.3)
        axes[0][0].set_ylabel("speed-up over one thread")
        fig.tight_layout()
        fig.savefig(args.chart, dpi=110)


if __name__ == "__main__":
    main()
