#!/usr/bin/python3
"""Plots of the speed/accuracy study (docs/tradeoff.md) from epi_study's study.csv.

One PNG per knob and camera (path, still), scenes as panels: median CPU time per frame (all
threads, with shading, log scale; the Pareto fronts use the same axis) against mean display RMSE, the knob's settings labelled, the defaults as a black square,
the baselines as grey crosses, the scene's Pareto front over every run (pareto_all) as a dashed
step line, and the knob's own front (pareto_knob) drawn as filled markers (hollow: dominated).
Also prints the Markdown table of the front per scene and camera (for docs/tradeoff.md).

  /usr/bin/python3 bench/study/plot_study.py build/study/study.csv --out docs/tradeoff
"""
import argparse
import csv
import math
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

COLUMNS = ["scene", "camera", "knob", "setting", "width", "height", "is_default", "frames", "evaluated", "ms", "ms_no_shade", "cpu_ms", "rmse",
           "relative_mse", "over_0_1", "over_0_2", "rmse_last", "pareto_knob", "pareto_all"]


def number(text):
    return float(text) if text != "" else math.nan


def read(path):
    with open(path, newline="") as f:
        reader = csv.DictReader(f)
        if reader.fieldnames != COLUMNS:
            sys.exit(f"{path}: columns {reader.fieldnames}, expected {COLUMNS} (epi_study's schema)")
        rows = []
        for r in reader:
            for k in ("ms", "ms_no_shade", "cpu_ms", "rmse", "relative_mse", "over_0_1", "over_0_2", "rmse_last"):
                r[k] = number(r[k])
            for k in ("is_default", "pareto_knob", "pareto_all"):
                r[k] = r[k] == "1"
            rows.append(r)
    if not rows:
        sys.exit(f"{path}: no rows")
    if len({(r["width"], r["height"]) for r in rows}) > 1:  # runs at several sizes: each its own panel
        for r in rows:
            r["scene"] = f"{r['scene']} {r['width']}x{r['height']}"
    return rows


def front_line(points):
    """The Pareto front as a step line (x ascending, y falling)."""
    pts = sorted(points)
    xs, ys = [], []
    for x, y in pts:
        if xs:
            xs.append(x), ys.append(ys[-1])
        xs.append(x), ys.append(y)
    return xs, ys


def plot_knob(rows, knob, camera, scenes, out_dir):
    fig, axes = plt.subplots(1, len(scenes), figsize=(4.2 * len(scenes), 3.8), squeeze=False)
    for ax, scene in zip(axes[0], scenes):
        group = [r for r in rows if r["scene"] == scene and r["camera"] == camera]
        front = [(r["cpu_ms"], r["rmse"]) for r in group if r["pareto_all"]]
        if front:
            xs, ys = front_line(front)
            ax.plot(xs, ys, "--", color="0.6", lw=1, label="front (all runs)")
        shown = 0
        for r in group:
            if r["knob"] == "baseline":
                ax.plot(r["cpu_ms"], r["rmse"], "x", color="0.4", ms=7)
                ax.annotate(r["setting"], (r["cpu_ms"], r["rmse"]), fontsize=6, color="0.4", xytext=(3, -8),
                            textcoords="offset points")
            elif r["is_default"]:
                ax.plot(r["cpu_ms"], r["rmse"], "s", color="black", ms=6, label="default")
            elif r["knob"] == knob:
                filled = r["pareto_knob"]
                ax.plot(r["cpu_ms"], r["rmse"], "o", color="C0", mfc="C0" if filled else "none", ms=6)
                shown += 1
                ax.annotate(r["setting"], (r["cpu_ms"], r["rmse"]), fontsize=7, color="C0",
                            xytext=(4, 3 if shown % 2 else -9), textcoords="offset points")
        ax.set_xscale("log")
        ax.set_title(f"{scene} ({camera})", fontsize=9)
        ax.set_xlabel("CPU ms per frame incl. shading, all threads (log)", fontsize=8)
        ax.set_ylabel("display RMSE vs reference", fontsize=8)
        ax.tick_params(labelsize=7)
        ax.grid(True, which="both", lw=0.3, alpha=0.5)
    axes[0][0].legend(fontsize=7, loc="upper right")
    fig.suptitle(f"knob: {knob}   (filled: on the knob's Pareto front; x: baselines)", fontsize=10)
    fig.tight_layout()
    path = os.path.join(out_dir, f"{knob}_{camera}.png")
    fig.savefig(path, dpi=80)
    plt.close(fig)
    return path


def front_table(rows):
    lines = ["| scene | camera | on the front (CPU ms, RMSE), cheapest first |", "|---|---|---|"]
    keys = sorted({(r["scene"], r["camera"]) for r in rows})
    for scene, camera in keys:
        front = sorted((r for r in rows if r["scene"] == scene and r["camera"] == camera and r["pareto_all"]),
                       key=lambda r: r["cpu_ms"])
        cells = "; ".join(f"{r['knob']} {r['setting']} ({r['cpu_ms']:.1f}, {r['rmse']:.4f})" for r in front)
        lines.append(f"| {scene} | {camera} | {cells} |")
    return "\n".join(lines)


def ratio_table(rows):
    """Per setting, its time and error relative to the default of the same scene and camera:
    the median over scenes and cameras, and the range (min-max)."""
    default = {(r["scene"], r["camera"]): r for r in rows if r["is_default"]}
    lines = ["| knob | setting | wall time / default | CPU time / default | RMSE / default | runs |",
             "|---|---|---|---|---|---|"]
    settings = list(dict.fromkeys((r["knob"], r["setting"]) for r in rows if not r["is_default"]))

    def cell(values):
        values = sorted(v for v in values if math.isfinite(v))
        if not values:
            return "-"
        mid = values[len(values) // 2] if len(values) % 2 else 0.5 * (values[len(values) // 2 - 1] + values[len(values) // 2])
        return f"{mid:.2f} ({values[0]:.2f}-{values[-1]:.2f})"

    for knob, setting in settings:
        pairs = [(r, default[(r["scene"], r["camera"])]) for r in rows
                 if r["knob"] == knob and r["setting"] == setting and (r["scene"], r["camera"]) in default]
        lines.append(f"| {knob} | {setting} | " + " | ".join(cell(r[k] / d[k] if d[k] else math.nan for r, d in pairs)
                                                         for k in ("ms", "cpu_ms", "rmse")) + f" | {len(pairs)} |")
    return "\n".join(lines)


TARGETS = [("1080p at 60 fps", 1920, 1080, 60.0), ("4K at 30 fps", 3840, 2160, 30.0)]


def budget_table(rows, cores):
    """The best setting (least RMSE) per scene and camera whose time at the target fits the target's
    frame time. Times at another size than measured are scaled by the pixel count (time per pixel
    held: derived, not measured). Two readings: the frame loop's wall time as measured
    (ms_no_shade: shading on other cores), and the CPU time with shading over `cores` cores
    (perfect scaling: an optimistic bound)."""
    lines = [f"| target | scene | camera | times | best by frame-loop wall time (ms at target, RMSE) | best by CPU time with shading / {cores} cores (ms at target, RMSE) |",
             "|---|---|---|---|---|---|"]
    keys = sorted({(r["scene"], r["camera"]) for r in rows})
    for name, w, h, fps in TARGETS:
        limit = 1000.0 / fps
        for scene, camera in keys:
            group = [r for r in rows if r["scene"] == scene and r["camera"] == camera]
            cells = []
            for column, divide in (("ms_no_shade", 1), ("cpu_ms", cores)):
                timed = [(r[column] / divide * w * h / (int(r["width"]) * int(r["height"])), r) for r in group
                         if math.isfinite(r[column]) and math.isfinite(r["rmse"])]
                fits = [(t, r) for t, r in timed if t <= limit]
                if fits:
                    t, r = min(fits, key=lambda tr: tr[1]["rmse"])
                    cells.append(f"{r['knob']} {r['setting']} ({t:.1f}, {r['rmse']:.4f})")
                elif timed:
                    t, r = min(timed, key=lambda tr: tr[0])
                    cells.append(f"none fits; fastest: {r['knob']} {r['setting']} ({t:.0f} = {t / limit:.1f}x over, {r['rmse']:.4f})")
                else:
                    cells.append("no timed run")
            sizes = sorted({f"{r['width']}x{r['height']}" for r in group})
            how = "measured" if sizes == [f"{w}x{h}"] else "derived from " + ", ".join(sizes)
            lines.append(f"| {name} | {scene} | {camera} | {how} | {cells[0]} | {cells[1]} |")
    return "\n".join(lines)


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("csv")
    p.add_argument("--out", default="build/study/plots")
    p.add_argument("--cores", type=int, default=2, help="cores of the target machine, for the budget table")
    a = p.parse_args()
    rows = read(a.csv)
    os.makedirs(a.out, exist_ok=True)
    scenes = list(dict.fromkeys(r["scene"] for r in rows))
    knobs = [k for k in dict.fromkeys(r["knob"] for r in rows) if k not in ("default", "baseline")]
    for camera in dict.fromkeys(r["camera"] for r in rows):
        for knob in knobs:
            knob_scenes = [s for s in scenes if any(r["scene"] == s and r["knob"] == knob and r["camera"] == camera
                                                    for r in rows)]
            if knob_scenes:
                print(plot_knob(rows, knob, camera, knob_scenes, a.out))
    print()
    print(front_table(rows))
    print()
    print(ratio_table(rows))
    print()
    print(budget_table(rows, a.cores))


if __name__ == "__main__":
    main()
