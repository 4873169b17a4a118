"""Makes a scene of a CAD-like part (a mesh file: PLY, STL, OBJ or glTF, e.g. the
110k-triangle cad_part made by make_cad_part.py) standing on a ground plane
under a sun 5 degrees wide, at 640x360: the setting in which RTSDF is checked
against Cycles and EEVEE. The part is scaled to 1.8 units across.

blender -b --factory-startup --python blend_samples/make_cad_on_ground.py -- MESH OUT.blend
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
    extension = os.path.splitext(mesh_path)[1].lower()
    if extension in (".glb", ".gltf"):
        import numpy
        numpy.bool = bool  # (Blender 3.4's glTF importer still uses it; numpy 1.24 removed it)
    importers = {".ply": bpy.ops.import_mesh.ply, ".stl": bpy.ops.import_mesh.stl, ".obj": bpy.ops.import_scene.obj,
                 ".glb": bpy.ops.import_scene.gltf, ".gltf": bpy.ops.import_scene.gltf}
    if extension not in importers:
        sys.exit(f"make_cad_on_ground: {mesh_path}: use a .ply, .stl, .obj, .glb or .gltf file")
    importers[extension](filepath=mesh_path)
    for obj in bpy.context.selected_objects:  # (a glTF's node empties come along)
        if obj.type != "MESH":
            obj.select_set(False)
    if not bpy.context.selected_objects:
        sys.exit(f"make_cad_on_ground: {mesh_path}: no mesh was imported")
    if len(bpy.context.selected_objects) > 1:
        bpy.context.view_layer.objects.active = bpy.context.selected_objects[0]
        bpy.ops.object.join()
    part = bpy.context.selected_objects[0]
    part.name = "Part"
    # 1.8 units across, centred over the origin.
    bpy.context.view_layer.update()
    corners = [part.matrix_world @ Vector(corner) for corner in part.bound_box]
    size = max(max(c[a] for c in corners) - min(c[a] for c in corners) for a in range(3))
    part.scale *= 1.8 / size
    bpy.context.view_layer.update()
    corners = [part.matrix_world @ Vector(corner) for corner in part.bound_box]
    part.location.x -= 0.5 * (max(c.x for c in corners) + min(c.x for c in corners))
    part.location.y -= 0.5 * (max(c.y for c in corners) + min(c.y for c in corners))
    bpy.context.view_layer.update()
    part.data.materials.clear()  # (an OBJ brings its own)
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
