"""Makes a terrain and a rock, both from Blender's bundled A.N.T. Landscape
add-on, under a low sun (12 degrees above the horizon, 2 degrees wide): the
terrain its default hetero-terrain noise on a 256 x 256 grid (131,072
triangles) scaled to 24 m across, one open heightfield mesh that shadows
itself with long, grazing shadows from its ridges; the rock its noise on a
sphere, about 1.6 m across, resting on a slope (the mover in bench/run).

blender -b --factory-startup --python blend_samples/make_landscape.py -- OUT.blend
"""
import os
import sys

import addon_utils
import bpy
from mathutils import Vector

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from sample_scene import add_camera, add_sun, finish, material, new_scene, sun_rotation  # noqa: E402

out, scene = new_scene("landscape.blend")
addon_utils.enable("ant_landscape", default_set=True)


def ant_object(name, scale, color, **options):
    """An A.N.T. Landscape mesh (bpy.ops.mesh.landscape_add(**options)) named `name`, scaled, in one colour."""
    bpy.ops.mesh.landscape_add(refresh=True, **options)
    obj = bpy.context.object
    obj.name = name
    obj.scale = scale
    obj.data.materials.clear()
    obj.data.materials.append(material(name, color))
    return obj


terrain = ant_object("Terrain", (12.0, 12.0, 8.0), (0.55, 0.5, 0.4), subdivision_x=256, subdivision_y=256,
                     mesh_size_x=2.0, mesh_size_y=2.0, random_seed=3, height=0.5)
rock = ant_object("Rock", (0.8, 0.8, 0.8), (0.45, 0.45, 0.48), sphere_mesh=True, subdivision_x=64,
                  subdivision_y=64, mesh_size=2.0, random_seed=11, height=0.3)
rock["rtsdf_bench_mover"] = True
# On the terrain near (2, -4): its lowest point a little into the ground, as a rock lies.
bpy.context.view_layer.update()
depsgraph = bpy.context.evaluated_depsgraph_get()
hit, location, *_ = scene.ray_cast(depsgraph, Vector((2.0, -4.0, 50.0)), Vector((0.0, 0.0, -1.0)))
rock.location = location if hit else Vector((2.0, -4.0, 0.0))
ground = rock.location.z
bpy.context.view_layer.update()
lowest = min((rock.matrix_world @ Vector(corner)).z for corner in rock.bound_box)
rock.location.z += ground - 0.15 * rock.dimensions.z - lowest

add_sun(scene, sun_rotation(12.0, 60.0), angle_degrees=2.0)
add_camera(scene, (9.0, -15.0, 7.0), (0.0, -1.0, 0.5), lens=30.0)
finish(scene, out)
