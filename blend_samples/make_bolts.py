"""Makes a handful of fasteners from Blender's bundled Bolt Factory add-on
(hex, Allen cap and dome-headed bolts with cut threads, and hex nuts) lying
and standing on a steel plate on the ground, under a sun 25 degrees high and
1 degree wide: real generator output at the scale of millimetres, whose
threads (1.5-1.75 mm pitch) are a few voxels of the bolts' own fields and
under one of the plate's, separate parts touching each other and the plate,
and a low sun that draws the threads' serrated edge into the shadows. The
bolt lying in front is the mover in bench/run.

blender -b --factory-startup --python blend_samples/make_bolts.py -- OUT.blend
"""
import math
import os
import sys

import addon_utils
import bpy

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from sample_scene import add_boxes, add_camera, add_ground, add_sun, finish, material, new_scene, sun_rotation  # noqa: E402

out, scene = new_scene("bolts.blend")
addon_utils.enable("add_mesh_BoltFactory", default_set=True)

MM = 0.001  # Bolt Factory works in millimetres; the scene in metres
PLATE_TOP = 0.003
STEEL = (0.55, 0.56, 0.58)


def fastener(name, xy, rotation_degrees, color, **options):
    """One Bolt Factory part (its operator's options), scaled to metres,
    turned, and resting on the plate's top at `xy`."""
    if bpy.ops.mesh.bolt_add(**options) != {"FINISHED"}:
        sys.exit(f"make_bolts: Bolt Factory did not make {name}")
    part = bpy.context.object
    part.name = name
    part.scale = (MM, MM, MM)
    part.location = (*xy, 0.0)
    part.rotation_euler = tuple(math.radians(a) for a in rotation_degrees)
    part.data.materials.clear()
    part.data.materials.append(material(name, color))
    bpy.context.view_layer.update()
    lowest = min((part.matrix_world @ v.co).z for v in part.data.vertices)
    part.location.z += PLATE_TOP - lowest
    return part


# M12 bolts (pitch 1.75 mm), 40-50 mm long (Bolt Factory's thread runs
# along -z from the head: a bolt standing on its head is turned over).
M12 = dict(bf_Major_Dia=12.0, bf_Minor_Dia=9.85, bf_Pitch=1.75, bf_Shank_Dia=12.0, bf_Crest_Percent=10,
           bf_Root_Percent=10, bf_Div_Count=36)
fastener("HexBolt", (0.0, 0.0), (180.0, 0.0, 0.0), STEEL, bf_Model_Type="bf_Model_Bolt",
         bf_Head_Type="bf_Head_Hex", bf_Hex_Head_Height=7.5, bf_Hex_Head_Flat_Distance=18.0, bf_Shank_Length=10.0,
         bf_Thread_Length=40.0, **M12)
fastener("CapBolt", (0.045, 0.02), (180.0, 0.0, 0.0), (0.2, 0.2, 0.22),
         bf_Model_Type="bf_Model_Bolt", bf_Head_Type="bf_Head_Cap", bf_Bit_Type="bf_Bit_Allen",
         bf_Cap_Head_Height=12.0, bf_Cap_Head_Dia=18.0, bf_Allen_Bit_Flat_Distance=10.0, bf_Allen_Bit_Depth=6.0,
         bf_Shank_Length=0.0, bf_Thread_Length=30.0, **M12)
# A dome-headed bolt lying on the plate (the mover), its thread towards the camera.
fastener("DomeBolt", (-0.02, -0.045), (90.0, 0.0, 70.0), (0.6, 0.5, 0.3),
         bf_Model_Type="bf_Model_Bolt", bf_Head_Type="bf_Head_Dome", bf_Bit_Type="bf_Bit_Philips",
         bf_Dome_Head_Dia=20.0, bf_Philips_Bit_Dia=6.0, bf_Shank_Length=5.0, bf_Thread_Length=45.0,
         **dict(M12, bf_Major_Dia=10.0, bf_Minor_Dia=8.16, bf_Pitch=1.5, bf_Shank_Dia=10.0))
bpy.context.object["rtsdf_bench_mover"] = True
# Hex nuts: one flat on the plate, one standing on its side.
nut = dict(bf_Model_Type="bf_Model_Nut", bf_Nut_Type="bf_Nut_Hex", bf_Hex_Nut_Height=10.0,
           bf_Hex_Nut_Flat_Distance=18.0, **M12)
fastener("Nut", (-0.05, 0.03), (0.0, 0.0, 15.0), STEEL, **nut)
fastener("NutOnSide", (0.03, -0.03), (90.0, 0.0, -25.0), STEEL, **nut)

add_boxes(scene, "Plate", [((0.2, 0.14, PLATE_TOP), (0.0, 0.0, PLATE_TOP / 2))], (0.4, 0.42, 0.45))
add_ground(scene, 2.0, color=(0.7, 0.7, 0.68))
add_sun(scene, sun_rotation(25.0, 40.0), angle_degrees=1.0)
add_camera(scene, (0.16, -0.24, 0.16), (0.0, 0.0, 0.02), lens=50.0, clip_end=10.0)
finish(scene, out)
