"""Makes thin.blend: thin geometry and its shadows. A picket fence of slats
0.02 thick on two rails; a plant whose leaves are closed boxes 0.005 thick on a
stem 0.012 thick; two floating plates 0.005 thick; a one-sided square sheet (a
single quad) on a slant; a chair with legs 0.03 thick; all on a ground under a sun 35
degrees high and 3 degrees wide, whose shadows fall towards the camera's
left.

blender -b --factory-startup --python blend_samples/make_thin.py -- OUT.blend
"""
import math
import os
import sys

import bpy

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from sample_scene import (add_boxes, add_camera, add_chair, add_ground, add_sun, finish,  # noqa: E402
                          material, new_scene, sun_rotation)


def main():
    out, scene = new_scene("thin.blend")

    add_ground(scene, 20.0)

    # The fence along x, behind the other things: slats 0.08 wide, 0.02 thick.
    fence = [((0.08, 0.02, 1.0), (-2.4 + 0.16 * i, 0, 0.5)) for i in range(24)]
    fence += [((3.8, 0.03, 0.05), (-0.56, 0.025, h)) for h in (0.25, 0.75)]
    add_boxes(scene, "Fence", fence, (0.85, 0.82, 0.7), (0, 1.6, 0))

    # A plant: a thin stem with leaves 0.005 thick, tilted this way and that.
    plant = [((0.012, 0.012, 0.9), (0, 0, 0.45))]
    for i in range(8):
        turn, height = 137.5 * i, 0.25 + 0.08 * i
        direction = math.radians(turn)
        reach = 0.11
        plant.append(((0.2, 0.07, 0.005), (reach * math.cos(direction), reach * math.sin(direction), height),
                      (0.0, -25.0 + 5 * (i % 3), turn)))
    add_boxes(scene, "Plant", plant, (0.25, 0.6, 0.2), (1.5, 0.2, 0))

    # Floating plates, closed boxes 0.005 thick.
    plate = add_boxes(scene, "Plate1", [((0.6, 0.4, 0.005), (0, 0, 0))], (0.8, 0.4, 0.2), (-0.1, -0.8, 0.55))
    plate.rotation_euler = (math.radians(20), math.radians(-10), math.radians(15))
    plate = add_boxes(scene, "Plate2", [((0.35, 0.35, 0.005), (0, 0, 0))], (0.3, 0.5, 0.8), (0.9, -0.6, 0.35))
    plate.rotation_euler = (math.radians(20), 0, math.radians(-20))

    # A one-sided sheet: a single quad, standing at a slant.
    mesh = bpy.data.meshes.new("Sheet")
    mesh.from_pydata([(-0.3, 0, -0.3), (0.3, 0, -0.3), (0.3, 0, 0.3), (-0.3, 0, 0.3)], [], [(0, 1, 2, 3)])
    mesh.materials.append(material("Sheet", (0.75, 0.75, 0.3)))
    sheet = bpy.data.objects.new("Sheet", mesh)
    sheet.location = (-1.9, 0.3, 0.45)
    sheet.rotation_euler = (math.radians(-60), 0, math.radians(25))
    scene.collection.objects.link(sheet)

    add_chair(scene, "Chair", (-0.9, -0.3, 0), 20, (0.6, 0.3, 0.25), leg=0.03)

    # Shadows fall towards the camera and to its left.
    add_sun(scene, sun_rotation(35, 150), strength=3.0, angle_degrees=3.0)
    add_camera(scene, (1.0, -5.6, 2.8), (-0.5, -0.1, 0.2), lens=38.0)

    finish(scene, out)


main()
