#!/usr/bin/python3
"""Turns render_bench JSON (Google Benchmark, --benchmark_format=json) into docs/performance.md's
"paper's table 2" (per-stage ms of a frame for each scene, size and mode; frame rate; the speed-up
over a 1-spp ray trace) and a per-stage stacked bar chart (PNG, matplotlib), so that no figure
there is typed by hand.

  build/bin/render_bench --benchmark_filter='BM_Frame/.*/[012]/|BM_RaytraceFrame' \\
      --benchmark_out=frame.json --benchmark_out_format=json
  /usr/bin/python3 bench/frame_tables.py frame.json [--chart docs/images/frame_stages.png]

(/usr/bin/python3: Debian's, with python3-matplotlib; tools/setup.sh installs it.)

The stage list is core/render/frame_stages.h's kFrameStages (read from the header: one list for
the renderer, the CLI, the bench and this script). Each figure is the best of the repetitions.
BM_Frame args: scene, width, height, mode (0 epi, stage by stage; 1 render cache; 2 epi with the
tiled reconstruction, whose whole time is counted under "interpolate"); the frame time excludes
shading (the paper shades on other processors). The speed-up divides a 1-spp ray trace frame
(BM_RaytraceFrame, direct and gi shaders) by the EPI frame of the same scene and size (mode 2
when present, else mode 0).
"""
import json
import os
import re
import sys
from collections import defaultdict

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
SIZE_NAMES = {(512, 512): "512²", (1920, 1080): "1080p", (3840, 2160): "4K"}
MODE_NAMES = {0: "epi (staged)", 1: "render cache", 2: "epi (tiled)"}
SCENES = ["cornell_box", "chains", "rooms", "torus_capsule", "grid_dragon"]  # render_bench's kScenes


def frame_stages():
    """(name, label) of each loop stage of kFrameStages, in order."""
    with open(os.path.join(ROOT, "core/render/frame_stages.h")) as f:
        text = f.read()
    rows = re.findall(r'\{FrameStage::(\w+), "(\w+)", "([^"]+)", (true|false)\}', text)
    if not rows:
        sys.exit("frame_tables.py: no kFrameStages rows found in core/render/frame_stages.h")
    return [(name, label) for _, name, label, loop in rows if loop == "true"]


def load(paths):
    runs, context = [], []
    for path in paths:
        with open(path) as f:
            data = json.load(f)
        context.append(data.get("context", {}))
        runs += [b for b in data["benchmarks"] if b.get("run_type", "iteration") == "iteration" and not b.get("error_occurred")]
    return runs, context


def args(name):
    parts = name.split("/")
    return parts[0], [int(p) for p in parts[1:] if p.lstrip("-").isdigit()]


def fmt(v, digits=1):
    if v is None:
        return "-"
    return f"{v:.{digits}f}" if abs(v) < 100 else f"{v:.0f}"


def to_ms(run):
    scale = {"ns": 1e-6, "us": 1e-3, "ms": 1.0, "s": 1e3}[run.get("time_unit", "ns")]
    return run["real_time"] * scale


def collect(runs):
    frames = defaultdict(list)  # (scene, w, h, mode) -> [run]
    raytrace = defaultdict(list)  # (scene, w, h, shader) -> [ms]
    async_loop = defaultdict(list)  # (scene, w, h, shader, split) -> [run]
    for r in runs:
        bench, a = args(r["name"])
        if bench == "BM_Frame" and len(a) >= 4:
            frames[tuple(a[:4])].append(r)
        elif bench == "BM_RaytraceFrame" and len(a) >= 4:
            raytrace[tuple(a[:4])].append(to_ms(r))
        elif bench == "BM_AsyncLoop" and len(a) >= 5:
            async_loop[tuple(a[:5])].append(r)
    # The best repetition: the least disturbed on a shared machine.
    best_frame = {k: min(v, key=lambda r: r["loop_ms"]) for k, v in frames.items()}
    best_ray = {k: min(v) for k, v in raytrace.items()}
    best_async = {k: max(v, key=lambda r: r["fps"]) for k, v in async_loop.items()}
    return best_frame, best_ray, best_async


def tables(best_frame, best_ray, best_async, context):
    stages = frame_stages()
    out = []
    for c in context:  # one line per input file
        out.append(f"Run {c.get('date', '?')}, {c.get('num_cpus', '?')} CPUs, load average "
                   f"{', '.join(f'{x:.1f}' for x in c.get('load_avg', [])) or '?'} (as the run started).\n")
    out.append("| scene | size | mode | " + " | ".join(label for _, label in stages) +
               " | frame ms | fps | ms per Mpixel | sparseness | simple % | complex % | edges | culled |")
    out.append("|---|---|---|" + "---|" * (len(stages) + 8))
    for key in sorted(best_frame, key=lambda k: (k[0], k[1] * k[2], k[3])):
        scene, w, h, mode = key
        r = best_frame[key]
        epi = mode != 1
        cells = [fmt(r.get(f"{name}_ms")) for name, _ in stages]  # 0.0: the stage does not run in this mode
        mpx = w * h / 1e6
        out.append(f"| {SCENES[scene] if scene < len(SCENES) else scene} | {SIZE_NAMES.get((w, h), f'{w}x{h}')} | "
                   f"{MODE_NAMES.get(mode, mode)} | " + " | ".join(cells) +
                   f" | {fmt(r['loop_ms'])} | {fmt(1000.0 / r['loop_ms'])} | {fmt(r['loop_ms'] / mpx)} | "
                   f"{fmt(r['sparseness'], 0)} | {fmt(r['simple_pct'])} | {fmt(r['complex_pct'], 2)} | "
                   f"{fmt(r['edges'], 0) if epi else ''} | {fmt(r['culled'], 0) if epi else ''} |")
    speed = []
    for (scene, w, h, shader), ray_ms in sorted(best_ray.items()):
        frame = best_frame.get((scene, w, h, 2)) or best_frame.get((scene, w, h, 0))
        if frame is None:
            continue
        speed.append((scene, w, h, shader, ray_ms, frame["loop_ms"]))
    if speed:
        out.append("\nSpeed-up of an EPI frame (tiled reconstruction when measured, else staged) over a 1-sample-per-pixel "
                   "ray trace frame of the same scene and size (`BM_RaytraceFrame`, the scene's default camera):\n")
        out.append("| scene | size | shader | ray trace ms | EPI frame ms | speed-up |")
        out.append("|---|---|---|---|---|---|")
        for scene, w, h, shader, ray_ms, frame_ms in speed:
            out.append(f"| {SCENES[scene] if scene < len(SCENES) else scene} | {SIZE_NAMES.get((w, h), f'{w}x{h}')} | "
                       f"{'gi' if shader == 1 else 'direct'} | {fmt(ray_ms)} | {fmt(frame_ms)} | {ray_ms / frame_ms:.0f}x |")
    if best_async:
        out.append("\nThe asynchronous shader and the loop sharing the cores (`BM_AsyncLoop`: frames back to back along "
                   "the path, budget 1 %; adaptive = FrameSettings::core_split's default, shared = both on all cores):\n")
        out.append("| scene | size | shader | split | loop fps | shading results/s | results/frame | loop threads (mean) |")
        out.append("|---|---|---|---|---|---|---|---|")
        for (scene, w, h, shader, split), r in sorted(best_async.items()):
            out.append(f"| {SCENES[scene] if scene < len(SCENES) else scene} | {SIZE_NAMES.get((w, h), f'{w}x{h}')} | "
                       f"{'gi' if shader == 1 else 'direct'} | {'adaptive' if split == 0 else 'shared'} | {fmt(r['fps'])} | "
                       f"{fmt(r['samples_per_s'], 0)} | {fmt(r['samples_per_frame'], 0)} | {fmt(r['loop_threads'], 2)} |")
    return "\n".join(out)


def chart(best_frame, path):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    stages = frame_stages()
    # One panel per mode (staged, render cache, tiled), its bars scene by scene and size by size.
    modes = sorted({k[3] for k in best_frame})
    per_mode = {m: sorted((k for k in best_frame if k[3] == m), key=lambda k: (k[0], k[1] * k[2])) for m in modes}
    width = max(len(v) for v in per_mode.values())
    fig, axes = plt.subplots(len(modes), 1, figsize=(max(6.0, 0.8 * width + 2.5), 3.2 * len(modes) + 0.6),
                             sharey=True, squeeze=False)
    colours = plt.get_cmap("tab10")
    for ax, m in zip(axes[:, 0], modes):
        keys = per_mode[m]
        labels = [f"{SCENES[k[0]] if k[0] < len(SCENES) else k[0]}\n{SIZE_NAMES.get((k[1], k[2]), f'{k[1]}x{k[2]}')}"
                  for k in keys]
        # Milliseconds per megapixel: the sizes share one axis, and a bar that grows with the size
        # shows a stage that grows faster than the pixel count.
        bottom = [0.0] * len(keys)
        for s, (name, label) in enumerate(stages):
            values = [best_frame[k].get(f"{name}_ms", 0.0) / (k[1] * k[2] / 1e6) for k in keys]
            ax.bar(range(len(keys)), values, bottom=bottom, label=label, color=colours(s % 10))
            bottom = [b + v for b, v in zip(bottom, values)]
        ax.set_xticks(range(len(keys)))
        ax.set_xticklabels(labels, fontsize=7)
        ax.set_ylabel("ms per megapixel")
        ax.set_title(f"{MODE_NAMES.get(m, m)}", fontsize=9)
    axes[0, 0].legend(fontsize=7, ncol=1, loc="upper left", bbox_to_anchor=(1.0, 1.0))
    fig.suptitle("epi frame loop: time per stage, frame without shading (render_bench, bench/frame_tables.py)", fontsize=10)
    fig.tight_layout()
    os.makedirs(os.path.dirname(os.path.abspath(path)), exist_ok=True)
    fig.savefig(path, dpi=110)


def main(argv):
    paths, chart_path = [], None
    it = iter(argv)
    for a in it:
        if a == "--chart":
            chart_path = next(it, None)
        else:
            paths.append(a)
    if not paths:
        sys.exit(__doc__)
    runs, context = load(paths)
    best_frame, best_ray, best_async = collect(runs)
    if not best_frame and not best_async:
        sys.exit("frame_tables.py: no BM_Frame or BM_AsyncLoop runs in " + ", ".join(paths))
    print(tables(best_frame, best_ray, best_async, context))
    if chart_path and best_frame:
        chart(best_frame, chart_path)


if __name__ == "__main__":
    main(sys.argv[1:])
