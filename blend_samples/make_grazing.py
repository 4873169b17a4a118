"""Makes grazing.blend: a sun 6 degrees above the horizon (2 degrees wide)
behind a few objects, a "Box", a "Tower", a "Cylinder" and a "Sphere", whose
long shadows (about ten times their height) run over the ground towards the
camera.

blender -b --factory-startup --python blend_samples/make_grazing.py -- OUT.blend
"""
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from sample_scene import (add_boxes, add_camera, add_ground, add_primitive, add_sun,  # noqa: E402
                          finish, new_scene, sun_rotation)


def main():
    out, scene = new_scene("grazing.blend")

    add_ground(scene, 60.0)
    add_boxes(scene, "Box", [((0.6, 0.6, 0.6), (0, 0, 0.3), 25)], (0.2, 0.4, 0.8), (-1.6, 4.0, 0))
    add_boxes(scene, "Tower", [((0.35, 0.35, 1.0), (0, 0, 0.5), -10)], (0.8, 0.7, 0.3), (1.8, 6.5, 0))
    add_primitive("cylinder", "Cylinder", (0.3, 0.7, 0.35),
                  vertices=32, radius=0.3, depth=0.8, location=(0.4, 2.5, 0.4))
    add_primitive("uv_sphere", "Sphere", (0.8, 0.3, 0.2),
                  smooth=True, radius=0.4, location=(-0.4, 8.0, 0.4), segments=32, ring_count=16)

    # Light travels towards the camera (-y), turned a little towards -x.
    add_sun(scene, sun_rotation(6, 170), strength=5.0, angle_degrees=2.0)
    add_camera(scene, (0.5, -12.5, 4.5), (0.3, -1.0, 0.0), lens=36.0)

    finish(scene, out)


main()
