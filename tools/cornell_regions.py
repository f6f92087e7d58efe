#!/usr/bin/python3
"""Region means of a render of the built-in Cornell box against a reference of the same frame.

Frame 0 of `ivgi render cornell` (any --cells, any --size with the default camera): each region is
picked from the reference's own layers (normal, depth, albedo, emission, pixel position), so the
same regions are measured in any test image of that frame (pixels the reference covers in part, along
the box's outline, are left out). Prints, per region, its pixels and the
ratio of the test's mean radiance to the reference's, then the whole image's relMSE.

    tools/cornell_regions.py TEST.exr REF.exr [--json FILE]

Needs Debian's python3-numpy and oiiotool (openimageio-tools); run it with /usr/bin/python3.
"""
import argparse
import json
import re
import subprocess
import sys

import numpy as np


def load(path):
    """The EXR's channels as an array (height, width, channels), with their names."""
    info = subprocess.run(["oiiotool", "--info", "-v", path], capture_output=True, text=True, check=True).stdout
    names = [n.strip() for n in re.search(r"channel list: (.*)", info).group(1).split(",")]
    dump = subprocess.run(["oiiotool", "--dumpdata", path], capture_output=True, text=True, check=True).stdout
    lines = dump.splitlines()
    w, h = map(int, re.match(r".*:\s*(\d+)\s*x\s*(\d+),", lines[0]).groups())
    pixels = [line.split(":", 1)[1].split() for line in lines[1:] if line.strip().startswith("Pixel")]
    return np.array(pixels, dtype=np.float64).reshape(h, w, len(names)), names


def channels(image, names, wanted):
    return np.stack([image[:, :, names.index(n)] for n in wanted], axis=-1)


def grow(mask, pixels):
    """The mask dilated by `pixels` (a square neighbourhood)."""
    out = mask.copy()
    for dy in range(-pixels, pixels + 1):
        for dx in range(-pixels, pixels + 1):
            out |= np.roll(np.roll(mask, dy, axis=0), dx, axis=1)
    return out


def regions(ref, names):
    """Named masks of the Cornell box's surfaces in frame 0, from the reference's layers."""
    h, w = ref.shape[:2]
    n = channels(ref, names, ["N.X", "N.Y", "N.Z"])
    z = ref[:, :, names.index("Z")]
    albedo = channels(ref, names, ["albedo.R", "albedo.G", "albedo.B"])
    emission = channels(ref, names, ["emission.R", "emission.G", "emission.B"]).sum(-1)
    lum = channels(ref, names, ["R", "G", "B"]).mean(-1)
    ys, xs = np.mgrid[0:h, 0:w] * np.array([240.0 / h, 320.0 / w])[:, None, None]  # in 320×240 pixels
    # Pixels wholly on the box: along its outline a pixel's covered share differs between a 4×4 grid
    # of samples and pt's random ones (up to a sixteenth of the pixel a row), which no solver changes.
    hit = (z > 0) & (ref[:, :, names.index("A")] > 0.999)
    up, down = hit & (n[..., 1] > 0.9), hit & (n[..., 1] < -0.9)
    towards = hit & (n[..., 2] < -0.9)  # faces toward the camera
    red = hit & (n[..., 0] < -0.9) & (albedo[..., 0] > 0.5) & (albedo[..., 1] < 0.2)
    green = hit & (n[..., 0] > 0.9) & (albedo[..., 1] > 0.3) & (albedo[..., 0] < 0.3)
    back_wall = towards & (np.abs(n[..., 0]) < 0.1) & (z > 1.33)
    short_front = towards & (n[..., 0] > 0.1) & (z < 0.95)
    short_top = up & (ys < 175) & (z < 1.0)
    tall_front = towards & (n[..., 0] < -0.1) & (z < 1.3)
    floor = up & ~short_top
    ceiling = down & (emission <= 0)
    walls = red | green | back_wall
    shadow_box = (xs >= 70) & (xs < 92) & (ys >= 150) & (ys < 205)
    floor_lit = np.median(lum[floor])
    masks = {
        "short block, front": short_front,
        "short block, top": short_top,
        "tall block, front": tall_front,
        "floor, front": floor & (z < 1.0),
        "floor, back": floor & (z > 1.15),
        "floor, shadowed (below half its median)": floor & (lum < 0.5 * floor_lit),
        "floor under the short block's front edge": floor & grow(short_front, 3) & (ys > 200),
        "back wall": back_wall,
        "left wall": red & ~shadow_box,
        "left wall in the tall block's shadow": red & shadow_box,
        "right wall": green,
        "ceiling": ceiling & ~grow(walls, 3),
        "ceiling-wall edge": ceiling & grow(walls, 3),
    }
    return masks


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("test")
    parser.add_argument("reference")
    parser.add_argument("--json", help="write the figures here too")
    args = parser.parse_args()
    test, tnames = load(args.test)
    ref, rnames = load(args.reference)
    if test.shape[:2] != ref.shape[:2]:
        sys.exit(f"cornell_regions: {args.test} and {args.reference} differ in size")
    t = channels(test, tnames, ["R", "G", "B"])
    r = channels(ref, rnames, ["R", "G", "B"])
    masks = regions(ref, rnames)
    rows = {}
    print(f"{'region':45s} {'pixels':>7s} {'test/ref':>9s}")
    for name, mask in masks.items():
        count = int(mask.sum())
        ratio = float(t[mask].sum() / max(r[mask].sum(), 1e-30)) if count else float("nan")
        rows[name] = {"pixels": count, "ratio": ratio}
        print(f"{name:45s} {count:7d} {ratio:9.3f}")
    relmse = float(np.mean((t - r) ** 2 / (r**2 + 0.01)))
    print(f"{'relMSE (whole image)':45s} {'':7s} {relmse:9.5f}")
    if args.json:
        with open(args.json, "w") as f:
            json.dump({"regions": rows, "relMSE": relmse}, f, indent=1)


if __name__ == "__main__":
    main()
