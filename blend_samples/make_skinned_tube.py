"""Makes a skinned FBX model from assimp-testmodels
(/usr/share/assimp/models/FBX/animation_with_skeleton.fbx: a tube of 1,056
faces bound to 16 bones whose action bends it over 21 frames) lying over a
ground under a sun: a long, thin mesh that deforms every frame, as it came
from Blender's FBX importer. 4 units long, 0.1 across, at 640x360.

blender -b --factory-startup --python blend_samples/make_skinned_tube.py -- MODEL.fbx OUT.blend

The importer's armature is parented to an empty named "Rig" (its action
keys the armature's own transform, so the scene scales and places the
empty); the tube keeps its name from the file ("Cube").
"""
import os
import sys

import bpy
from mathutils import Vector

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from sample_scene import add_camera, add_ground, add_sun, finish, material, sun_rotation  # noqa: E402


def played_bounds(mesh, frames):
    """World bounds of the deformed mesh over the scene's frames (every other one)."""
    scene = bpy.context.scene
    lo, hi = Vector((1e30,) * 3), Vector((-1e30,) * 3)
    for frame in range(frames[0], frames[1] + 1, 2):
        scene.frame_set(frame)
        evaluated = mesh.evaluated_get(bpy.context.evaluated_depsgraph_get())
        for vertex in evaluated.data.vertices:
            p = evaluated.matrix_world @ vertex.co
            lo, hi = Vector(map(min, lo, p)), Vector(map(max, hi, p))
    return lo, hi


def main():
    args = sys.argv[sys.argv.index("--") + 1:]
    model, out = args[0], args[1]
    bpy.ops.wm.read_factory_settings(use_empty=True)
    scene = bpy.context.scene
    bpy.ops.import_scene.fbx(filepath=model)
    for obj in list(scene.objects):
        if obj.type in ("LIGHT", "CAMERA"):
            bpy.data.objects.remove(obj)
    armatures = [o for o in scene.objects if o.type == "ARMATURE"]
    meshes = [o for o in scene.objects if o.type == "MESH" and any(m.type == "ARMATURE" for m in o.modifiers)]
    if len(armatures) != 1 or len(meshes) != 1 or not (armatures[0].animation_data and armatures[0].animation_data.action):
        sys.exit("make_skinned_tube: expected one animated armature and one mesh skinned to it")
    armature, tube = armatures[0], meshes[0]
    start, end = (int(f) for f in armature.animation_data.action.frame_range)
    scene.frame_start, scene.frame_end = start, end
    rig = bpy.data.objects.new("Rig", None)
    scene.collection.objects.link(rig)
    armature.parent = rig  # (a mover of the tube as a whole: tests/blender/viewport_driver.py --moving Rig)
    lo, hi = played_bounds(tube, (start, end))
    rig.scale = (4.0 / max(hi - lo),) * 3
    bpy.context.view_layer.update()
    lo, hi = played_bounds(tube, (start, end))
    centre = 0.5 * (lo + hi)
    rig.location = -Vector((centre.x, centre.y, lo.z - 0.3))  # (its lowest point 0.3 above the ground)
    tube.data.materials.clear()
    tube.data.materials.append(material("Tube", (0.75, 0.75, 0.75)))
    add_ground(scene, 14.0)
    add_sun(scene, sun_rotation(50, -20), angle_degrees=3.0)
    add_camera(scene, (0.0, -3.6, 2.4), (0.0, 0.0, 0.3), lens=40)
    scene.frame_set(start)
    finish(scene, out)


main()
