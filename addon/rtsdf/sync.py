"""Reads what RTSDF renders from Blender's evaluated depsgraph into plain data
for the native module: meshes (numpy, through foreach_get), instances with
transforms and base colours, lights, the camera and the world colour."""

import contextlib
import gc
import itertools
import math

import numpy as np
from mathutils import Vector

GEOMETRY_TYPES = {"MESH", "CURVE", "SURFACE", "FONT", "META"}
# Geometry without faces (e.g. what a Geometry Nodes tree outputs), as the user is told it is.
SURFACELESS_TYPES = {"POINTCLOUD": "a point cloud", "CURVES": "hair curves", "VOLUME": "a volume"}
DEGENERATE_SCALE = 1e-4  # (the native kDegenerateScale: instances flatter than this are left out of the fields)


class SceneError(Exception):
    """A scene RTSDF cannot render; the message is for the user."""


def mesh_arrays(obj, with_uvs=False, color_attribute=None, warnings=None):
    """Triangles of an evaluated object (modifiers applied), with each
    triangle's material slot, or None if it has none. with_uvs: also the
    active UV map's coordinates per vertex (a vertex on a seam becomes one
    per UV), where the mesh has one. color_attribute: also that colour
    attribute per vertex ("colors", "": the one set for rendering), noted
    in `warnings` where the mesh has none of that name."""
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
        if len(mesh.materials) > 1:
            slots = np.empty(triangles, dtype=np.int32)
            mesh.loop_triangles.foreach_get("material_index", slots)
            arrays["materials"] = slots.astype(np.uint32)
        # Per-corner attributes split the vertices they differ at.
        corners = {}
        shading = normals_domain(mesh)
        if shading == "POINT":
            normals = np.empty(len(mesh.vertices) * 3, dtype=np.float32)
            mesh.vertices.foreach_get("normal", normals)
            arrays["normals"] = normals.reshape(-1, 3)
        elif shading == "CORNER":  # (FACE: no normals, the G-buffer shades each face flat)
            corners["normals"] = corner_normals(mesh)
        if with_uvs and mesh.uv_layers.active is not None:
            uvs = np.empty(len(mesh.loops) * 2, dtype=np.float32)
            mesh.uv_layers.active.data.foreach_get("uv", uvs)
            corners["uvs"] = uvs.reshape(-1, 2)[triangle_loops(mesh)]
        if color_attribute is not None:
            arrays["color_attribute"] = color_attribute
            colors = corner_colors(mesh, color_attribute)
            if colors is not None:
                corners["colors"] = colors
            elif warnings is not None:
                warnings.append(f"Object '{obj.name}' has no colour attribute "
                                f"'{color_attribute or '(render default)'}' for its material: its base colour stands in")
        if corners:
            if "normals" in arrays:  # (smooth everywhere: per vertex, but split with the UVs)
                corners["normals"] = arrays["normals"][arrays["indices"].reshape(-1)]
            split_by_corners(arrays, corners)
        return arrays
    finally:
        obj.to_mesh_clear()


def normals_domain(mesh):
    """How the mesh's shading normals vary: per vertex (every face smooth),
    per face (every face flat) or per face corner (smooth and flat faces
    mixed, sharp edges under Auto Smooth, custom split normals), as Blender
    4.1's Mesh.normals_domain says."""
    if hasattr(mesh, "normals_domain"):
        return mesh.normals_domain
    smooth = np.empty(len(mesh.polygons), dtype=bool)
    mesh.polygons.foreach_get("use_smooth", smooth)
    if mesh.has_custom_normals or (smooth.any() and getattr(mesh, "use_auto_smooth", False)):
        return "CORNER"
    return "POINT" if smooth.all() else "FACE" if not smooth.any() else "CORNER"


def triangle_loops(mesh):
    """The face corner (loop) of each loop triangle's corners, in triangle order."""
    loops = np.empty(len(mesh.loop_triangles) * 3, dtype=np.int32)
    mesh.loop_triangles.foreach_get("loops", loops)
    return loops


def corner_normals(mesh):
    """Shading normals per loop triangle corner (sharp edges, flat faces and custom normals as Blender shades them)."""
    corners = np.empty(len(mesh.loops) * 3, dtype=np.float32)
    if hasattr(mesh, "corner_normals"):  # Blender 4.1+
        mesh.corner_normals.foreach_get("vector", corners)
    else:
        mesh.calc_normals_split()
        mesh.loops.foreach_get("normal", corners)
    return corners.reshape(-1, 3)[triangle_loops(mesh)]


def corner_colors(mesh, name):
    """Linear RGB per loop triangle corner of the colour attribute `name`
    ("": the one set for rendering), from whichever domain it lives on; None
    if the mesh has no such attribute."""
    if name == "":
        attributes = getattr(mesh, "color_attributes", None)
        index = getattr(attributes, "render_color_index", -1) if attributes is not None else -1
        attribute = attributes[index] if attributes is not None and 0 <= index < len(attributes) else None
    else:
        attribute = mesh.attributes.get(name)
    if attribute is None or attribute.data_type not in ("FLOAT_COLOR", "BYTE_COLOR", "FLOAT_VECTOR", "FLOAT"):
        return None
    field, width = {"FLOAT_COLOR": ("color", 4), "BYTE_COLOR": ("color", 4), "FLOAT_VECTOR": ("vector", 3),
                    "FLOAT": ("value", 1)}[attribute.data_type]
    values = np.empty(len(attribute.data) * width, dtype=np.float32)
    attribute.data.foreach_get(field, values)
    values = np.repeat(values.reshape(-1, width), 3, axis=1)[:, :3] if width == 1 else values.reshape(-1, width)[:, :3]
    if attribute.domain == "POINT":
        vertices = np.empty(len(mesh.loop_triangles) * 3, dtype=np.int32)
        mesh.loop_triangles.foreach_get("vertices", vertices)
        return values[vertices]
    if attribute.domain == "CORNER":
        return values[triangle_loops(mesh)]
    if attribute.domain == "FACE":
        faces = np.empty(len(mesh.loop_triangles), dtype=np.int32)
        mesh.loop_triangles.foreach_get("polygon_index", faces)
        return np.repeat(values[faces], 3, axis=0)
    return None  # (edge attributes have no colour to show on a face)


def split_by_corners(arrays, corners):
    """Per-corner attributes (name -> values per triangle corner): a vertex
    whose corners differ in any (a sharp edge, a flat face beside a smooth
    one, a UV seam) becomes one vertex per combination, and each attribute a
    per-vertex array. (The fields weld vertices by position, so they see the
    same surface.)"""
    vertices = arrays["indices"].reshape(-1).astype(np.int64)
    keys = np.column_stack([vertices] + [np.round(values * 32767.0).astype(np.int64) for values in corners.values()])
    unique, first, inverse = np.unique(keys, axis=0, return_index=True, return_inverse=True)
    arrays["positions"] = np.ascontiguousarray(arrays["positions"][unique[:, 0]])
    for name, values in corners.items():
        arrays[name] = np.ascontiguousarray(values[first])
    arrays["indices"] = inverse.reshape(-1, 3).astype(np.uint32)


DEFAULT_COLOR = (0.8, 0.8, 0.8)  # (Blender's for a surface without a material)


def surface_shader(material):
    """The shader node a material's surface comes from: the one linked to its
    active Material Output (for Cycles or all engines); through Mix and Add
    Shader nodes, their first linked shader. None if there is none."""
    nodes = material.node_tree.nodes
    outputs = [n for n in nodes if n.type == "OUTPUT_MATERIAL" and n.target in ("ALL", "CYCLES")]
    outputs.sort(key=lambda n: not n.is_active_output)
    if not outputs or not outputs[0].inputs["Surface"].is_linked:
        return None
    node = outputs[0].inputs["Surface"].links[0].from_node
    while node.type in ("MIX_SHADER", "ADD_SHADER"):
        linked = [s for s in node.inputs if s.type == "SHADER" and s.is_linked]
        if not linked:
            return None
        node = linked[0].links[0].from_node
    return node


def material_color(material, warnings=None):
    """(linear RGB, image or None, colour attribute name or None): a
    material's base colour as RTSDF shades it, followed from its Material
    Output to its BSDF's Base Color (or Color): an Image Texture linked
    there, or a Color Attribute (or Attribute) node (its attribute's name;
    "": the one set for rendering), else the colour set there (which also
    stands in where a mesh lacks the attribute). Other nodes on the way to the colour, and everything
    else the BSDF does (roughness, metal, normal maps, transparency), are
    left out. A material without such a BSDF, or an image that cannot be
    read, gives the colour that stands in and a note in `warnings` (a list)."""
    if material is None:
        return DEFAULT_COLOR, None, None
    if not (material.use_nodes and material.node_tree):
        return tuple(material.diffuse_color[:3]), None, None
    shader = surface_shader(material)
    if shader is None:  # (no output linked: the first BSDF, as the viewport shows it)
        shader = next((n for n in material.node_tree.nodes if n.type in ("BSDF_PRINCIPLED", "BSDF_DIFFUSE")), None)
    socket = None if shader is None else shader.inputs.get("Base Color") or shader.inputs.get("Color")
    if socket is None or socket.type != "RGBA":
        if warnings is not None:
            warnings.append(f"Material '{material.name}' has no BSDF with a colour RTSDF can read: its viewport "
                            f"colour stands in")
        return tuple(material.diffuse_color[:3]), None, None
    color = tuple(socket.default_value[:3])
    if socket.is_linked:
        source = socket.links[0].from_node
        if source.type == "TEX_IMAGE" and source.image is not None:
            if source.image.size[0] > 0 and source.image.size[1] > 0:
                return color, source.image, None
            if warnings is not None:
                warnings.append(f"Image '{source.image.name}' of material '{material.name}' could not be read "
                                f"('{source.image.filepath}'): the colour set on its BSDF stands in")
        elif source.type == "VERTEX_COLOR":
            return color, None, source.layer_name
        elif source.type == "ATTRIBUTE" and source.attribute_type == "GEOMETRY" and source.attribute_name:
            return color, None, source.attribute_name
    return color, None, None


def slot_materials(obj):
    """The object's material slots' materials (None for an empty slot); one None for an object with none."""
    return [slot.material for slot in obj.material_slots] or [None]


# Images already read: (name, size, path, colour space, float) -> texels.
_image_texels = {}
MAX_IMAGE_SIZE = 2048


def image_texels(image):
    """(H, W, 4) uint8 texels of an image, rows from the bottom, the colour
    sRGB-encoded as the native G-buffer decodes it. Images larger than
    MAX_IMAGE_SIZE a side are taken at every n-th texel."""
    key = (image.name, tuple(image.size), image.filepath, image.colorspace_settings.name, image.is_float)
    if key not in _image_texels:
        width, height = image.size
        pixels = np.empty(width * height * 4, dtype=np.float32)
        image.pixels.foreach_get(pixels)
        pixels = pixels.reshape(height, width, 4)
        step = max(1, -(-max(width, height) // MAX_IMAGE_SIZE))
        pixels = pixels[::step, ::step]
        # A byte image in sRGB holds sRGB-encoded values already; any other holds linear ones.
        if image.is_float or image.colorspace_settings.name != "sRGB":
            rgb = np.clip(pixels[..., :3], 0.0, 1.0)
            pixels[..., :3] = np.where(rgb <= 0.0031308, rgb * 12.92, 1.055 * rgb ** (1 / 2.4) - 0.055)
        _image_texels[key] = np.ascontiguousarray(np.round(np.clip(pixels, 0.0, 1.0) * 255.0).astype(np.uint8))
    return _image_texels[key]


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


def world_color(scene, warnings=None):
    """The world's light as one colour (what lights a diffuse surface from
    everywhere): the Background's colour times its strength; an Environment
    Texture feeding it gives its mean radiance over the sphere. Other nodes
    (a Sky Texture's light cannot be read here) give the world's Viewport
    Display colour, with a note in `warnings` (a list) to tell the user."""
    world = scene.world
    if world is None:
        return (0.0, 0.0, 0.0)
    if world.use_nodes and world.node_tree:
        for node in world.node_tree.nodes:
            if node.type == "BACKGROUND" and any(link.is_valid for link in node.outputs[0].links):
                strength = node.inputs["Strength"].default_value
                color = node.inputs["Color"]
                if not color.is_linked:
                    return tuple(c * strength for c in color.default_value[:3])
                source = color.links[0].from_node
                if source.type == "TEX_ENVIRONMENT" and source.image is not None:
                    return tuple(c * strength for c in environment_mean(source.image))
                if warnings is not None:
                    warnings.append(f"The world's colour comes from a '{source.bl_label}' node, which RTSDF cannot "
                                    "read: it lights the scene with the world's Viewport Display colour instead")
                return tuple(c * strength for c in world.color)
    return tuple(world.color)


_environment_means = {}


def environment_mean(image):
    """Mean radiance of an equirectangular environment image over the sphere
    (rows weighted by the solid angle they cover), linear RGB; cached per
    image file (an image edited in Blender is read again)."""
    key = (image.name, image.filepath, tuple(image.size))
    if image.is_dirty or not image.filepath or key not in _environment_means:
        width, height = image.size
        if width == 0 or height == 0:
            raise SceneError(f"The world's image '{image.name}' has no pixels (missing file?)")
        pixels = np.empty(width * height * image.channels, dtype=np.float32)
        image.pixels.foreach_get(pixels)
        rgb = pixels.reshape(height, width, image.channels)[..., :3]
        if not image.is_float and image.colorspace_settings.name == "sRGB":
            rgb = np.where(rgb <= 0.04045, rgb / 12.92, ((rgb + 0.055) / 1.055) ** 2.4)
        latitude = (np.arange(height) + 0.5) / height * np.pi - 0.5 * np.pi
        weights = np.cos(latitude)
        _environment_means[key] = tuple(float(c) for c in (rgb.mean(axis=1) * weights[:, None]).sum(0) / weights.sum())
    return _environment_means[key]


def render_size(scene):
    render = scene.render
    scale = render.resolution_percentage / 100.0
    return max(1, int(render.resolution_x * scale)), max(1, int(render.resolution_y * scale))


def render_region(scene, width, height):
    """(x, y, w, h): the pixels a render covers (x, y from the bottom left):
    the Render Region (Output > Format > Render Region) when set, else the
    whole frame. Blender takes the region's pixels as it truncates them."""
    render = scene.render
    if not render.use_border:
        return 0, 0, width, height
    x0, x1 = int(render.border_min_x * width), int(render.border_max_x * width)
    y0, y1 = int(render.border_min_y * height), int(render.border_max_y * height)
    if x1 <= x0 or y1 <= y0:
        raise SceneError("The render region holds no pixels")
    return x0, y0, x1 - x0, y1 - y0


def region_projection(projection, width, height, region):
    """The projection of the whole frame narrowed to `region` (see render_region):
    the region's part of the frame fills the clip space."""
    x, y, w, h = region
    narrow = np.eye(4, dtype=np.float32)
    for axis, (start, size, full) in enumerate(((x, w, width), (y, h, height))):
        centre = (2.0 * start + size) / full - 1.0  # the region's centre in the frame's NDC
        narrow[axis, axis] = full / size
        narrow[axis, 3] = -centre * full / size
    return narrow @ projection


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


def holdout_collections(view_layer):
    """Names of the collections the view layer marks Holdout (they and their children)."""
    names, pending = set(), [(view_layer.layer_collection, False)]
    while pending:
        layer, inherited = pending.pop()
        held = inherited or layer.holdout
        if held:
            names.add(layer.collection.name)
        pending.extend((child, held) for child in layer.children)
    return names


def is_holdout(obj, held_collections):
    """Object Properties > Visibility > Holdout, or a collection marked Holdout in the view layer."""
    original = obj.original
    return bool(getattr(original, "is_holdout", False)) or \
        any(c.name in held_collections for c in original.users_collection)


def geometry(depsgraph, cache=None, stale=None, warnings=None):
    """(meshes, instances, textures) as the native module takes them. With
    `cache` (a dict kept by the caller, mesh key -> arrays), a mesh whose
    owner (see geometry_key) is not in `stale` (a set of object names; None:
    all stale) is taken from the cache instead of being read again. Each mesh
    dict carries its "key" and "owner"; each instance its material slots
    ("materials": colour, and the index of its image in `textures`). What a
    material cannot give is noted in `warnings` (a list), once per material."""
    meshes, instances, mesh_index = [], [], {}
    textures, texture_index = [], {}
    held = holdout_collections(depsgraph.view_layer)

    slots = {}  # material name (None: no material) -> its slot, read once however many instances use it

    def slot(material):
        name = None if material is None else material.name
        if name in slots:
            return slots[name]
        notes = []
        color, image, attribute = material_color(material, notes)
        if warnings is not None:
            warnings.extend(notes)
        slots[name] = {"color": color}
        if attribute is not None:
            slots[name]["attribute"] = attribute
        if image is not None:
            if image.name not in texture_index:
                texture_index[image.name] = len(textures)
                textures.append({"name": image.name, "pixels": image_texels(image)})
            slots[name]["texture"] = texture_index[image.name]
        return slots[name]

    by_vertex = {}  # material name -> its slot on a mesh with the colour attribute it reads

    def slot_by_vertex(material, slot):
        name = None if material is None else material.name
        if name not in by_vertex:
            by_vertex[name] = dict(slot, color=(1.0, 1.0, 1.0), vertex_color=True) if "attribute" in slot else slot
        return by_vertex[name]

    flags = {}  # original object -> its visibility flags, read once however many instances it has

    def object_flags(obj):
        key = obj.original.as_pointer()
        if key not in flags:
            # Object Properties > Visibility > Ray Visibility > Shadow, > Camera; Holdout
            flags[key] = {"casts_shadow": bool(getattr(obj, "visible_shadow", True)),
                          "visible_camera": bool(getattr(obj, "visible_camera", True)),
                          "holdout": is_holdout(obj, held)}
        return flags[key]

    matrices, owners = [], []  # (each instance's transform and object)
    noted = set()

    def note(message):  # (once per message, however many instances share it)
        if warnings is not None and message not in noted:
            noted.add(message)
            warnings.append(message)

    def add_instance(instance):
        obj = instance.object
        if obj.type not in GEOMETRY_TYPES:
            if obj.type in SURFACELESS_TYPES:
                note(f"Object '{obj.name}' is {SURFACELESS_TYPES[obj.type]} (no faces): RTSDF renders faces only, "
                     f"it is left out")
            return
        if not instance.is_instance and not instance.show_self:
            return  # (an instancer shown through its instances only, e.g. a particle emitter)
        # Instances of one mesh share its triangles; only their transforms differ.
        key, owner = geometry_key(instance)
        slot_owners = slot_materials(obj)
        materials = [slot(m) for m in slot_owners]
        textured = any("texture" in m for m in materials)
        # (one colour attribute per mesh: the first its materials read)
        attribute = next((m["attribute"] for m in materials if "attribute" in m), None)
        if key not in mesh_index:
            cached = cache.get(key) if cache is not None else None
            if cached is not None and stale is not None and owner not in stale and \
                    (not textured or "uvs" in cached) and cached.get("color_attribute") == attribute:
                arrays = cached
            else:
                arrays = mesh_arrays(obj, with_uvs=textured, color_attribute=attribute, warnings=warnings)
                if arrays is not None:
                    arrays["key"], arrays["owner"] = key, owner
                elif obj.type != "MESH" or len(obj.data.vertices):  # (not a tree's empty mesh beside its points)
                    note(f"Object '{obj.name}' has no faces (points, edges or curves only): it is left out")
                if cache is not None:
                    cache[key] = arrays
            mesh_index[key] = None if arrays is None else len(meshes)
            if arrays is not None:
                meshes.append(arrays)
        if mesh_index[key] is None:
            return
        if attribute is not None and "colors" in meshes[mesh_index[key]]:
            materials = [slot_by_vertex(m, s) for m, s in zip(slot_owners, materials)]
        matrices.append(instance.matrix_world.copy())  # (the instance's own is valid during this step only)
        owners.append(obj.original)
        instances.append({"mesh": mesh_index[key], "color": materials[0]["color"], "materials": materials,
                          **object_flags(obj)})

    with collection_paused():  # (a collection every few thousand new objects costs a third of the time)
        for instance in depsgraph.object_instances:
            add_instance(instance)
    matrices = as_arrays(matrices)
    for instance, matrix in zip(instances, matrices):
        instance["matrix"] = matrix
    for name in sorted({owners[i].name for i in np.flatnonzero(flattened(matrices))}):
        note(f"Object '{name}' has instances scaled flat (to zero size along an axis): they cast no shadow "
             f"and show nothing")
    if cache is not None:
        for gone in set(cache) - set(mesh_index):  # (objects deleted, geometry evaluated anew)
            del cache[gone]
    if not instances:
        raise SceneError("Nothing to render: the scene has no objects with faces")
    return meshes, instances, textures


@contextlib.contextmanager
def collection_paused():
    """Python's cyclic garbage collection held off while many objects are
    made that live on (a sync's instances), as it then keeps walking them all."""
    enabled = gc.isenabled()
    gc.disable()
    try:
        yield
    finally:
        if enabled:
            gc.enable()


def flattened(matrices):
    """(N,) bool: which of the (N, 4, 4) transforms scale to zero size along
    some axis (their smallest singular value under DEGENERATE_SCALE of their
    largest, or all zero), as the native renderer leaves them out of the fields."""
    linear = matrices[:, :3, :3].astype(np.float64)
    largest = np.linalg.norm(linear, axis=1).max(axis=1, initial=0.0)
    # (only transforms whose volume is small against their largest axis can be flat: few get an SVD)
    suspects = np.flatnonzero(np.abs(np.linalg.det(linear)) <= 1e-3 * largest ** 3)
    flat = np.zeros(len(matrices), bool)
    if len(suspects):
        singular = np.linalg.svd(linear[suspects], compute_uv=False)
        flat[suspects] = singular[:, -1] <= DEGENERATE_SCALE * singular[:, 0]
    return flat


def as_arrays(matrices):
    """(N, 4, 4) float32, rows as mathutils' Matrix rows, from a list of N
    matrices: in one pass (numpy's conversion of each Matrix alone takes 7x
    as long, 1.5 s for 100,000 instances)."""
    values = itertools.chain.from_iterable(itertools.chain.from_iterable(matrices))
    return np.fromiter(values, dtype=np.float32, count=16 * len(matrices)).reshape(-1, 4, 4)


def lights(depsgraph, warnings=None):
    """Every light instance's light_data; a light of negative or non-finite
    power is left out, with a note in `warnings`."""
    found = []
    for instance in depsgraph.object_instances:
        if instance.object.type != "LIGHT":
            continue
        light = instance.object.data
        if not (math.isfinite(light.energy) and light.energy >= 0.0):
            if warnings is not None:
                warnings.append(f"Light '{instance.object.name}' has a power of {light.energy:g} W: RTSDF takes "
                                f"no negative light, it is left out")
            continue
        found.append(light_data(light, instance.matrix_world))
    return found


def extract(depsgraph):
    """The scene as the native renderer takes it; raises SceneError for what it cannot render."""
    scene = depsgraph.scene
    if scene.camera is None:
        raise SceneError("The scene has no camera")
    if scene.camera.type == "CAMERA" and scene.camera.data.type == "PANO":
        raise SceneError("Panoramic cameras are not supported: RTSDF renders perspective and orthographic cameras")
    width, height = render_size(scene)
    region = render_region(scene, width, height)
    warnings = []
    meshes, instances, textures = geometry(depsgraph, warnings=warnings)
    camera = camera_data(depsgraph, scene.camera.evaluated_get(depsgraph), width, height)
    camera["projection"] = region_projection(camera["projection"], width, height, region)
    ambient = world_color(scene, warnings)
    return {
        "warnings": warnings,
        "meshes": meshes,
        "instances": instances,
        "textures": textures,
        "lights": lights(depsgraph, warnings),
        "camera": camera,
        "width": region[2],
        "height": region[3],
        "ambient": ambient,
    }


def view_lighting(depsgraph, warnings=None):
    """The lights and the world colour a viewport draws with. They change only
    with the scene, so the viewport reads them in view_update, not at every
    redraw."""
    return {"lights": lights(depsgraph, warnings), "ambient": world_color(depsgraph.scene, warnings)}


def view_data(region_data, width, height, lighting):
    """What a viewport draw needs besides the scene: the view's camera (as the
    region draws it: perspective, orthographic, or the camera view with its
    zoom and offset), its size, and `lighting` (view_lighting)."""
    return {
        "camera": {
            "world_to_view": np.array(region_data.view_matrix, dtype=np.float32),
            "projection": np.array(region_data.window_matrix, dtype=np.float32),
            "orthographic": not region_data.is_perspective,
        },
        **lighting,
        "width": width,
        "height": height,
    }
