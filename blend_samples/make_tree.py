"""Makes a tree from Blender's bundled Sapling Tree Gen add-on (3 levels of
branches, 1,271 single-sided rectangular leaf cards) on a ground under a sun
3 degrees wide: third-party geometry of the kind that casts pale shadows
when leaf cards are not handled (see the README's evaluation).

blender -b --factory-startup --python blend_samples/make_tree.py -- OUT.blend
"""
import os
import sys

import addon_utils
import bpy

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from sample_scene import add_camera, add_ground, add_sun, finish, material, new_scene, sun_rotation  # noqa: E402

out, scene = new_scene("tree.blend")
addon_utils.enable("add_curve_sapling", default_set=True)
bpy.ops.curve.tree_add(do_update=True, bevel=True, showLeaves=True, leaves=25, leafScale=0.25, leafShape="rect",
                       levels=3, seed=7, useArm=False)
# The generator makes curves (branches) and a leaf mesh: all become meshes.
for obj in list(scene.objects):
    obj.select_set(obj.type == "CURVE")
    if obj.type == "CURVE":
        bpy.context.view_layer.objects.active = obj
bpy.ops.object.convert(target="MESH")
for obj in scene.objects:
    if obj.type == "MESH":
        obj.data.materials.clear()
        leaves = "leaves" in obj.name.lower()
        obj.data.materials.append(material(obj.name, (0.35, 0.5, 0.25) if leaves else (0.45, 0.35, 0.25)))
add_ground(scene, 40.0)
add_sun(scene, sun_rotation(40.0, 30.0), angle_degrees=3.0)
add_camera(scene, (14.0, -16.0, 9.0), (0.0, 2.0, 3.0), lens=35.0)
finish(scene, out)
