"""Makes blend_samples/sphere_plane.blend: a sphere and a box on a ground plane
under a sun 5 degrees wide, seen by a perspective camera, with a dim world.
The simplest scene for comparing RTSDF's soft shadows with Cycles.

blender -b --factory-startup --python blend_samples/make_sphere_plane.py -- OUT.blend
"""
import math
import os
import sys

import bpy

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from sample_scene import add_sun, finish, material, new_scene  # noqa: E402


def main():
    out, scene = new_scene("sphere_plane.blend")

    bpy.ops.mesh.primitive_plane_add(size=8.0, location=(0, 0, 0))
    bpy.context.object.name = "Ground"
    bpy.context.object.data.materials.append(material("Ground", (0.8, 0.8, 0.8)))
    bpy.ops.mesh.primitive_uv_sphere_add(radius=0.6, location=(-0.6, 0.2, 0.9), segments=64, ring_count=32)
    bpy.context.object.name = "Sphere"
    bpy.ops.object.shade_smooth()
    bpy.context.object.data.materials.append(material("Sphere", (0.8, 0.3, 0.2)))
    bpy.ops.mesh.primitive_cube_add(size=0.8, location=(1.0, -0.6, 0.4), rotation=(0, 0, math.radians(30)))
    bpy.context.object.name = "Box"
    bpy.context.object.data.materials.append(material("Box", (0.2, 0.4, 0.8)))

    add_sun(scene, (40, 0, 30))

    camera = bpy.data.objects.new("Camera", bpy.data.cameras.new("Camera"))
    camera.location = (0.0, -6.5, 4.5)
    camera.rotation_euler = (math.radians(58), 0, 0)
    scene.collection.objects.link(camera)
    scene.camera = camera

    finish(scene, out)


main()
