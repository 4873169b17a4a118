"""Makes a scene of a CAD-like part (a mesh file, e.g. the 110k-triangle
cad_part made by make_cad_part.py) standing on a ground plane under a sun
5 degrees wide, at 640x360: the setting in which RTSDF is checked against
Cycles and EEVEE.

blender -b --factory-startup --python blend_samples/make_cad_on_ground.py -- MESH.ply OUT.blend
"""
import os
import sys

import bpy

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from sample_scene import add_sun, finish, material  # noqa: E402
from mathutils import Vector


def main():
    mesh_path, out = sys.argv[sys.argv.index("--") + 1:][:2]
    bpy.ops.wm.read_factory_settings(use_empty=True)
    scene = bpy.context.scene
    bpy.ops.import_mesh.ply(filepath=mesh_path)
    part = bpy.context.selected_objects[0]
    part.name = "Part"
    part.data.materials.append(material("Part", (0.7, 0.7, 0.75)))
    # Stand it on the ground: its lowest point at z = 0.
    lowest = min((part.matrix_world @ Vector(corner)).z for corner in part.bound_box)
    part.location.z -= lowest

    bpy.ops.mesh.primitive_plane_add(size=6.0, location=(0, 0, 0))
    bpy.context.object.name = "Ground"
    bpy.context.object.data.materials.append(material("Ground", (0.8, 0.8, 0.8)))

    add_sun(scene, (45, 0, -35))

    camera = bpy.data.objects.new("Camera", bpy.data.cameras.new("Camera"))
    camera.location = (1.6, -3.2, 2.2)
    direction = Vector((0.0, 0.0, 0.2)) - camera.location
    camera.rotation_euler = direction.to_track_quat("-Z", "Y").to_euler()
    scene.collection.objects.link(camera)
    scene.camera = camera

    finish(scene, out)


main()
