#!/usr/bin/env python3
"""What a user sees while moving, in the asynchronous loop (docs/render.md, "Requests traced ahead").

For each scene, renders 64-spp references of some frames of its bundled camera path (kept in
REFS_DIR), runs `epi render` asynchronously along the path for each seed and setting, writing
every frame, and compares those frames with their references (`epi compare`). Prints one
Markdown row per scene and setting: display RMSE and the shares of pixels off by more than 0.1
and 0.2, means over the frames and seeds, with the range of the per-run means. Timing-dependent
(the shader runs beside the loop): read means over several seeds.

  bench/render/async_along_path.py EPI REFS_DIR --seeds 1,2,3,4 --settings=-,--no-trace-ahead SCENE.gltf...

A setting is extra `epi render` flags ("-": none). Options: --frames-at 15,25,35,45,55,59 (frame
indices of the 60-frame path), --size 256, --budget 0.02. --targets: issue 9's figures for the
asynchronous loop instead: beside the path, the still error at the same views (60 frames with
the camera held at each chosen key, the last frame compared) and the render cache along the path
(`--mode rendercache`); path over still (target at most 1.5), path over the render cache (at most
0.75), the path's share of pixels over 0.2 (at most 0.3 %); and, for scale, the still view's
share over 0.2 and a 1-spp ray trace of each chosen view (every pixel shaded once, `--mode
raytrace --spp 1`, the same seed), its RMSE and its share over 0.2.
--pace N: each key of the path N frames after the last (the path N times slower; 1, the default,
is the bundled pace of about 6 degrees a frame); the frames compared are those at the chosen keys.
--rate R: the path on the loop's clock (`epi render --path-rate R`: R path frames a second of the
loop's own time, as a viewer shows motion; each chosen key is drawn exactly at it by the first
frame whose clock reaches it), so that a setting that slows the loop shows fewer frames along the
path instead of the same frames later; the still runs last as long (60 frames held at R frames a
second). Every table gets the loop's frames a second (median frame time, the runs' mean).
--settle N: how fast the image settles once the camera stops, in the real loop. Each run follows
the path and then holds the camera at its last view for N frames (a camera path file: the 60 keys,
then the last again at frame 59 + N); the frames after the stop are compared with the last
view's reference, beside the still run (60 frames held at that view). Prints the RMSE at the stop
and 1, 2, 4, ... frames after it, the frames until it comes within 1.5x and 1.1x of the still
error, and those frames in milliseconds of the loop (the run's mean frame time, `--stats`'s fps).
"""
import argparse
import json
import os
import re
import shutil
import statistics
import subprocess
import sys
import tempfile

COMPARE = re.compile(r"display RMSE ([\d.]+) .*> 0\.1: ([\d.]+) %, by > 0\.2: ([\d.]+) %")


def camera_path(scene):
    """The scene's bundled camera keys (scene-format.md: the default scene's extras, else the root's)."""
    with open(scene) as f:
        gltf = json.load(f)
    keys = gltf["scenes"][gltf.get("scene", 0)].get("extras", {}).get("epi", {}).get("camera_path") or \
        gltf.get("extras", {}).get("epi", {}).get("camera_path")
    if not keys:
        sys.exit(f"{scene}: no camera_path in the scene's extras.epi")
    if len(keys) != 60:
        sys.exit(f"{scene}: {len(keys)} camera keys, expected 60 (one per frame)")
    return keys


def camera_flags(key):
    """`epi render` flags for one camera key of the path."""
    vec = lambda v: ",".join(repr(float(x)) for x in v)
    return ["--eye", vec(key["eye"]), "--target", vec(key["target"]), "--up", vec(key["up"]), "--fov",
            repr(float(key["yfov"]))]


def compare(epi, image, reference):
    out = subprocess.run([epi, "compare", image, reference], check=True, capture_output=True, text=True).stdout
    m = COMPARE.search(out)
    if not m:
        sys.exit(f"epi compare {image}: unexpected output: {out}")
    return tuple(float(v) for v in m.groups())


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("epi")
    ap.add_argument("refs")
    ap.add_argument("scenes", nargs="+")
    ap.add_argument("--seeds", default="1,2,3,4")
    ap.add_argument("--settings", default="-,--no-trace-ahead")
    ap.add_argument("--frames-at", default="15,25,35,45,55,59")
    ap.add_argument("--size", type=int, default=256)
    ap.add_argument("--budget", default="0.02")
    ap.add_argument("--targets", action="store_true")
    ap.add_argument("--settle", type=int, default=0)
    ap.add_argument("--pace", type=int, default=1)
    ap.add_argument("--rate", type=float, default=0.0)
    a = ap.parse_args()
    if a.rate > 0 and (a.pace > 1 or a.settle > 0):
        sys.exit("--rate paces the path by the clock: not with --pace or --settle")
    if a.settle > 0:
        a.frames_at = "59"
        return settle_main(a)
    frames_at = [int(k) for k in a.frames_at.split(",")]
    size = f"{a.size}x{a.size}"
    os.makedirs(a.refs, exist_ok=True)
    loop = "sync (every setting passes --sync)" if all("--sync" in t.split() for t in a.settings.split(",")) else \
        "async unless a setting passes --sync"
    pace = f", each key {a.pace} frames after the last" if a.pace > 1 else \
        f", on the loop's clock at {a.rate:g} path frames a second" if a.rate > 0 else ""
    print(f"{size}, {loop}, budget {a.budget}, keys {a.frames_at} of each 60-key path{pace}, seeds {a.seeds}, "
          "64-spp references")
    if a.targets:
        print("| scene | setting | runs | path RMSE | still RMSE | render cache RMSE | path / still | path / render cache "
              "| > 0.2 path | > 0.2 still | 1-spp ray trace RMSE | > 0.2 1-spp ray trace | fps along the path |")
        print("|---|---|---|---|---|---|---|---|---|---|---|---|---|")
    else:
        print("| scene | setting | runs | RMSE (mean, range of runs) | > 0.1 | > 0.2 | fps |")
        print("|---|---|---|---|---|---|---|")
    for scene in a.scenes:
        name = os.path.splitext(os.path.basename(scene))[0]
        keys = camera_path(scene)
        refs = {k: reference_at(a, scene, size, keys, k) for k in frames_at}
        for setting in a.settings.split(","):
            flags = [] if setting == "-" else setting.split()
            label = "default" if setting == "-" else setting
            path = along_path(a, scene, size, refs, flags)
            if not a.targets:
                rmse = [r[0] for r in path]
                print(f"| {name} | {label} | {len(path)} | {statistics.mean(rmse):.4f} ({min(rmse):.4f}-{max(rmse):.4f}) | "
                      f"{statistics.mean(r[1] for r in path):.2f} % | {statistics.mean(r[2] for r in path):.2f} % | "
                      f"{statistics.mean(r[3] for r in path):.0f} |", flush=True)
                continue
            still = held_at_keys(a, scene, size, keys, refs, flags)
            rc = along_path(a, scene, size, refs, flags + ["--mode", "rendercache"])
            rt = ray_traced_at_keys(a, scene, size, keys, refs)
            mean = lambda runs, i=0: statistics.mean(r[i] for r in runs)
            print(f"| {name} | {label} | {len(path)} | {mean(path):.4f} | {mean(still):.4f} | {mean(rc):.4f} | "
                  f"{mean(path) / mean(still):.2f} | {mean(path) / mean(rc):.2f} | {mean(path, 2):.2f} % | "
                  f"{mean(still, 2):.2f} % | {mean(rt):.4f} | {mean(rt, 2):.2f} % | {mean(path, 3):.0f} |", flush=True)


def reference_at(a, scene, size, keys, k):
    """The 64-spp reference of camera key k (kept in REFS_DIR)."""
    name = os.path.splitext(os.path.basename(scene))[0]
    ref = os.path.join(a.refs, f"{name}_{size}_64spp_key{k}.exr")
    if not os.path.exists(ref):
        subprocess.run([a.epi, "render", scene, "--mode", "reference", "--spp", "64", "--size", size] +
                       camera_flags(keys[k]) + ["--quiet", "-o", ref], check=True, stdout=subprocess.DEVNULL)
    return ref


def settle_main(a):
    size = f"{a.size}x{a.size}"
    os.makedirs(a.refs, exist_ok=True)
    at = [0] + [1 << i for i in range(a.settle.bit_length()) if (1 << i) <= a.settle]
    if at[-1] != a.settle:
        at.append(a.settle)
    print(f"{size}, budget {a.budget}, each 60-frame path then {a.settle} frames held at its last view, seeds {a.seeds}, "
          "64-spp reference of the last view")
    print("| scene | setting | runs | " + " | ".join(f"+{f}" for f in at) + " | still | frames to 1.5x still | "
          "frames to 1.1x still | ms a frame | ms to 1.1x still |")
    print("|---|---|---|" + "---|" * (len(at) + 5))
    for scene in a.scenes:
        name = os.path.splitext(os.path.basename(scene))[0]
        keys = camera_path(scene)
        ref = reference_at(a, scene, size, keys, 59)
        for setting in a.settings.split(","):
            flags = [] if setting == "-" else setting.split()
            label = "default" if setting == "-" else setting
            still = statistics.mean(r[0] for r in held_at_keys(a, scene, size, keys, {59: ref}, flags))
            curves, frame_ms = [], []
            for seed in a.seeds.split(","):
                work = tempfile.mkdtemp(prefix="epi_settle_")
                try:
                    path_file = os.path.join(work, "settle.path")
                    write_path(path_file, keys + [keys[59]], lambda k: k if k < 60 else 59 + a.settle)
                    stats = os.path.join(work, "stats.json")
                    subprocess.run([a.epi, "render", scene, "--size", size, "--frames", str(60 + a.settle), "--camera-path",
                                    path_file, "--sample-budget", a.budget, "--seed", seed, "--quiet", "--no-speedup",
                                    "--frames-out", os.path.join(work, "f%d.exr"), "--stats", stats,
                                    "-o", os.path.join(work, "last.exr")] + flags, check=True, stdout=subprocess.DEVNULL)
                    curves.append([compare(a.epi, os.path.join(work, f"f{59 + k}.exr"), ref)[0] for k in range(a.settle + 1)])
                    with open(stats) as f:
                        frame_ms.append(1000.0 / json.load(f)["fps"])
                finally:
                    shutil.rmtree(work)
            mean_curve = [statistics.mean(c[k] for c in curves) for k in range(a.settle + 1)]

            def frames_to(factor):
                runs = [next((k for k, e in enumerate(c) if e <= factor * still), None) for c in curves]
                if any(r is None for r in runs):
                    return f"> {a.settle} in {sum(r is None for r in runs)} of {len(runs)}", None
                return f"{statistics.mean(runs):.1f} ({min(runs)}-{max(runs)})", statistics.mean(runs)
            to15, _ = frames_to(1.5)
            to11, mean11 = frames_to(1.1)
            ms = statistics.mean(frame_ms)
            print(f"| {name} | {label} | {len(curves)} | " + " | ".join(f"{mean_curve[f]:.4f}" for f in at) +
                  f" | {still:.4f} | {to15} | {to11} | {ms:.1f} | " + (f"{mean11 * ms:.0f}" if mean11 is not None else "") +
                  " |", flush=True)


def write_path(file, keys, frame_of):
    """A camera path file (`epi render --camera-path`) with key k at frame frame_of(k)."""
    vec = lambda v: " ".join(repr(float(x)) for x in v)
    with open(file, "w") as f:
        for k, key in enumerate(keys):
            f.write(f"camera {frame_of(k)} eye {vec(key['eye'])} target {vec(key['target'])} up {vec(key['up'])} "
                    f"fov {float(key['yfov'])!r}\n")


def render(a, scene, size, seed, flags, work, frames=60):
    """Runs `epi render` into the folder `work`; returns the loop's frames a second."""
    rate = ["--path-rate", f"{a.rate:g}"] if a.rate > 0 else []
    stats = os.path.join(work, "stats.json")
    subprocess.run([a.epi, "render", scene, "--size", size, "--frames", str(frames), "--sample-budget", a.budget,
                    "--seed", seed, "--quiet", "--no-speedup", "--stats", stats, "-o", os.path.join(work, "last.exr")] +
                   rate + flags, check=True, stdout=subprocess.DEVNULL)
    with open(stats) as f:
        return json.load(f)["fps"]


def along_path(a, scene, size, refs, flags):
    """Per seed, the errors of the chosen frames of a run along the path, averaged over them."""
    runs = []
    for seed in a.seeds.split(","):
        work = tempfile.mkdtemp(prefix="epi_along_")
        try:
            paced = []
            if a.pace > 1:
                write_path(os.path.join(work, "paced.path"), camera_path(scene), lambda k: k * a.pace)
                paced = ["--camera-path", os.path.join(work, "paced.path")]
            at = ["--frames-at", ",".join(str(k * a.pace) for k in refs)]
            fps = render(a, scene, size, seed, flags + paced + at + ["--frames-out", os.path.join(work, "f%d.exr")], work,
                         frames=59 * a.pace + 1)
            errors = [compare(a.epi, os.path.join(work, f"f{k * a.pace}.exr"), refs[k]) for k in refs]
        finally:
            shutil.rmtree(work)
        runs.append(tuple(statistics.mean(e[i] for e in errors) for i in range(3)) + (fps,))
    return runs


def at_keys(a, refs, image_at):
    """Per seed, the errors of one image per chosen key (image_at(seed, key, work) writes it into the
    folder `work` and returns its path), averaged over the keys."""
    runs = []
    for seed in a.seeds.split(","):
        errors = []
        for k, ref in refs.items():
            work = tempfile.mkdtemp(prefix="epi_key_")
            try:
                errors.append(compare(a.epi, image_at(seed, k, work), ref))
            finally:
                shutil.rmtree(work)
        runs.append(tuple(statistics.mean(e[i] for e in errors) for i in range(3)))
    return runs


def held_at_keys(a, scene, size, keys, refs, flags):
    """Per seed, the last of 60 frames with the camera held at each chosen key, averaged over the keys."""
    def still(seed, k, work):
        render(a, scene, size, seed, flags + camera_flags(keys[k]), work)
        return os.path.join(work, "last.exr")
    return at_keys(a, refs, still)


def ray_traced_at_keys(a, scene, size, keys, refs):
    """Per seed, a 1-spp ray trace of each chosen view, averaged over the keys."""
    def ray_trace(seed, k, work):
        out = os.path.join(work, "rt.exr")
        subprocess.run([a.epi, "render", scene, "--mode", "raytrace", "--spp", "1", "--size", size, "--seed", seed,
                        "--quiet", "-o", out] + camera_flags(keys[k]), check=True, stdout=subprocess.DEVNULL)
        return out
    return at_keys(a, refs, ray_trace)


if __name__ == "__main__":
    main()
