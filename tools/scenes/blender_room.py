"""Builds a room in Blender and writes it with Blender's own glTF exporter: white walls (albedo 0.7),
a subdivided Suzanne turning once in 2 s, a sphere, a torus and an emissive panel in the ceiling, and a camera. It is
the kind of file ivgi's users export themselves (about 36,000 vertices); benchmarks and
tools/perf_tables.py render it.

With --vertex-colours the left wall is painted red and the right wall green, and the sphere with a
gradient from bottom to top, in colour attributes on white materials: the exporter writes them as
COLOR_0, which glTF multiplies into the base colour.

With --textured-panel the panel's emission comes from an image texture that glows only in six bars
(29 % of it; the rest black), at a strength that keeps its power near the plain panel's:
the exporter writes it as emissiveTexture, as a sign or a screen would come.

Usage: blender --background --factory-startup --python tools/scenes/blender_room.py -- OUT.glb
       [--vertex-colours] [--textured-panel]
Needs Debian's blender (not installed by ci/install-deps.sh: the tests do not use it).
"""
import math
import sys

import bpy


def material(name, colour, emission=None, strength=0.0):
    m = bpy.data.materials.new(name)
    m.use_nodes = True
    bsdf = m.node_tree.nodes["Principled BSDF"]
    bsdf.inputs["Base Color"].default_value = (*colour, 1.0)
    bsdf.inputs["Roughness"].default_value = 1.0
    bsdf.inputs["Specular"].default_value = 0.0
    if emission:
        bsdf.inputs["Emission"].default_value = (*emission, 1.0)
        bsdf.inputs["Emission Strength"].default_value = strength
    return m


def glowing_bars(name, width=128, height=64):
    """An image, packed into the file, black but for six white bars (29 % of its texels)."""
    image = bpy.data.images.new(name, width, height, alpha=False)
    pixels = [0.0] * (4 * width * height)
    for k, (x0, x1) in enumerate([(8, 20), (28, 34), (42, 60), (70, 76), (84, 100), (108, 118)]):
        y0, y1 = (12, 52) if k % 2 == 0 else (20, 44)
        for y in range(y0, y1):
            for x in range(x0, x1):
                pixels[4 * (y * width + x):4 * (y * width + x) + 3] = (1.0, 1.0, 1.0)
    for i in range(3, len(pixels), 4):
        pixels[i] = 1.0
    image.pixels = pixels
    image.pack()
    return image


def textured_emission(m, image):
    """Links an image texture into `m`'s emission colour."""
    node = m.node_tree.nodes.new("ShaderNodeTexImage")
    node.image = image
    m.node_tree.links.new(node.outputs["Color"], m.node_tree.nodes["Principled BSDF"].inputs["Emission"])


def plane(name, location, rotation, size, cuts, mat, scale=(1.0, 1.0, 1.0)):
    bpy.ops.mesh.primitive_grid_add(x_subdivisions=cuts, y_subdivisions=cuts, size=size, location=location,
                                    rotation=rotation)
    obj = bpy.context.active_object
    obj.scale = scale
    obj.name = name
    obj.data.materials.append(mat)
    return obj


def paint(obj, colour_of):
    """Colours each vertex of `obj` by colour_of(its world position), in a colour attribute per point."""
    attribute = obj.data.color_attributes.new(name="Col", type="FLOAT_COLOR", domain="POINT")
    for vertex, value in zip(obj.data.vertices, attribute.data):
        value.color = (*colour_of(obj.matrix_world @ vertex.co), 1.0)
    obj.data.color_attributes.active_color = attribute


def turn(obj, seconds):
    """Keys `obj` to turn once about the vertical axis in `seconds`, evenly, from its pose now."""
    scene = bpy.context.scene
    frames = round(seconds * scene.render.fps)
    scene.frame_start, scene.frame_end = 0, frames  # the exporter writes frame f at f / fps seconds
    start = obj.rotation_euler.z
    for frame, angle in ((0, start), (frames, start + 2 * math.pi)):
        obj.rotation_euler.z = angle
        obj.keyframe_insert("rotation_euler", index=2, frame=frame)
    for curve in obj.animation_data.action.fcurves:
        for key in curve.keyframe_points:
            key.interpolation = "LINEAR"
    obj.rotation_euler.z = start


def main(out, vertex_colours, textured_panel):
    bpy.ops.wm.read_factory_settings(use_empty=True)
    white = material("walls", (0.7, 0.7, 0.7))
    # A 4 m × 4 m room, 3 m high, floor at z = 0 (Blender's up is +z; the exporter turns it to +y).
    w, h = 4.0, 3.0
    plane("floor", (0, 0, 0), (0, 0, 0), w, 12, white)
    plane("ceiling", (0, 0, h), (math.pi, 0, 0), w, 12, white)
    plane("back", (0, w / 2, h / 2), (math.pi / 2, 0, 0), w, 12, white, (1, h / w, 1))
    plane("front", (0, -w / 2, h / 2), (-math.pi / 2, 0, 0), w, 12, white, (1, h / w, 1))
    left = plane("left", (-w / 2, 0, h / 2), (0, math.pi / 2, 0), w, 12, white, (h / w, 1, 1))
    right = plane("right", (w / 2, 0, h / 2), (0, -math.pi / 2, 0), w, 12, white, (h / w, 1, 1))
    if vertex_colours:  # the walls' albedo 0.7 times these
        paint(left, lambda p: (1.0, 0.15, 0.15))
        paint(right, lambda p: (0.15, 1.0, 0.15))
    panel_material = material("panel", (0.0, 0.0, 0.0), (1.0, 0.95, 0.85), 40.0 if textured_panel else 12.0)
    if textured_panel:
        textured_emission(panel_material, glowing_bars("bars"))
    panel = plane("panel", (0, 0, h - 0.01), (math.pi, 0, 0), 1.0, 1, panel_material)
    panel.scale = (1.0, 0.6, 1.0)

    bpy.ops.mesh.primitive_monkey_add(size=1.2, location=(-0.6, 0.4, 0.9), rotation=(0, 0, math.radians(20)))
    monkey = bpy.context.active_object
    monkey.name = "suzanne"
    bpy.ops.object.shade_smooth()
    sub = monkey.modifiers.new("subdivision", "SUBSURF")
    sub.levels = sub.render_levels = 3
    monkey.data.materials.append(material("suzanne", (0.8, 0.45, 0.2)))
    turn(monkey, seconds=2.0)

    bpy.ops.mesh.primitive_uv_sphere_add(segments=64, ring_count=32, radius=0.45, location=(0.9, -0.3, 0.45))
    bpy.ops.object.shade_smooth()
    sphere = bpy.context.active_object
    if vertex_colours:
        sphere.data.materials.append(material("sphere", (1.0, 1.0, 1.0)))
        paint(sphere, lambda p: (1.0 - p.z / 0.9, 0.3, p.z / 0.9))
    else:
        sphere.data.materials.append(material("sphere", (0.2, 0.4, 0.8)))

    bpy.ops.mesh.primitive_torus_add(major_radius=0.45, minor_radius=0.15, major_segments=64, minor_segments=24,
                                     location=(0.6, 1.1, 0.15))
    bpy.ops.object.shade_smooth()
    bpy.context.active_object.data.materials.append(material("torus", (0.3, 0.7, 0.3)))

    bpy.ops.object.camera_add(location=(0.0, -1.85, 1.5), rotation=(math.radians(80), 0, 0))
    camera = bpy.context.active_object
    camera.data.angle = math.radians(75)
    bpy.context.scene.camera = camera

    bpy.ops.export_scene.gltf(filepath=out, export_format="GLB", export_apply=True, export_cameras=True,
                              export_lights=False)


if __name__ == "__main__":
    args = sys.argv[sys.argv.index("--") + 1:]
    main(args[0], "--vertex-colours" in args[1:], "--textured-panel" in args[1:])
