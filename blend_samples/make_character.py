"""Makes a skinned character driven by BVH motion capture (e.g. assimp-testmodels'
/usr/share/assimp/models/BVH/01_01.bvh, from the CMU database) on a ground
under a sun: the armature imported from the BVH, a body grown around its
bones with the Skin modifier, bound to them with automatic weights, so that
every frame deforms the mesh. 1.8 units tall, at 640x360.

blender -b --factory-startup --python blend_samples/make_character.py -- MOTION.bvh OUT.blend [FRAMES]

The armature is named "Character" and the body "Body"; the scene plays the
motion's first FRAMES frames (default 120).
"""
import builtins
import os
import sys

import bpy
from mathutils import Vector

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from sample_scene import add_camera, add_ground, add_sun, finish, material, sun_rotation  # noqa: E402


def import_bvh(path):
    """Blender 3.4's BVH importer opens files with mode 'rU', which Python 3.11 refuses."""
    import io_anim_bvh.import_bvh as importer
    importer.open = lambda file, mode="r", *args, **kwargs: builtins.open(file, mode.replace("U", ""), *args, **kwargs)
    bpy.ops.import_anim.bvh(filepath=path, frame_start=1, use_fps_scale=False, rotate_mode="NATIVE")
    return bpy.context.object


def body_around(armature, radius):
    """A mesh along the armature's bones in their rest pose, grown into a body by the Skin modifier."""
    mesh = bpy.data.meshes.new("Body")
    points, edges = [], []
    for bone in armature.data.bones:
        if (bone.tail_local - bone.head_local).length < 1e-4:
            continue
        points += [armature.matrix_world @ bone.head_local, armature.matrix_world @ bone.tail_local]
        edges.append((len(points) - 2, len(points) - 1))
    mesh.from_pydata(points, edges, [])
    mesh.validate()
    body = bpy.data.objects.new("Body", mesh)
    bpy.context.scene.collection.objects.link(body)
    bpy.context.view_layer.objects.active = body
    body.select_set(True)
    bpy.ops.object.mode_set(mode="EDIT")
    bpy.ops.mesh.select_all(action="SELECT")
    bpy.ops.mesh.remove_doubles(threshold=1e-3)
    bpy.ops.object.mode_set(mode="OBJECT")
    skin = body.modifiers.new("Skin", "SKIN")
    skin.use_smooth_shade = True
    for vertex in body.data.skin_vertices[0].data:
        vertex.radius = (radius, radius)
    body.modifiers.new("Subdivision", "SUBSURF").levels = 2
    for modifier in list(body.modifiers):
        bpy.ops.object.modifier_apply(modifier=modifier.name)
    body.data.materials.append(material("Body", (0.75, 0.6, 0.5)))
    return body


def posed_bounds(body):
    """World bounds of the deformed body at the scene's first frame."""
    bpy.context.scene.frame_set(bpy.context.scene.frame_start)
    evaluated = body.evaluated_get(bpy.context.evaluated_depsgraph_get())
    points = [evaluated.matrix_world @ v.co for v in evaluated.data.vertices]
    return (Vector(tuple(min(p[a] for p in points) for a in range(3))),
            Vector(tuple(max(p[a] for p in points) for a in range(3))))


def main():
    args = sys.argv[sys.argv.index("--") + 1:]
    motion, out = args[0], args[1]
    frames = int(args[2]) if len(args) > 2 else 120
    bpy.ops.wm.read_factory_settings(use_empty=True)
    scene = bpy.context.scene
    armature = import_bvh(motion)
    armature.name = "Character"
    # bench/run's move carries the character by its rig, as an animator does
    # (moving the skinned body away from its armature stretched its limbs
    # across the scene: each bone's deformation turns the offset its own way).
    armature["rtsdf_bench_mover"] = True
    # 1.8 units tall in the rest pose.
    ends = [armature.matrix_world @ p for b in armature.data.bones for p in (b.head_local, b.tail_local)]
    armature.scale *= 1.8 / (max(p.z for p in ends) - min(p.z for p in ends))
    bpy.context.view_layer.update()

    body = body_around(armature, 0.07)
    bpy.ops.object.select_all(action="DESELECT")
    body.select_set(True)
    armature.select_set(True)
    bpy.context.view_layer.objects.active = armature
    try:
        bpy.ops.object.parent_set(type="ARMATURE_AUTO")
    except RuntimeError:
        bpy.ops.object.parent_set(type="ARMATURE_ENVELOPE")
    if not any(m.type == "ARMATURE" for m in body.modifiers):
        sys.exit("make_character: the body could not be bound to the armature")

    scene.frame_start, scene.frame_end = 1, frames
    # The motion's own root height: its first frame's feet on the ground.
    lo, hi = posed_bounds(body)
    armature.location.z -= lo.z
    lo, hi = posed_bounds(body)
    add_ground(scene, 12.0)
    add_sun(scene, sun_rotation(40, 30))
    centre = 0.5 * (lo + hi)
    add_camera(scene, (centre.x + 3.5, centre.y - 5.0, 2.6), (centre.x, centre.y, 0.8), lens=40)
    finish(scene, out)


main()
