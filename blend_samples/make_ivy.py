"""Makes ivy from Blender's bundled IvyGen add-on grown up a wall (its
stems bevelled curves, 18,192 faces as a mesh, and 1,390 single-sided leaf
quads lying within a few centimetres of the wall) on a ground under a sun
35 degrees high and 2 degrees wide: leaf cards whose shadows fall on the
surface they cling to, nearer than a voxel. The ivy (stems and leaves, one
object) is the mover in bench/run.

blender -b --factory-startup --python blend_samples/make_ivy.py -- OUT.blend
"""
import os
import sys

import addon_utils
import bpy

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from sample_scene import add_boxes, add_camera, add_ground, add_sun, finish, material, new_scene, sun_rotation  # noqa: E402

out, scene = new_scene("ivy.blend")
addon_utils.enable("add_curve_ivygen", default_set=True)
wall = add_boxes(scene, "Wall", [((4.0, 0.3, 2.6), (0.0, 0.0, 1.3))], (0.75, 0.72, 0.68))
bpy.context.view_layer.objects.active = wall
wall.select_set(True)
# IvyGen grows from the 3D cursor over the active mesh: from the foot of the wall's sunny face.
scene.cursor.location = (0.3, -0.16, 0.02)
props = bpy.context.window_manager.ivy_gen_props
props.maxIvyLength, props.ivySize, props.ivyLeafSize, props.randomSeed, props.maxTime = 2.5, 0.04, 0.07, 5, 30.0
if bpy.ops.curve.ivy_gen(updateIvy=True) != {"FINISHED"}:
    sys.exit("make_ivy: IvyGen did not finish")
# The stems are a curve: made a mesh, and joined with the leaves into one object.
wall.select_set(False)
stems = next(o for o in scene.objects if o.type == "CURVE")
bpy.context.view_layer.objects.active = stems
stems.select_set(True)
bpy.ops.object.convert(target="MESH")
stems.data.materials.clear()
stems.data.materials.append(material("Stems", (0.35, 0.25, 0.15)))
leaves = next(o for o in scene.objects if o.type == "MESH" and o not in (wall, stems))
leaves.data.materials.clear()
leaves.data.materials.append(material("Leaves", (0.3, 0.45, 0.2)))
leaves.select_set(True)
bpy.ops.object.join()
ivy = bpy.context.view_layer.objects.active
ivy.name = "Ivy"
ivy["rtsdf_bench_mover"] = True

add_ground(scene, 12.0)
add_sun(scene, sun_rotation(35.0, 30.0), angle_degrees=2.0)
add_camera(scene, (2.0, -5.0, 2.0), (0.0, 0.0, 1.1), lens=35.0)
finish(scene, out)
