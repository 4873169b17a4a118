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
from sample_scene import add_primitive, add_sun, finish, new_scene  # noqa: E402


def main():
    out, scene = new_scene("sphere_plane.blend")

    add_primitive("plane", "Ground", (0.8, 0.8, 0.8), size=8.0, location=(0, 0, 0))
    add_primitive("uv_sphere", "Sphere", (0.8, 0.3, 0.2),
                  smooth=True, radius=0.6, location=(-0.6, 0.2, 0.9), segments=64, ring_count=32)
    add_primitive("cube", "Box", (0.2, 0.4, 0.8),
                  size=0.8, location=(1.0, -0.6, 0.4), rotation=(0, 0, math.radians(30)))

    add_sun(scene, (40, 0, 30))

    camera = bpy.data.objects.new("Camera", bpy.data.cameras.new("Camera"))
    camera.location = (0.0, -6.5, 4.5)
    camera.rotation_euler = (math.radians(58), 0, 0)
    scene.collection.objects.link(camera)
    scene.camera = camera

    finish(scene, out)


main()
