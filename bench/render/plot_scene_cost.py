#!/usr/bin/python3
"""Memory and set-up time against scene content: the figure of docs/tradeoff-memory.md.

Reads the CSV of `render_scene_cost` (bench/render/scene_cost.cpp) and draws one column per
series (objects, triangles, point lights, area lights, subdivision level): memory per structure on
top, set-up time per step below. Run with Debian's python3 (python3-matplotlib):

    build/bin/render_scene_cost --out scene_cost.csv
    /usr/bin/python3 bench/render/plot_scene_cost.py scene_cost.csv docs/images/scene_cost.png
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
        for key, name in MEMORY:
            y = [float(r[key]) / 2**20 for r in data]
            if any(v > 0 for v in y):
                top.plot(x, y, marker="o", ms=3, label=name)
            else:
                top.plot([], [], label=name + " (none built)")
        for key, name in TIME:
            y = [float(r[key]) for r in data]
            if any(v > 0 for v in y):
                bottom.plot(x, y, marker="o", ms=3, label=name)
        for ax in (top, bottom):
            if log_x:
                ax.set_xscale("log")
            ax.set_yscale("symlog", linthresh=0.01)
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


if __name__ == "__main__":
    if len(sys.argv) != 3:
        sys.exit("usage: plot_scene_cost.py SCENE_COST.csv OUT.png")
    main(sys.argv[1], sys.argv[2])
