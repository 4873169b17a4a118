"""Instances of one mesh: sync plus the first frame of an F12 render, for N
Geometry Nodes instances of one ico sphere on a grid over a ground (the
object-space fields share one field among them). With --meshes 3, the
points take an ico sphere, a cube and a cone in turn (a collection's
children, picked by the point's index).

BLENDER_USER_SCRIPTS=build/blender_user_scripts blender -b --factory-startup \
    --python bench/instances.py -- [--meshes 3] 1 1000 100000

Prints one line per count: meshes, fields, the time extract() takes (sync),
and the native render of one sample (first frame, fields built from scratch).
"""
import sys
import time

import addon_utils
import bpy

addon_utils.enable("rtsdf", default_set=True, handle_error=None)
from rtsdf import native, sync

args = sys.argv[sys.argv.index("--") + 1:]
mesh_count = 1
if "--meshes" in args:
    at = args.index("--meshes")
    mesh_count = int(args[at + 1])
    del args[at:at + 2]
if mesh_count not in (1, 3):
    sys.exit("--meshes takes 1 or 3")
counts = [int(c) for c in args]
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
if mesh_count == 3:
    shapes = bpy.data.collections.new("shapes")
    sphere.users_collection[0].objects.unlink(sphere)
    shapes.objects.link(sphere)
    bpy.ops.mesh.primitive_cube_add(size=0.5)
    cube = bpy.context.object
    bpy.ops.mesh.primitive_cone_add(radius1=0.3, depth=0.6)
    for shape in (cube, bpy.context.object):
        shape.users_collection[0].objects.unlink(shape)
        shapes.objects.link(shape)
    children = tree.nodes.new("GeometryNodeCollectionInfo")
    children.inputs["Collection"].default_value = shapes
    children.inputs["Separate Children"].default_value = True
    children.inputs["Reset Children"].default_value = True
    inst.inputs["Pick Instance"].default_value = True
    index = tree.nodes.new("GeometryNodeInputIndex")  # (the pick wraps around the children)
    tree.links.new(index.outputs["Index"], inst.inputs["Instance Index"])
    tree.links.new(children.outputs["Geometry"], inst.inputs["Instance"])
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
