"""Makes large_small.blend: small objects far apart on a very large ground,
the test of fitting SDF grids to the shadow casters rather than to the scene's
bounds. A "Ground" 200 x 200 units; a "Box" (0.8), a "Sphere" (radius 0.5) and
a "Cylinder" (0.7 wide, 1 high) 30 units apart in a line that the camera looks
along, and two more out of its view, a "Cube" (0.2) and a "Cone" (0.6 high),
40-60 units from the others; a sun 40 degrees high (3 degrees wide) throws
their shadows sideways across the camera's view.

blender -b --factory-startup --python blend_samples/make_large_small.py -- OUT.blend
"""
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from sample_scene import (add_boxes, add_camera, add_ground, add_primitive, add_sun,  # noqa: E402
                          finish, new_scene, sun_rotation)


def main():
    out, scene = new_scene("large_small.blend")

    add_ground(scene, 200.0)
    # In view, along the camera's line of sight.
    add_boxes(scene, "Box", [((0.8, 0.8, 0.8), (0, 0, 0.4), 30)], (0.2, 0.4, 0.8), (0.0, 10.0, 0))
    add_primitive("uv_sphere", "Sphere", (0.8, 0.3, 0.2),
                  smooth=True, radius=0.5, location=(-2.0, 40.0, 0.5), segments=32, ring_count=16)
    add_primitive("cylinder", "Cylinder", (0.3, 0.7, 0.35),
                  vertices=32, radius=0.35, depth=1.0, location=(2.0, 70.0, 0.5))
    # Out of view.
    add_boxes(scene, "Cube", [((0.2, 0.2, 0.2), (0, 0, 0.1))], (0.8, 0.7, 0.3), (-45.0, -30.0, 0))
    add_primitive("cone", "Cone", (0.6, 0.4, 0.7),
                  vertices=32, radius1=0.3, depth=0.6, location=(55.0, 30.0, 0.3))

    # Shadows fall to the camera's left (-x), a little towards it.
    add_sun(scene, sun_rotation(40, 110), strength=3.0, angle_degrees=3.0)
    add_camera(scene, (1.5, -6.0, 7.0), (0.0, 25.0, 0.0), lens=40.0, clip_end=300.0)

    finish(scene, out)


main()
