"""Makes animated.blend: 48 frames (1-48) of moving and deforming shadow
casters on a ground under a sun 45 degrees high and 3 degrees wide. A
"Sphere" slides across the ground (linear keyframes), a "Box" turns half a
turn about z, a "Bender" column bends over and back up (a Simple Deform
"Bend" modifier with a keyframed angle), and a "Flag" on a "Pole" ripples (a
Wave modifier).

blender -b --factory-startup --python blend_samples/make_animated.py -- OUT.blend
"""
import math
import os
import sys

import bpy

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from sample_scene import (add_boxes, add_camera, add_ground, add_primitive, add_sun,  # noqa: E402
                          finish, material, new_scene, sun_rotation)

FIRST, LAST = 1, 48


def linear(obj):
    """Linear interpolation for every keyframe of `obj` (object or data)."""
    for curve in obj.animation_data.action.fcurves:
        for point in curve.keyframe_points:
            point.interpolation = "LINEAR"


def column(scene, name, radius, height, sides, levels, color, location):
    """A closed cylinder with `levels` rings of side quads, for a smooth bend."""
    verts = [(radius * math.cos(2 * math.pi * j / sides), radius * math.sin(2 * math.pi * j / sides),
              height * i / levels) for i in range(levels + 1) for j in range(sides)]
    faces = [(i * sides + j, i * sides + (j + 1) % sides, (i + 1) * sides + (j + 1) % sides, (i + 1) * sides + j)
             for i in range(levels) for j in range(sides)]
    faces += [tuple(reversed(range(sides))), tuple(levels * sides + j for j in range(sides))]
    mesh = bpy.data.meshes.new(name)
    mesh.from_pydata(verts, [], faces)
    mesh.materials.append(material(name, color))
    obj = bpy.data.objects.new(name, mesh)
    obj.location = location
    scene.collection.objects.link(obj)
    return obj


def main():
    out, scene = new_scene("animated.blend")
    scene.frame_start, scene.frame_end = FIRST, LAST

    add_ground(scene, 24.0)

    # The sphere slides from left to right across the front.
    sphere = add_primitive("uv_sphere", "Sphere", (0.8, 0.3, 0.2),
                           smooth=True, radius=0.45, location=(-2.0, -0.9, 0.45), segments=32, ring_count=16)
    sphere.keyframe_insert("location", frame=FIRST)
    sphere.location.x = 2.6
    sphere.keyframe_insert("location", frame=LAST)
    linear(sphere)

    # The box turns half a turn about z.
    box = add_boxes(scene, "Box", [((0.8, 0.8, 0.8), (0, 0, 0.4))], (0.2, 0.4, 0.8), (1.5, 1.0, 0))
    box.keyframe_insert("rotation_euler", frame=FIRST)
    box.rotation_euler.z = math.pi
    box.keyframe_insert("rotation_euler", frame=LAST)
    linear(box)

    # The column bends over (to 110 degrees at frame 24) and straightens again.
    bender = column(scene, "Bender", 0.12, 1.6, 16, 32, (0.85, 0.7, 0.2), (-1.9, 0.6, 0))
    bend = bender.modifiers.new("Bend", "SIMPLE_DEFORM")
    bend.deform_method = "BEND"
    bend.deform_axis = "Y"
    for frame, degrees in ((FIRST, 0.0), ((FIRST + LAST) // 2, 110.0), (LAST, 0.0)):
        bend.angle = math.radians(degrees)
        bender.keyframe_insert('modifiers["Bend"].angle', frame=frame)

    # A flag on a pole, rippling.
    add_boxes(scene, "Pole", [((0.04, 0.04, 1.9), (0, 0, 0.95))], (0.5, 0.5, 0.5), (0.1, 2.0, 0))
    bpy.ops.mesh.primitive_grid_add(x_subdivisions=48, y_subdivisions=24, size=1.0,
                                    location=(0.56, 2.46, 1.5), rotation=(math.radians(90), 0, math.radians(45)))
    flag = bpy.context.object
    flag.name = "Flag"
    flag.scale = (1.3, 0.7, 1.0)
    flag.data.materials.append(material("Flag", (0.2, 0.6, 0.3)))
    wave = flag.modifiers.new("Wave", "WAVE")
    wave.use_y = False
    wave.start_position_x = -0.5
    wave.height = 0.25
    wave.width = 0.5
    wave.narrowness = 12.0
    wave.speed = 0.04
    wave.time_offset = -40.0  # already rippling at frame 1

    add_sun(scene, sun_rotation(45, 120), strength=3.0, angle_degrees=3.0)
    add_camera(scene, (0.5, -7.0, 4.0), (0.0, 0.4, 0.5), lens=35.0)

    finish(scene, out)


main()
