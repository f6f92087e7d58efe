#!/usr/bin/python3
"""Writes a .gltf file's scene turned askew to the world's axes: its root nodes, cameras and lights
among them, under one new node turned by DEGREES about AXIS. The camera turns with the scene, so pt
renders the same image; a method whose result changes with the turn depends on where the world's
axes fall, which a file from elsewhere will not respect. docs/notes/receivers.md (*The same scene
turned*) and docs/notes/glossy.md (*Session 105*) judge iv and ar this way.

Usage: tools/scenes/turned.py IN.gltf OUT.gltf DEGREES [--axis X,Y,Z]   (default axis 1,1,1)
A .gltf's buffers stay where they were: embedded data URIs travel with it; a relative URI must
resolve beside OUT.gltf as it did beside IN.gltf. Needs only Python 3's standard library.
"""
import argparse
import json
import math
import os
import sys


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("source", help="the .gltf file to turn")
    parser.add_argument("out", help="the .gltf file to write")
    parser.add_argument("degrees", type=float, help="the turn's angle")
    parser.add_argument("--axis", default="1,1,1", help="the turn's axis, X,Y,Z (default 1,1,1)")
    args = parser.parse_args()
    try:
        axis = [float(v) for v in args.axis.split(",")]
        length = math.sqrt(sum(v * v for v in axis))
        if len(axis) != 3 or not length > 0.0 or not math.isfinite(length) or not math.isfinite(args.degrees):
            raise ValueError
    except ValueError:
        sys.exit(f"turned.py: --axis {args.axis} with {args.degrees}°: give three numbers, not all zero, and a finite angle")
    try:
        with open(args.source, encoding="utf-8") as f:
            gltf = json.load(f)
    except (OSError, ValueError) as e:
        sys.exit(f"turned.py: {args.source}: {e}")
    scenes = gltf.get("scenes") or []
    if not scenes:
        sys.exit(f"turned.py: {args.source}: no scene to turn")
    half = math.radians(args.degrees) / 2.0
    rotation = [v / length * math.sin(half) for v in axis] + [math.cos(half)]
    nodes = gltf.setdefault("nodes", [])
    for scene in scenes:  # each scene's roots under a turn of its own
        nodes.append({"name": "turn", "rotation": rotation, "children": scene.get("nodes", [])})
        scene["nodes"] = [len(nodes) - 1]
    with open(args.out + ".tmp", "w", encoding="utf-8") as f:
        json.dump(gltf, f)
    os.replace(args.out + ".tmp", args.out)


if __name__ == "__main__":
    main()
