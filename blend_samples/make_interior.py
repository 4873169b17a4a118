"""Makes interior.blend: a living room like the RTSDF paper's. A closed room
(floor "Ground", walls, ceiling) with a window in its left wall; a sun 3 degrees
wide shines in through it and lays a patch of light on the floor, across the
thin legs of two chairs (0.035 thick) by a table. A sofa and a bookshelf stand
by the other walls. The camera stands inside, in a corner, looking at the sun
patch and the window.

blender -b --factory-startup --python blend_samples/make_interior.py -- OUT.blend
"""
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from sample_scene import add_boxes, add_camera, add_chair, add_ground, add_sun, finish, new_scene, sun_rotation  # noqa: E402

# The room's inside: x in [-3, 3], y in [-2.5, 2.5], z in [0, 2.7]; walls 0.15 thick.
X, Y, H, T = 3.0, 2.5, 2.7, 0.15
# The window in the left wall (x = -X): y in [-WY, WY], z in [W0, W1].
WY, W0, W1 = 1.1, 0.7, 2.2


def main():
    out, scene = new_scene("interior.blend")

    add_ground(scene, (2 * X, 2 * Y), (0.75, 0.62, 0.45))
    walls = [
        ((T, 2 * Y + 2 * T, H), (X + T / 2, 0, H / 2)),  # right
        ((2 * X + 2 * T, T, H), (0, Y + T / 2, H / 2)),  # back
        ((2 * X + 2 * T, T, H), (0, -Y - T / 2, H / 2)),  # front (behind the camera)
        # The left wall, around the window.
        ((T, Y + T - WY, H), (-X - T / 2, -(Y + T + WY) / 2, H / 2)),
        ((T, Y + T - WY, H), (-X - T / 2, (Y + T + WY) / 2, H / 2)),
        ((T, 2 * WY, W0), (-X - T / 2, 0, W0 / 2)),
        ((T, 2 * WY, H - W1), (-X - T / 2, 0, (H + W1) / 2)),
    ]
    add_boxes(scene, "Walls", walls, (0.85, 0.85, 0.8))
    add_boxes(scene, "Ceiling", [((2 * X + 2 * T, 2 * Y + 2 * T, T), (0, 0, H + T / 2))], (0.9, 0.9, 0.9))

    # A table with two chairs, in the sun patch.
    table = [((1.1, 0.7, 0.04), (0, 0, 0.73))]
    table += [((0.05, 0.05, 0.71), (sx * 0.49, sy * 0.29, 0.355)) for sx in (-1, 1) for sy in (-1, 1)]
    add_boxes(scene, "Table", table, (0.45, 0.3, 0.18), (0.4, 1.6, 0))
    chair = add_chair(scene, "Chair1", (-1.3, 0.2, 0), 130, (0.7, 0.25, 0.2))
    chair["rtsdf_bench_mover"] = True  # bench/run moves it to measure ghosting
    add_chair(scene, "Chair2", (-0.4, 0.85, 0), 166, (0.25, 0.45, 0.65))

    # A sofa by the back wall.
    sofa = [((2.0, 0.85, 0.42), (0, 0, 0.21)), ((2.0, 0.2, 0.45), (0, 0.325, 0.645)),
            ((0.2, 0.85, 0.22), (-0.9, 0, 0.53)), ((0.2, 0.85, 0.22), (0.9, 0, 0.53))]
    add_boxes(scene, "Sofa", sofa, (0.3, 0.5, 0.35), (1.5, Y - 0.45, 0))

    # A bookshelf by the right wall, with a few books.
    shelf = [((0.35, 0.03, 1.8), (0, sy * 0.5, 0.9)) for sy in (-1, 1)]
    shelf += [((0.35, 1.0, 0.025), (0, 0, 0.05 + 0.42 * i)) for i in range(5)]
    shelf += [((0.25, 0.06, 0.28), (0.02, -0.4 + 0.08 * i, 0.2125 + 0.42 * (i % 3))) for i in range(8)]
    add_boxes(scene, "Shelf", shelf, (0.55, 0.4, 0.25), (X - 0.2, -1.2, 0))

    # The sun comes in through the window, towards +x and a little towards +y.
    add_sun(scene, sun_rotation(32, -75), strength=3.0, angle_degrees=3.0)
    add_camera(scene, (2.5, -2.2, 1.7), (-1.0, 0.2, 0.3), lens=20.0)

    finish(scene, out)


main()
