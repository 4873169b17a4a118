"""Pieces every sample scene script shares: diffuse materials, a sun, the
dim world, and the render settings the comparisons use (640x360, Standard
view transform, Cycles with direct light only and no denoiser, as RTSDF
shades). Imported by the make_*.py scripts, which Blender runs."""
import math

import bpy


def material(name, color):
    """A rough, non-specular Principled material (and the same viewport colour)."""
    mat = bpy.data.materials.new(name)
    mat.use_nodes = True
    bsdf = mat.node_tree.nodes["Principled BSDF"]
    bsdf.inputs["Base Color"].default_value = (*color, 1.0)
    bsdf.inputs["Specular"].default_value = 0.0
    bsdf.inputs["Roughness"].default_value = 1.0
    mat.diffuse_color = (*color, 1.0)
    return mat


def add_sun(scene, rotation_degrees, strength=3.0, angle_degrees=5.0):
    sun = bpy.data.lights.new("Sun", "SUN")
    sun.energy = strength
    sun.angle = math.radians(angle_degrees)
    sun_object = bpy.data.objects.new("Sun", sun)
    sun_object.rotation_euler = tuple(math.radians(a) for a in rotation_degrees)
    scene.collection.objects.link(sun_object)
    return sun_object


def finish(scene, out):
    """Dim world, comparison render settings, then save to `out`."""
    world = bpy.data.worlds.new("World")
    world.use_nodes = True
    world.node_tree.nodes["Background"].inputs["Color"].default_value = (0.05, 0.05, 0.05, 1.0)
    scene.world = world
    scene.render.resolution_x, scene.render.resolution_y = 640, 360
    scene.render.resolution_percentage = 100
    scene.view_settings.view_transform = "Standard"
    scene.cycles.samples = 64
    scene.cycles.use_denoising = False
    scene.cycles.max_bounces = 0
    scene.eevee.use_soft_shadows = True
    scene.eevee.shadow_cascade_size = "4096"
    bpy.ops.wm.save_as_mainfile(filepath=out)
    print(f"wrote {out}")
