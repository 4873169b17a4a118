"""Makes blend_samples/sphere_plane.blend: a sphere and a box on a ground plane
under a sun 5 degrees wide, seen by a perspective camera, with a dim world.
The simplest scene for comparing RTSDF's soft shadows with Cycles.

blender -b --factory-startup --python blend_samples/make_sphere_plane.py -- OUT.blend
"""
import math
import sys

import bpy


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
    out = sys.argv[sys.argv.index("--") + 1] if "--" in sys.argv else "sphere_plane.blend"
    bpy.ops.wm.read_factory_settings(use_empty=True)
    scene = bpy.context.scene

    bpy.ops.mesh.primitive_plane_add(size=8.0, location=(0, 0, 0))
    bpy.context.object.name = "Ground"
    bpy.context.object.data.materials.append(material("Ground", (0.8, 0.8, 0.8)))
    bpy.ops.mesh.primitive_uv_sphere_add(radius=0.6, location=(-0.6, 0.2, 0.9), segments=64, ring_count=32)
    bpy.context.object.name = "Sphere"
    bpy.ops.object.shade_smooth()
    bpy.context.object.data.materials.append(material("Sphere", (0.8, 0.3, 0.2)))
    bpy.ops.mesh.primitive_cube_add(size=0.8, location=(1.0, -0.6, 0.4), rotation=(0, 0, math.radians(30)))
    bpy.context.object.name = "Box"
    bpy.context.object.data.materials.append(material("Box", (0.2, 0.4, 0.8)))

    sun = bpy.data.lights.new("Sun", "SUN")
    sun.energy = 3.0
    sun.angle = math.radians(5.0)
    sun_object = bpy.data.objects.new("Sun", sun)
    sun_object.rotation_euler = (math.radians(40), 0, math.radians(30))
    scene.collection.objects.link(sun_object)

    camera = bpy.data.objects.new("Camera", bpy.data.cameras.new("Camera"))
    camera.location = (0.0, -6.5, 4.5)
    camera.rotation_euler = (math.radians(58), 0, 0)
    scene.collection.objects.link(camera)
    scene.camera = camera

    world = bpy.data.worlds.new("World")
    world.use_nodes = True
    world.node_tree.nodes["Background"].inputs["Color"].default_value = (0.05, 0.05, 0.05, 1.0)
    scene.world = world

    scene.render.resolution_x, scene.render.resolution_y = 640, 360
    scene.render.resolution_percentage = 100
    scene.view_settings.view_transform = "Standard"
    scene.cycles.samples = 64
    scene.cycles.use_denoising = False
    scene.cycles.max_bounces = 0  # direct light only, as RTSDF shades
    bpy.ops.wm.save_as_mainfile(filepath=out)
    print(f"wrote {out}")


main()
