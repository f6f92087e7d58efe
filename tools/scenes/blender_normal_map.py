"""Builds a grey 2 m plane under a sun 45 degrees up from +x, seen straight down by an orthographic
camera, renders it with Cycles, and writes it with Blender's own glTF exporter. With --striped its
normal comes from a 64x64 tangent-space normal texture of 8-texel stripes tilted 30 degrees toward
+u and -u in turn (a Normal Map node), which the exporter writes as normalTexture: ivgi's reading
of another exporter's normal texture, against another path tracer.

Cycles renders a Diffuse BSDF (Lambertian; Principled's diffuse is Burley's) with one bounce into
OUT_cycles.exr at 64x64 and 64 samples; the exported file carries the Principled BSDF, specular 0,
roughness 1. The exporter converts the sun's W/m^2 to lux (x683), so compare the two renders'
ratios (striped over plain), not their values. docs/notes/gltf-conformance.md has the figures.

Usage: blender --background --factory-startup --python tools/scenes/blender_normal_map.py -- OUT [--striped]
       (writes OUT.glb and OUT_cycles.exr)
Needs Debian's blender (not installed by ci/install-deps.sh: the tests do not use it).
"""
import math
import os
import sys

import bpy

sys.path.append(os.path.dirname(os.path.abspath(__file__)))
import blender_overhead  # noqa: E402

out, flags = blender_overhead.start()
striped = "--striped" in flags

plane, material, principled = blender_overhead.principled_plane(2.0, "tile", 0.5, roughness=1.0)
principled.inputs["Specular"].default_value = 0.0
nodes, links = material.node_tree.nodes, material.node_tree.links
diffuse = nodes.new("ShaderNodeBsdfDiffuse")
diffuse.inputs["Color"].default_value = (0.5, 0.5, 0.5, 1)
if striped:
    normal = blender_overhead.stripes_normal_map(
        material, out, 64, lambda x, y: math.radians(30.0) * (1 if (x // 8) % 2 == 0 else -1))
    links.new(normal, principled.inputs["Normal"])
    links.new(normal, diffuse.inputs["Normal"])
plane.data.materials.append(material)
output = nodes["Material Output"]

blender_overhead.sun_camera_and_cycles(out, width=2.0, height=3.0, size=64, samples=64, bounces=1)
links.new(diffuse.outputs["BSDF"], output.inputs["Surface"])
bpy.ops.render.render(write_still=True)

links.new(principled.outputs["BSDF"], output.inputs["Surface"])
nodes.remove(diffuse)
bpy.ops.export_scene.gltf(filepath=out + ".glb", export_format="GLB", export_cameras=True, export_lights=True)
