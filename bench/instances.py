"""Instances of one mesh: sync plus the first frame of an F12 render, for N
Geometry Nodes instances of one ico sphere on a grid over a ground (the
object-space fields share one field among them).

BLENDER_USER_SCRIPTS=build/blender_user_scripts blender -b --factory-startup \
    --python bench/instances.py -- 1 1000 100000

Prints one line per count: meshes, fields, the time extract() takes (sync),
and the native render of one sample (first frame, fields built from scratch).
"""
import sys
import time

import addon_utils
import bpy

addon_utils.enable("rtsdf", default_set=True, handle_error=None)
from rtsdf import native, sync

counts = [int(c) for c in sys.argv[sys.argv.index("--") + 1:]]
scene = bpy.context.scene
bpy.ops.mesh.primitive_plane_add(size=400)
bpy.ops.mesh.primitive_ico_sphere_add(subdivisions=2, radius=0.3)
sphere = bpy.context.object
sphere.hide_render = True
bpy.ops.mesh.primitive_plane_add(size=1)
holder = bpy.context.object
modifier = holder.modifiers.new("grid", "NODES")
tree = bpy.data.node_groups.new("grid", "GeometryNodeTree")
modifier.node_group = tree
out = tree.nodes.new("NodeGroupOutput")
tree.outputs.new("NodeSocketGeometry", "Geometry")
grid = tree.nodes.new("GeometryNodeMeshGrid")
points = tree.nodes.new("GeometryNodeMeshToPoints")
inst = tree.nodes.new("GeometryNodeInstanceOnPoints")
info = tree.nodes.new("GeometryNodeObjectInfo")
info.inputs["Object"].default_value = sphere
tree.links.new(grid.outputs["Mesh"], points.inputs["Mesh"])
tree.links.new(points.outputs["Points"], inst.inputs["Points"])
tree.links.new(info.outputs["Geometry"], inst.inputs["Instance"])
tree.links.new(inst.outputs["Instances"], out.inputs[0])
bpy.ops.object.camera_add(location=(0, -150, 120), rotation=(0.9, 0, 0))
scene.camera = bpy.context.object
bpy.ops.object.light_add(type="SUN")
scene.render.resolution_x, scene.render.resolution_y = 320, 180
session, error = native.session()
for n in counts:
    side = int(round(n ** 0.5))
    grid.inputs["Vertices X"].default_value = side
    grid.inputs["Vertices Y"].default_value = max(n // side, 1)
    grid.inputs["Size X"].default_value = 2.0 * side
    grid.inputs["Size Y"].default_value = 2.0 * side
    holder.location.z = 1.0
    bpy.context.view_layer.update()
    session.forget_fields()  # (each count builds its fields, as a first render does)
    start = time.perf_counter()
    data = sync.extract(bpy.context.evaluated_depsgraph_get())
    extracted = time.perf_counter()
    out = session.render(data, dict(scene.rtsdf.as_dict(), samples=1))
    done = time.perf_counter()
    st = out["stats"]
    print(f"INSTANCES {len(data['instances'])}: meshes {len(data['meshes'])}, fields {st['fields']}, "
          f"sync {1000*(extracted-start):.0f} ms, first frame {1000*(done-extracted):.0f} ms "
          f"(native total {out['ms']['total']:.0f}), field MB {st['field_mb']:.1f}")
