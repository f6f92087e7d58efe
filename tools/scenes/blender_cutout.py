"""Builds a grey 4 m floor (0.5) under a white 1 m screen cut by a 2x2 checker of alpha 1 and 0, lit by a
sun 45 degrees up from +x and seen straight down by an orthographic camera; renders it with Cycles
and writes it with Blender's own glTF exporter, which writes the screen's "Alpha Clip" blend mode
as alphaMode MASK: ivgi's reading of another exporter's cut-out surface, against another path
tracer.

With --blended the checker's cut cells have alpha 0.5 instead and the blend mode is "Alpha Blend",
which the exporter writes as alphaMode BLEND: those cells pass half the light and half the view.

Blender's axes: z up. The floor lies at z = 0 over x, y in [-2, 2]; the screen at z = 1 over x in
[0, 1], y in [-0.5, 0.5], so that the sun throws its shadow 1 m toward -x, beside it. The camera
sees x, y in [-2, 2] at 64x64 (16 pixels a metre, x to the right, y up).

Cycles renders Diffuse BSDFs (Lambertian; Principled's diffuse is Burley's), the screen's mixed with
a Transparent BSDF by the texture's alpha (Cycles' own alpha), into OUT_cycles.exr at 256 samples;
the exported file carries Principled BSDFs, specular 0, roughness 1. The exporter converts the
sun's W/m^2 to lux (x683), so compare regions' ratios to the lit floor, not their values.
docs/notes/gltf-conformance.md has the figures.

Usage: blender --background --factory-startup --python tools/scenes/blender_cutout.py -- OUT [--blended]
       (writes OUT.glb and OUT_cycles.exr)
Needs Debian's blender (not installed by ci/install-deps.sh: the tests do not use it).
"""
import os
import sys

import bpy

sys.path.append(os.path.dirname(os.path.abspath(__file__)))
import blender_overhead  # noqa: E402

out, flags = blender_overhead.start()
blended = "--blended" in flags


def lambertian(name, grey):
    """A material whose exported form is a Principled BSDF (grey, specular 0, roughness 1) and whose
    rendered form is a Diffuse BSDF of the same grey, both fed by the returned node tree."""
    material = bpy.data.materials.new(name)
    material.use_nodes = True
    nodes = material.node_tree.nodes
    principled = nodes["Principled BSDF"]
    principled.inputs["Base Color"].default_value = (grey, grey, grey, 1)
    principled.inputs["Roughness"].default_value = 1.0
    principled.inputs["Specular"].default_value = 0.0
    diffuse = nodes.new("ShaderNodeBsdfDiffuse")
    diffuse.inputs["Color"].default_value = (grey, grey, grey, 1)
    return material, principled, diffuse


bpy.ops.mesh.primitive_plane_add(size=4.0)
floor = bpy.context.active_object
floor_material, floor_principled, floor_diffuse = lambertian("floor", 0.5)
floor.data.materials.append(floor_material)

bpy.ops.mesh.primitive_plane_add(size=1.0, location=(0.5, 0.0, 1.0))
screen = bpy.context.active_object
screen_material, screen_principled, screen_diffuse = lambertian("screen", 0.8)
screen_material.blend_method = "BLEND" if blended else "CLIP"
screen_material.alpha_threshold = 0.5
screen_material.use_backface_culling = False
image = bpy.data.images.new("checker", 2, 2, alpha=True, float_buffer=False)
cut = 0.5 if blended else 0.0
image.pixels = [1, 1, 1, 1, 1, 1, 1, cut, 1, 1, 1, cut, 1, 1, 1, 1]  # bottom row first
texture = blender_overhead.nearest_texture(screen_material, image, out + "_checker.png")
nodes, links = screen_material.node_tree.nodes, screen_material.node_tree.links
links.new(texture.outputs["Color"], screen_principled.inputs["Base Color"])
links.new(texture.outputs["Color"], screen_diffuse.inputs["Color"])  # white: the exported base colour
links.new(texture.outputs["Alpha"], screen_principled.inputs["Alpha"])
transparent = nodes.new("ShaderNodeBsdfTransparent")
mix = nodes.new("ShaderNodeMixShader")
links.new(texture.outputs["Alpha"], mix.inputs["Fac"])
links.new(transparent.outputs["BSDF"], mix.inputs[1])
links.new(screen_diffuse.outputs["BSDF"], mix.inputs[2])
screen.data.materials.append(screen_material)

blender_overhead.sun_camera_and_cycles(out, width=4.0, height=5.0, size=64, samples=256, bounces=8)
floor_output = floor_material.node_tree.nodes["Material Output"]
screen_output = nodes["Material Output"]
floor_material.node_tree.links.new(floor_diffuse.outputs["BSDF"], floor_output.inputs["Surface"])
links.new(mix.outputs["Shader"], screen_output.inputs["Surface"])
bpy.ops.render.render(write_still=True)

floor_material.node_tree.links.new(floor_principled.outputs["BSDF"], floor_output.inputs["Surface"])
links.new(screen_principled.outputs["BSDF"], screen_output.inputs["Surface"])
for material, diffuse in ((floor_material, floor_diffuse), (screen_material, screen_diffuse)):
    material.node_tree.nodes.remove(diffuse)
nodes.remove(mix)
nodes.remove(transparent)
bpy.ops.export_scene.gltf(filepath=out + ".glb", export_format="GLB", export_cameras=True, export_lights=True)
