#!/usr/bin/python3
"""Memory and set-up time against scene content: the figure of docs/tradeoff-memory.md.

Reads the CSV of `render_scene_cost` (bench/render/scene_cost.cpp) and draws one column per
series (objects, triangles, point lights, area lights, subdivision level): memory per structure on
top, set-up time per step below. Run with Debian's python3 (python3-matplotlib):

    build/bin/render_scene_cost --out scene_cost.csv
    /usr/bin/python3 bench/render/plot_scene_cost.py scene_cost.csv docs/images/scene_cost.png
    /usr/bin/python3 bench/render/plot_scene_cost.py --table scene_cost.csv   # the doc's table
"""
import csv
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

SERIES = [
    ("objects", "objects (instances of one 2k-triangle mesh)", True),
    ("triangles", "triangles (one sphere)", True),
    ("point_lights", "point lights", False),
    ("area_lights", "area lights (emissive quads)", False),
    ("subdivision", "Catmull-Clark level (cube cage)", False),
]
MEMORY = [
    ("mem_meshes", "meshes"),
    ("mem_area_lights", "area lights"),
    ("mem_embree", "Embree BVH"),
    ("mem_edge_meshes", "edge meshes"),
    ("mem_edge_trees", "edge trees"),
    ("mem_receiver_trees", "receiver trees"),
]
TIME = [
    ("ms_subdivide", "subdivision"),
    ("ms_area_lights", "area lights"),
    ("ms_ray_scene", "ray scene (Embree)"),
    ("ms_edge_finder", "edge finder"),
]


def main(csv_path, png_path):
    with open(csv_path, newline="") as f:
        rows = list(csv.DictReader(f))
    fig, axes = plt.subplots(2, len(SERIES), figsize=(4.0 * len(SERIES), 7.0), squeeze=False)
    for column, (series, label, log_x) in enumerate(SERIES):
        data = sorted((r for r in rows if r["series"] == series), key=lambda r: float(r["x"]))
        if not data:
            continue
        x = [float(r["x"]) for r in data]
        top, bottom = axes[0][column], axes[1][column]
        # Log axes; a structure not built (0 bytes) has no point there, and says so in the legend.
        for key, name in MEMORY:
            points = [(xi, float(r[key]) / 2**20) for xi, r in zip(x, data) if float(r[key]) > 0]
            if len(points) == len(data):
                top.plot(*zip(*points), marker="o", ms=3, label=name)
            elif points:
                top.plot(*zip(*points), marker="o", ms=3, label=f"{name} (from {points[0][0]:g} on)")
            else:
                top.plot([], [], marker="o", ms=3, label=name + " (none built)")
        for key, name in TIME:
            points = [(xi, float(r[key])) for xi, r in zip(x, data) if float(r[key]) > 0]
            if points:
                bottom.plot(*zip(*points), marker="o", ms=3, label=name)
        for ax in (top, bottom):
            if log_x:
                ax.set_xscale("log")
            ax.set_yscale("log")
            ax.grid(True, which="both", alpha=0.3)
            ax.set_xlabel(label)
        top.set_title(label.split(" (")[0])
        if column == 0:
            top.set_ylabel("memory, MiB")
            bottom.set_ylabel("set-up time, ms (fastest of 3)")
        top.legend(fontsize=7)
        bottom.legend(fontsize=7)
    fig.suptitle("What epi builds before the first frame, against scene content (render_scene_cost)")
    fig.tight_layout()
    fig.savefig(png_path, dpi=90)


def table(csv_path):
    """The markdown table of docs/tradeoff-memory.md: per row, memory by structure and set-up time."""
    with open(csv_path, newline="") as f:
        rows = list(csv.DictReader(f))
    print("| series | x | triangles | meshes | area lights | Embree | edge meshes | edge trees | receiver trees "
          "| total MiB | bytes / triangle | set-up ms |")
    print("|---|---|---|---|---|---|---|---|---|---|---|---|")
    for r in rows:
        if r["series"] == "warm-up":
            continue
        mem = [int(r[k]) for k, _ in MEMORY]
        total = sum(mem)
        ms = sum(float(r[k]) for k, _ in TIME)
        cells = " | ".join(f"{m / 2**20:.3f}" if m else "-" for m in mem)
        print(f"| {r['series']} | {float(r['x']):g} | {r['triangles']} | {cells} | {total / 2**20:.2f} "
              f"| {total / max(1, int(r['triangles'])):.0f} | {ms:.1f} |")


if __name__ == "__main__":
    if len(sys.argv) == 3 and sys.argv[1] == "--table":
        table(sys.argv[2])
    elif len(sys.argv) == 3:
        main(sys.argv[1], sys.argv[2])
    else:
        sys.exit("usage: plot_scene_cost.py SCENE_COST.csv OUT.png | plot_scene_cost.py --table SCENE_COST.csv")
