"""Makes a scene of a CAD-like part (a mesh file, e.g. the 110k-triangle
cad_part made by make_cad_part.py) standing on a ground plane under a sun
5 degrees wide, at 640x360: the setting in which RTSDF is checked against
Cycles and EEVEE.

blender -b --factory-startup --python blend_samples/make_cad_on_ground.py -- MESH.ply OUT.blend
"""
import math
import sys

import bpy
from mathutils import Vector


def material(name, color):
    mat = bpy.data.materials.new(name)
    mat.use_nodes = True
    bsdf = mat.node_tree.nodes["Principled BSDF"]
    bsdf.inputs["Base Color"].default_value = (*color, 1.0)
    bsdf.inputs["Specular"].default_value = 0.0
    bsdf.inputs["Roughness"].default_value = 1.0
    mat.diffuse_color = (*color, 1.0)
    return mat


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

    sun = bpy.data.lights.new("Sun", "SUN")
    sun.energy = 3.0
    sun.angle = math.radians(5.0)
    sun_object = bpy.data.objects.new("Sun", sun)
    sun_object.rotation_euler = (math.radians(45), 0, math.radians(-35))
    scene.collection.objects.link(sun_object)

    camera = bpy.data.objects.new("Camera", bpy.data.cameras.new("Camera"))
    camera.location = (1.6, -3.2, 2.2)
    direction = Vector((0.0, 0.0, 0.2)) - camera.location
    camera.rotation_euler = direction.to_track_quat("-Z", "Y").to_euler()
    scene.collection.objects.link(camera)
    scene.camera = camera

    world = bpy.data.worlds.new("World")
    world.use_nodes = True
    world.node_tree.nodes["Background"].inputs["Color"].default_value = (0.05, 0.05, 0.05, 1.0)
    scene.world = world
    scene.render.resolution_x, scene.render.resolution_y = 640, 360
    scene.render.resolution_percentage = 100
    scene.view_settings.view_transform = "Standard"
    scene.eevee.use_soft_shadows = True
    scene.eevee.shadow_cascade_size = "4096"
    bpy.ops.wm.save_as_mainfile(filepath=out)
    print(f"wrote {out}")


main()
