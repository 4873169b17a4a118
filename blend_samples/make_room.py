"""Makes room.blend from Blender's bundled Archimesh add-on: a closed room 5 x 4
x 2.6 whose walls (one mesh, solidified 0.12 thick: 2.4% of the room's
width) stand on a floor and under a ceiling that are one-sided sheets, with
an Archimesh window (frame and sill; the glazed sashes removed, as RTSDF has
no glass) cut into the front wall by the add-on's boolean. A low sun 2
degrees wide shines in through the window onto the floor and a table (a thin
top on thin legs). Third-party geometry of the kind that leaked light at
wall seams and lost thin shadows (../shared/field-reports.md).

blender -b --factory-startup --python blend_samples/make_room.py -- OUT.blend
"""
import os
import sys

import addon_utils
import bpy

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from sample_scene import add_boxes, add_camera, add_sun, finish, material, new_scene, sun_rotation  # noqa: E402

out, scene = new_scene("room.blend")
addon_utils.enable("archimesh", default_set=True)

# (Archimesh 3.4 prints tracebacks from some property updates - a floor
# material it cannot build - and builds the geometry all the same.)
bpy.ops.mesh.archimesh_room()
room = bpy.data.objects["Room"]
settings = room.RoomGenerator[0]
settings.baseboard = False
settings.wall_num = 3
for wall, (length, angle) in zip(settings.walls, [(5.0, 0.0), (4.0, 90.0), (5.0, 180.0)]):
    wall.w, wall.r = length, angle
settings.merge = True  # a fourth wall closes the room
settings.wall_width = 0.12
settings.room_height = 2.6
settings.floor = True
settings.ceiling = True

bpy.ops.object.select_all(action="DESELECT")
bpy.ops.mesh.archimesh_window()
bpy.data.objects["Window_Group"].location = (2.5, 0.0, 1.0)  # in the front wall (y = 0), 1 to 2 m up
for name in ("Window.L", "Window.R", "Handle", "Handle.001"):
    bpy.data.objects.remove(bpy.data.objects[name])
bpy.context.view_layer.update()
bpy.ops.object.select_all(action="DESELECT")
room.select_set(True)
bpy.context.view_layer.objects.active = room
bpy.ops.object.archimesh_cut_holes()
bpy.ops.object.select_all(action="DESELECT")

colours = {"Room": (0.85, 0.85, 0.8), "Floor": (0.75, 0.62, 0.45), "Ceiling": (0.9, 0.9, 0.9),
           "WindowFrame": (0.8, 0.8, 0.8), "Windows_Sill": (0.8, 0.8, 0.8)}
for obj in scene.objects:
    if obj.type == "MESH" and obj.name in colours:
        obj.data.materials.clear()
        obj.data.materials.append(material(obj.name, colours[obj.name]))

# A table in the sun patch: a 3 cm top on 4 cm legs.
table = [((1.0, 0.6, 0.03), (0, 0, 0.735))]
table += [((0.04, 0.04, 0.72), (sx * 0.45, sy * 0.25, 0.36)) for sx in (-1, 1) for sy in (-1, 1)]
add_boxes(scene, "Table", table, (0.45, 0.3, 0.18), (2.3, 1.6, 0.0))["rtsdf_bench_mover"] = True

add_sun(scene, sun_rotation(28.0, 15.0), strength=3.0, angle_degrees=2.0)
add_camera(scene, (4.6, 3.7, 2.0), (2.0, 1.0, 0.4), lens=18.0)
finish(scene, out)
