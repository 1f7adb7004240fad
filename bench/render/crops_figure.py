#!/usr/bin/python3
# A figure of the same crop of several images, side by side with a 4-pixel white gap, scaled
# (Lanczos): e.g. a reference, a frame before and after a change (docs/render.md's figures).
#   /usr/bin/python3 bench/render/crops_figure.py --box X0 Y0 X1 Y1 [--scale S] -o OUT.png IMAGE...
import argparse

from PIL import Image

parser = argparse.ArgumentParser(description=__doc__)
parser.add_argument("--box", nargs=4, type=int, required=True, metavar=("X0", "Y0", "X1", "Y1"))
parser.add_argument("--scale", type=float, default=1.0)
parser.add_argument("-o", "--out", required=True)
parser.add_argument("images", nargs="+")
args = parser.parse_args()
crops = [Image.open(path).convert("RGB").crop(tuple(args.box)) for path in args.images]
w, h = crops[0].size
figure = Image.new("RGB", (len(crops) * (w + 4) - 4, h), (255, 255, 255))
for k, crop in enumerate(crops):
    figure.paste(crop, (k * (w + 4), 0))
figure.resize((round(figure.width * args.scale), round(figure.height * args.scale)), Image.LANCZOS).save(args.out)
