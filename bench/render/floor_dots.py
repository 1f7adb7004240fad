#!/usr/bin/python3
# Dark dots on a plain surface: the pixels of IMAGE darker than REFERENCE by more than 0.1 (8-bit
# sRGB, as written) where the reference shows a grey, unsaturated surface with no other colour in
# its 5x5 (the floor of chains.gltf, not its border, chains or shadows' edges), in rows FIRST..LAST.
# docs/render.md, "Stray background points":
#   /usr/bin/python3 bench/render/floor_dots.py --rows 300 460 REFERENCE.png IMAGE.png...
# --figure OUT.png X Y W H: also the W x H crops at (X, Y) of the images and then the reference,
# one above the other, three times enlarged.
import argparse

import numpy as np
from numpy.lib.stride_tricks import sliding_window_view
from PIL import Image

parser = argparse.ArgumentParser(description=__doc__)
parser.add_argument("--rows", nargs=2, type=int, default=(0, 1 << 30), metavar=("FIRST", "LAST"))
parser.add_argument("--figure", nargs=5, metavar=("OUT", "X", "Y", "W", "H"))
parser.add_argument("reference")
parser.add_argument("images", nargs="+")
args = parser.parse_args()


def load(path):
    return np.asarray(Image.open(path).convert("RGB"), dtype=np.float64) / 255.0


reference = load(args.reference)
grey = reference.mean(axis=2)
plain = (grey > 0.15) & (reference.max(axis=2) - reference.min(axis=2) < 0.08)
floor = np.zeros_like(plain)
floor[2:-2, 2:-2] = sliding_window_view(plain, (5, 5)).all(axis=(2, 3))
floor[: args.rows[0]] = False
floor[args.rows[1] :] = False
for path in args.images:
    image = load(path)
    if image.shape != reference.shape:
        raise SystemExit(f"{path}: {image.shape[1]}x{image.shape[0]}, the reference is {reference.shape[1]}x{reference.shape[0]}")
    dots = ((grey - image.mean(axis=2)) > 0.1) & floor
    print(f"{path}: {int(dots.sum())} of {int(floor.sum())} floor pixels darker than the reference by > 0.1")
if args.figure:
    out, x, y, w, h = args.figure[0], *map(int, args.figure[1:])
    crops = [Image.open(path).convert("RGB").crop((x, y, x + w, y + h)) for path in args.images + [args.reference]]
    figure = Image.new("RGB", (3 * w, 3 * h * len(crops)))
    for k, crop in enumerate(crops):
        figure.paste(crop.resize((3 * w, 3 * h), Image.NEAREST), (0, 3 * h * k))
    figure.save(out)
