"""Makes a scene lit by a point, a spot and an area light (no sun): the check
that RTSDF's light units, falloff, cones and soft shadows match Cycles.

blender -b --factory-startup --python blend_samples/make_lights.py -- OUT.blend
"""
import math
import os
import sys

import bpy
from mathutils import Vector

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from sample_scene import finish, material, new_scene  # noqa: E402


def add_light(scene, kind, location, target, **settings):
    light = bpy.data.lights.new(kind.title(), kind)
    for name, value in settings.items():
        setattr(light, name, value)
    obj = bpy.data.objects.new(kind.title(), light)
    obj.location = location
    obj.rotation_euler = (Vector(target) - Vector(location)).to_track_quat("-Z", "Y").to_euler()
    scene.collection.objects.link(obj)


def main():
    out, scene = new_scene("lights.blend")
    bpy.ops.mesh.primitive_plane_add(size=8.0)
    bpy.context.object.data.materials.append(material("Ground", (0.8, 0.8, 0.8)))
    for i, (x, y) in enumerate(((-1.6, 0.4), (0.0, -0.4), (1.6, 0.4))):
        bpy.ops.mesh.primitive_cube_add(size=0.6, location=(x, y, 0.3), rotation=(0, 0, math.radians(20 * i)))
        bpy.context.object.data.materials.append(material(f"Box{i}", (0.3 + 0.2 * i, 0.5, 0.7 - 0.2 * i)))
    add_light(scene, "POINT", (-1.6, -0.6, 1.6), (-1.6, 0.4, 0.0), energy=150.0, shadow_soft_size=0.15)
    add_light(scene, "SPOT", (0.0, -1.6, 2.2), (0.0, -0.4, 0.0), energy=400.0, shadow_soft_size=0.1,
              spot_size=math.radians(50), spot_blend=0.3)
    add_light(scene, "AREA", (1.6, -0.4, 1.8), (1.6, 0.4, 0.0), energy=120.0, size=0.4)
    camera = bpy.data.objects.new("Camera", bpy.data.cameras.new("Camera"))
    camera.location = (0.0, -6.0, 4.0)
    camera.rotation_euler = (Vector((0.0, 0.0, 0.2)) - camera.location).to_track_quat("-Z", "Y").to_euler()
    scene.collection.objects.link(camera)
    scene.camera = camera
    finish(scene, out)


main()
