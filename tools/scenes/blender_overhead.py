"""What the probes against Blender share: a sun 45 degrees up from +x (3 W/m^2, sharp), an
orthographic camera looking straight down from `height` over `width` metres, a black world, and
Cycles' settings (no denoising, the Standard view transform, an EXR of `size` x `size` pixels at
OUT_cycles.exr), a plane of one Principled material, image textures and a striped normal texture.
Imported by blender_normal_map.py, blender_glossy_normal_map.py and blender_cutout.py, which run
inside Blender.
"""
import math
import sys

import bpy


def start():
    """The script's OUT and its flags (what follows `--` on Blender's command line), in an empty scene."""
    args = sys.argv[sys.argv.index("--") + 1:]
    bpy.ops.wm.read_factory_settings(use_empty=True)
    return args[0], set(args[1:])


def sun_camera_and_cycles(out, width, height, size, samples, bounces):
    scene = bpy.context.scene
    bpy.ops.object.light_add(type="SUN", rotation=(0.0, math.radians(45.0), 0.0))
    sun = bpy.context.active_object.data
    sun.energy = 3.0
    sun.angle = 0.0

    bpy.ops.object.camera_add(location=(0, 0, height), rotation=(0, 0, 0))
    camera = bpy.context.active_object
    camera.data.type = "ORTHO"
    camera.data.ortho_scale = width
    scene.camera = camera
    scene.world = bpy.data.worlds.new("black")
    scene.world.color = (0, 0, 0)

    cycles(out, size, samples, bounces)


def cycles(out, size, samples, bounces):
    """Cycles without denoising, `bounces` deep, the Standard view transform, an EXR of `size` x
    `size` pixels at OUT_cycles.exr."""
    scene = bpy.context.scene
    scene.render.engine = "CYCLES"
    scene.cycles.samples = samples
    scene.cycles.use_denoising = False
    scene.cycles.max_bounces = bounces
    scene.cycles.transparent_max_bounces = bounces
    scene.render.resolution_x = scene.render.resolution_y = size
    scene.view_settings.view_transform = "Standard"
    scene.render.image_settings.file_format = "OPEN_EXR"
    scene.render.filepath = out + "_cycles.exr"


def principled_plane(size, name, base, roughness, metallic=0.0):
    """A `size` m plane at the origin with a material `name` of grey `base`, `roughness` and
    `metallic`: the plane, its material and the material's Principled BSDF node."""
    bpy.ops.mesh.primitive_plane_add(size=size)
    plane = bpy.context.active_object
    material = bpy.data.materials.new(name)
    material.use_nodes = True
    principled = material.node_tree.nodes["Principled BSDF"]
    principled.inputs["Base Color"].default_value = (base, base, base, 1)
    principled.inputs["Metallic"].default_value = metallic
    principled.inputs["Roughness"].default_value = roughness
    return plane, material, principled


def stripes_normal_map(material, out, side, tilt):
    """A `side` x `side` tangent-space normal texture whose texel (x, y) tilts the normal by
    tilt(x, y) radians toward +u (saved as OUT_stripes.png, read by its nearest texel), through a
    Normal Map node of `material`: the node's Normal output."""
    image = bpy.data.images.new("stripes", side, side, float_buffer=False)
    image.colorspace_settings.name = "Non-Color"
    pixels = []
    for y in range(side):
        for x in range(side):
            t = tilt(x, y)
            pixels += [0.5 + 0.5 * math.sin(t), 0.5, 0.5 + 0.5 * math.cos(t), 1.0]
    image.pixels = pixels
    texture = nearest_texture(material, image, out + "_stripes.png")
    normal_map = material.node_tree.nodes.new("ShaderNodeNormalMap")
    material.node_tree.links.new(texture.outputs["Color"], normal_map.inputs["Color"])
    return normal_map.outputs["Normal"]


def nearest_texture(material, image, path):
    """`image` saved as a PNG at `path` (the exporter embeds it from there), in an Image Texture
    node of `material` that reads its nearest texel."""
    image.filepath_raw = path
    image.file_format = "PNG"
    image.save()
    texture = material.node_tree.nodes.new("ShaderNodeTexImage")
    texture.image = image
    texture.interpolation = "Closest"
    return texture
