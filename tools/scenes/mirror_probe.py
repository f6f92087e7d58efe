#!/usr/bin/python3
"""Writes the mirror probe: a polished metal floor (4 m square, base 0.9, metallic 1) with a white
panel (0.8 m square, base 0.8) standing on it 1.125 m from its centre and facing the camera, which
looks at the panel from 2.5 m. A spot lamp in front of the panel lights it; nothing else does (no sky).
The floor mirrors the panel: how sharp and how bright that reflection comes out is what the probe
measures against pt (docs/notes/glossy.md, *Session 100*).

Render it twice, the second time with --panel-base 0, and subtract: the difference is the floor's
reflection of the panel alone (the lamp's own light on the floor is in both).

Usage: tools/scenes/mirror_probe.py OUT.gltf [--roughness 0.2] [--panel-base 0.8]
Needs only Python 3's standard library.
"""
import argparse
import base64
import json
import math
import struct


def grid(corner, u_edge, v_edge, cells_u, cells_v, normal):
    """A quad from `corner` along two edges, split into cells: positions, normals, triangle indices."""
    positions, indices = [], []
    for j in range(cells_v + 1):
        for i in range(cells_u + 1):
            s, t = i / cells_u, j / cells_v
            positions.append([corner[k] + s * u_edge[k] + t * v_edge[k] for k in range(3)])
    for j in range(cells_v):
        for i in range(cells_u):
            a = j * (cells_u + 1) + i
            indices += [a, a + 1, a + cells_u + 2, a, a + cells_u + 2, a + cells_u + 1]
    return positions, [normal] * len(positions), indices


def gltf(meshes, materials):
    """The glTF document of `meshes` (name, (positions, normals, indices), material index), one
    buffer embedded, with the probe's camera and lamp."""
    data, views, accessors, gltf_meshes = b"", [], [], []

    def add(blob, accessor):
        nonlocal data
        views.append({"buffer": 0, "byteOffset": len(data), "byteLength": len(blob)})
        data += blob
        accessors.append(dict(accessor, bufferView=len(views) - 1))
        return len(accessors) - 1

    for name, (positions, normals, indices), material in meshes:
        vec3 = lambda rows: b"".join(struct.pack("<3f", *row) for row in rows)
        position = add(vec3(positions), {"componentType": 5126, "count": len(positions), "type": "VEC3",
                                         "min": [min(p[k] for p in positions) for k in range(3)],
                                         "max": [max(p[k] for p in positions) for k in range(3)]})
        normal = add(vec3(normals), {"componentType": 5126, "count": len(normals), "type": "VEC3"})
        index = add(b"".join(struct.pack("<I", i) for i in indices),
                    {"componentType": 5125, "count": len(indices), "type": "SCALAR"})
        gltf_meshes.append({"name": name, "primitives": [
            {"attributes": {"POSITION": position, "NORMAL": normal}, "indices": index, "material": material}]})
    pitch = -0.16  # the camera looks down this many radians
    return {
        "asset": {"version": "2.0", "generator": "ivgi tools/scenes/mirror_probe.py"},
        "scene": 0,
        "scenes": [{"nodes": [0, 1, 2, 3]}],
        "nodes": [
            {"name": "floor", "mesh": 0},
            {"name": "panel", "mesh": 1},
            {"name": "camera", "camera": 0, "translation": [0, 0.5, 1.4],
             "rotation": [math.sin(pitch / 2), 0, 0, math.cos(pitch / 2)]},
            {"name": "lamp", "translation": [0, 0.4, 0.3], "extensions": {"KHR_lights_punctual": {"light": 0}}},
        ],
        "meshes": gltf_meshes,
        "materials": materials,
        "accessors": accessors,
        "bufferViews": views,
        "buffers": [{"byteLength": len(data),
                     "uri": "data:application/octet-stream;base64," + base64.b64encode(data).decode()}],
        "cameras": [{"type": "perspective", "perspective": {"yfov": 0.6, "znear": 0.01, "aspectRatio": 4 / 3}}],
        "extensionsUsed": ["KHR_lights_punctual"],
        "extensions": {"KHR_lights_punctual": {"lights": [
            {"type": "spot", "intensity": 3.0, "spot": {"innerConeAngle": 0.3, "outerConeAngle": 0.5}}]}},
    }


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("out", help="the .gltf file to write")
    parser.add_argument("--roughness", type=float, default=0.2, help="the floor's roughnessFactor")
    parser.add_argument("--panel-base", type=float, default=0.8, help="the panel's base colour (grey)")
    a = parser.parse_args()
    floor = grid([-2, 0, 2], [4, 0, 0], [0, 0, -4], 16, 16, [0, 1, 0])
    # Halfway between two rows of the floor's vertices (every 0.25 m): a sheet standing on a row of
    # them would darken the floor along its foot (README, the dark band), which is not what the
    # probe measures.
    panel = grid([-0.4, 0, -1.125], [0.8, 0, 0], [0, 0.8, 0], 4, 4, [0, 0, 1])
    materials = [
        {"name": "polished metal",
         "pbrMetallicRoughness": {"baseColorFactor": [0.9, 0.9, 0.9, 1], "metallicFactor": 1.0,
                                  "roughnessFactor": a.roughness}},
        {"name": "panel",
         "pbrMetallicRoughness": {"baseColorFactor": [a.panel_base] * 3 + [1], "metallicFactor": 0.0,
                                  "roughnessFactor": 1.0}},
    ]
    with open(a.out, "w") as f:
        json.dump(gltf([("floor", floor, 0), ("panel", panel, 1)], materials), f)


if __name__ == "__main__":
    main()
