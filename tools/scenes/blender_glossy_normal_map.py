"""Builds a 2 m rough metal plane (base 0.9, roughness 0.35) under a white sky (radiance 1), seen
by an orthographic camera 30 degrees above its horizon, and renders it with Cycles and writes it
with Blender's own glTF exporter. Its normal comes from a 48x48 tangent-space normal texture of
three 16-texel stripes across the view: flat, tilted TILT degrees (25 by default) toward +u (toward
the camera) and toward -u (away from it). Seen 60 degrees from the plane's normal, the view's
mirror direction about the last stripe's normal lies below the plane's horizon: how a renderer
treats a shading normal there decides that stripe's light. docs/notes/gltf-conformance.md has the
figures. With --plain the plane has no normal texture.

Cycles renders the Principled BSDF with one bounce into OUT_cycles.exr at 96x96 and 256 samples.

Usage: blender --background --factory-startup --python tools/scenes/blender_glossy_normal_map.py -- OUT [--tilt=DEGREES] [--plain]
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
tilt = math.radians(next((float(f.split("=")[1]) for f in flags if f.startswith("--tilt=")), 25.0))

plane, material, principled = blender_overhead.principled_plane(2.0, "metal", 0.9, roughness=0.35, metallic=1.0)

if "--plain" not in flags:
    normal = blender_overhead.stripes_normal_map(material, out, 48, lambda x, y: (0.0, tilt, -tilt)[y // 16])
    material.node_tree.links.new(normal, principled.inputs["Normal"])
plane.data.materials.append(material)

scene = bpy.context.scene
elevation = math.radians(30.0)
bpy.ops.object.camera_add(location=(10 * math.cos(elevation), 0, 10 * math.sin(elevation)),
                          rotation=(math.pi / 2 - elevation, 0, math.pi / 2))
camera = bpy.context.active_object
camera.data.type = "ORTHO"
camera.data.ortho_scale = 2.2
scene.camera = camera
scene.world = bpy.data.worlds.new("white")
scene.world.color = (1, 1, 1)

blender_overhead.cycles(out, size=96, samples=256, bounces=1)
bpy.ops.render.render(write_still=True)
bpy.ops.export_scene.gltf(filepath=out + ".glb", export_format="GLB", export_cameras=True)
