"""Reads what RTSDF renders from Blender's evaluated depsgraph into plain data
for the native module: meshes (numpy, through foreach_get), instances with
transforms and base colours, lights, the camera and the world colour."""

import math

import numpy as np
from mathutils import Vector

GEOMETRY_TYPES = {"MESH", "CURVE", "SURFACE", "FONT", "META"}


class SceneError(Exception):
    """A scene RTSDF cannot render; the message is for the user."""


def mesh_arrays(obj):
    """Triangles of an evaluated object (modifiers applied), or None if it has none."""
    mesh = obj.to_mesh()
    try:
        if mesh is None:
            return None
        mesh.calc_loop_triangles()
        triangles = len(mesh.loop_triangles)
        if triangles == 0:
            return None
        positions = np.empty(len(mesh.vertices) * 3, dtype=np.float32)
        mesh.vertices.foreach_get("co", positions)
        indices = np.empty(triangles * 3, dtype=np.int32)
        mesh.loop_triangles.foreach_get("vertices", indices)
        positions = positions.reshape(-1, 3)
        if not np.isfinite(positions).all():
            raise SceneError(f"Object '{obj.name}' has NaN or infinite vertex coordinates")
        arrays = {"name": obj.name, "positions": positions, "indices": indices.reshape(-1, 3).astype(np.uint32)}
        # Vertex normals only where every face is smooth-shaded (and no custom
        # split normals): otherwise faces shade flat, as sharp edges need.
        smooth = np.empty(len(mesh.polygons), dtype=bool)
        mesh.polygons.foreach_get("use_smooth", smooth)
        if smooth.all() and not mesh.has_custom_normals:
            normals = np.empty(len(mesh.vertices) * 3, dtype=np.float32)
            mesh.vertices.foreach_get("normal", normals)
            arrays["normals"] = normals.reshape(-1, 3)
        return arrays
    finally:
        obj.to_mesh_clear()


def base_color(obj):
    """Linear base colour of the object's first material (Principled BSDF or viewport colour)."""
    material = obj.active_material
    if material is None:
        return (0.8, 0.8, 0.8)
    if material.use_nodes and material.node_tree:
        for node in material.node_tree.nodes:
            if node.type == "BSDF_PRINCIPLED":
                return tuple(node.inputs["Base Color"].default_value[:3])
            if node.type == "BSDF_DIFFUSE":
                return tuple(node.inputs["Color"].default_value[:3])
    return tuple(material.diffuse_color[:3])


def shadow_toggle(light):
    """(owner, name) of the light's shadow toggle as Cycles reads it: Cast
    Shadow in Blender 3.x's Cycles settings, `use_shadow` since 4.0 (3.x's
    use_shadow is EEVEE's)."""
    cycles = getattr(light, "cycles", None)
    if cycles is not None and hasattr(cycles, "cast_shadow"):
        return cycles, "cast_shadow"
    return light, "use_shadow"


def light_casts_shadow(light):
    owner, name = shadow_toggle(light)
    return bool(getattr(owner, name, True))


def set_light_casts_shadow(light, casts):
    owner, name = shadow_toggle(light)
    setattr(owner, name, casts)


def light_data(light, matrix):
    direction = (matrix.to_3x3() @ Vector((0.0, 0.0, -1.0))).normalized()
    data = {
        "type": light.type,
        "position": tuple(matrix.translation),
        "direction": tuple(direction),
        "color": tuple(light.color),
        "energy": float(light.energy),
        "casts_shadow": light_casts_shadow(light),
    }
    if light.type == "SUN":
        data["angle"] = float(light.angle)
    elif light.type in {"POINT", "SPOT"}:
        data["radius"] = float(light.shadow_soft_size)
        if light.type == "SPOT":
            data["spot_size"] = float(light.spot_size)
            data["spot_blend"] = float(light.spot_blend)
    elif light.type == "AREA":
        size_y = light.size_y if light.shape in {"RECTANGLE", "ELLIPSE"} else light.size
        data["radius"] = 0.5 * math.sqrt(light.size * size_y)
    return data


def world_color(scene):
    """The world's uniform colour times strength (what lights a diffuse surface from everywhere)."""
    world = scene.world
    if world is None:
        return (0.0, 0.0, 0.0)
    if world.use_nodes and world.node_tree:
        for node in world.node_tree.nodes:
            if node.type == "BACKGROUND" and any(link.is_valid for link in node.outputs[0].links):
                strength = node.inputs["Strength"].default_value
                return tuple(c * strength for c in node.inputs["Color"].default_value[:3])
    return tuple(world.color)


def render_size(scene):
    render = scene.render
    scale = render.resolution_percentage / 100.0
    return max(1, int(render.resolution_x * scale)), max(1, int(render.resolution_y * scale))


def camera_data(depsgraph, camera, width, height):
    render = depsgraph.scene.render
    projection = camera.calc_matrix_camera(depsgraph, x=width, y=height,
                                           scale_x=render.pixel_aspect_x, scale_y=render.pixel_aspect_y)
    return {
        "world_to_view": np.array(camera.matrix_world.inverted(), dtype=np.float32),
        "projection": np.array(projection, dtype=np.float32),
        "orthographic": camera.data.type == "ORTHO",
    }


def geometry_key(instance):
    """(key, owner): what names an instance's evaluated geometry, so that
    instances of one mesh share it, and the object whose geometry updates
    make it stale. Collection and particle instances of an object share that
    object's mesh. Geometry Nodes instances come as copies of the object
    whose modifier made them, each holding the instanced mesh: those are
    told apart by that mesh (its evaluated data, which all instances of it
    share)."""
    obj = instance.object
    owner = obj.original.name
    made_by_parent = instance.is_instance and instance.parent is not None and \
        instance.parent.original == obj.original
    if not made_by_parent or obj.data is None:
        return owner, owner
    return f"{owner}/{obj.data.name}@{obj.data.as_pointer():x}", owner


def geometry(depsgraph, cache=None, stale=None):
    """(meshes, instances) as the native module takes them. With `cache` (a
    dict kept by the caller, mesh key -> arrays), a mesh whose owner (see
    geometry_key) is not in `stale` (a set of object names; None: all stale)
    is taken from the cache instead of being read again. Each mesh dict
    carries its "key" and "owner"."""
    meshes, instances, mesh_index = [], [], {}
    for instance in depsgraph.object_instances:
        obj = instance.object
        if obj.type not in GEOMETRY_TYPES:
            continue
        if not instance.is_instance and not instance.show_self:
            continue  # (an instancer shown through its instances only, e.g. a particle emitter)
        # Instances of one mesh share its triangles; only their transforms differ.
        key, owner = geometry_key(instance)
        if key not in mesh_index:
            if cache is not None and key in cache and stale is not None and owner not in stale:
                arrays = cache[key]
            else:
                arrays = mesh_arrays(obj)
                if arrays is not None:
                    arrays["key"], arrays["owner"] = key, owner
                if cache is not None:
                    cache[key] = arrays
            mesh_index[key] = None if arrays is None else len(meshes)
            if arrays is not None:
                meshes.append(arrays)
        if mesh_index[key] is None:
            continue
        instances.append({"mesh": mesh_index[key], "matrix": np.array(instance.matrix_world, dtype=np.float32),
                          "color": base_color(obj),
                          # Object Properties > Visibility > Ray Visibility > Shadow
                          "casts_shadow": bool(getattr(obj, "visible_shadow", True))})
    if cache is not None:
        for gone in set(cache) - set(mesh_index):  # (objects deleted, geometry evaluated anew)
            del cache[gone]
    if not instances:
        raise SceneError("Nothing to render: the scene has no objects with faces")
    return meshes, instances


def lights(depsgraph):
    return [light_data(instance.object.data, instance.matrix_world)
            for instance in depsgraph.object_instances if instance.object.type == "LIGHT"]


def extract(depsgraph):
    """The scene as the native renderer takes it; raises SceneError for what it cannot render."""
    scene = depsgraph.scene
    if scene.camera is None:
        raise SceneError("The scene has no camera")
    width, height = render_size(scene)
    meshes, instances = geometry(depsgraph)
    camera = scene.camera.evaluated_get(depsgraph)
    return {
        "meshes": meshes,
        "instances": instances,
        "lights": lights(depsgraph),
        "camera": camera_data(depsgraph, camera, width, height),
        "width": width,
        "height": height,
        "ambient": world_color(scene),
    }


def view_data(depsgraph, region_data, width, height):
    """What a viewport draw needs besides the scene: the view's camera (as the
    region draws it: perspective, orthographic, or the camera view with its
    zoom and offset), lights, world colour and size."""
    return {
        "camera": {
            "world_to_view": np.array(region_data.view_matrix, dtype=np.float32),
            "projection": np.array(region_data.window_matrix, dtype=np.float32),
            "orthographic": not region_data.is_perspective,
        },
        "lights": lights(depsgraph),
        "ambient": world_color(depsgraph.scene),
        "width": width,
        "height": height,
    }
