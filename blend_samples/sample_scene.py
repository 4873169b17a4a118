"""Pieces every sample scene script shares: diffuse materials, a sun, the
dim world, and the render settings the comparisons use (640x360, Standard
view transform, Cycles with direct light only and no denoiser, as RTSDF
shades). Imported by the make_*.py scripts, which Blender runs."""
import math
import sys

import bmesh
import bpy
from mathutils import Euler, Matrix, Vector


def new_scene(default_out):
    """The output path (the argument after '--' on Blender's command line, else
    `default_out`) and a new, empty scene to build."""
    out = sys.argv[sys.argv.index("--") + 1] if "--" in sys.argv else default_out
    bpy.ops.wm.read_factory_settings(use_empty=True)
    return out, bpy.context.scene


def material(name, color):
    """A Lambertian material (Diffuse BSDF, roughness 0), as RTSDF shades, and
    the same viewport colour. (Principled's diffuse at roughness 1 reflects
    back towards grazing views: a far ground came out brighter in Cycles.)"""
    mat = bpy.data.materials.new(name)
    mat.use_nodes = True
    nodes = mat.node_tree.nodes
    nodes.remove(nodes["Principled BSDF"])
    bsdf = nodes.new("ShaderNodeBsdfDiffuse")
    bsdf.inputs["Color"].default_value = (*color, 1.0)
    bsdf.inputs["Roughness"].default_value = 0.0
    mat.node_tree.links.new(bsdf.outputs["BSDF"], nodes["Material Output"].inputs["Surface"])
    mat.diffuse_color = (*color, 1.0)
    return mat


def add_primitive(kind, name, color, smooth=False, **options):
    """A mesh primitive (bpy.ops.mesh.primitive_<kind>_add(**options)) named
    `name`, with a material of the same name and colour."""
    getattr(bpy.ops.mesh, f"primitive_{kind}_add")(**options)
    obj = bpy.context.object
    obj.name = name
    if smooth:
        bpy.ops.object.shade_smooth()
    obj.data.materials.append(material(name, color))
    return obj


def add_sun(scene, rotation_degrees, strength=3.0, angle_degrees=5.0):
    sun = bpy.data.lights.new("Sun", "SUN")
    sun.energy = strength
    sun.angle = math.radians(angle_degrees)
    sun_object = bpy.data.objects.new("Sun", sun)
    sun_object.rotation_euler = tuple(math.radians(a) for a in rotation_degrees)
    scene.collection.objects.link(sun_object)
    return sun_object


def sun_rotation(elevation_degrees, azimuth_degrees):
    """add_sun's rotation for a sun `elevation_degrees` above the horizon whose
    light travels towards +Y turned `azimuth_degrees` about +Z (so shadows fall
    that way: 0 is +Y, 90 is -X, -90 is +X, 180 is -Y)."""
    return (90.0 - elevation_degrees, 0.0, azimuth_degrees)


def add_camera(scene, location, target, lens=50.0, clip_end=100.0):
    """The scene camera at `location`, looking at `target`."""
    camera = bpy.data.objects.new("Camera", bpy.data.cameras.new("Camera"))
    camera.location = location
    camera.rotation_euler = (Vector(target) - Vector(location)).to_track_quat("-Z", "Y").to_euler()
    camera.data.lens = lens
    camera.data.clip_end = clip_end
    scene.collection.objects.link(camera)
    scene.camera = camera
    return camera


def add_boxes(scene, name, boxes, color, location=(0.0, 0.0, 0.0)):
    """One object made of closed boxes, each (size, centre[, rotation]) in the
    object's own frame, the rotation in degrees: about z, or (x, y, z) Euler
    angles; with a material of `color`."""
    bm = bmesh.new()
    for box in boxes:
        size, centre = box[0], box[1]
        turn = box[2] if len(box) > 2 else 0.0
        turn = (0.0, 0.0, turn) if isinstance(turn, (int, float)) else turn
        rotation = Euler(tuple(math.radians(a) for a in turn)).to_matrix().to_4x4()
        matrix = Matrix.Translation(centre) @ rotation @ Matrix.Diagonal((*size, 1.0))
        bmesh.ops.create_cube(bm, size=1.0, matrix=matrix)
    mesh = bpy.data.meshes.new(name)
    bm.to_mesh(mesh)
    bm.free()
    mesh.materials.append(material(name, color))
    obj = bpy.data.objects.new(name, mesh)
    obj.location = location
    scene.collection.objects.link(obj)
    return obj


def add_chair(scene, name, location, turn_degrees, color, leg=0.035):
    """A chair of boxes: legs `leg` thick, a seat 0.44 wide at 0.45-0.49, a back
    on its +y side (so it faces -y before `turn_degrees` about z)."""
    seat = 0.44
    half = seat / 2 - leg / 2
    boxes = [((leg, leg, 0.45), (sx * half, sy * half, 0.225)) for sx in (-1, 1) for sy in (-1, 1)]
    boxes.append(((seat, seat, 0.04), (0, 0, 0.47)))
    # The back: two posts rising from the back legs and two slats.
    boxes += [((leg, leg, 0.45), (sx * half, half, 0.715)) for sx in (-1, 1)]
    boxes += [((seat, 0.025, 0.12), (0, half, 0.86)), ((seat, 0.025, 0.05), (0, half, 0.66))]
    obj = add_boxes(scene, name, boxes, color, location)
    obj.rotation_euler.z = math.radians(turn_degrees)
    return obj


def add_ground(scene, size, color=(0.8, 0.8, 0.8), centre=(0.0, 0.0)):
    """The ground: one quad (two triangles) `size` across (a number, or (x, y)),
    named "Ground" (the evaluation code looks for that name)."""
    sx, sy = (size, size) if isinstance(size, (int, float)) else size
    cx, cy = centre
    mesh = bpy.data.meshes.new("Ground")
    mesh.from_pydata([(cx - sx / 2, cy - sy / 2, 0), (cx + sx / 2, cy - sy / 2, 0),
                      (cx + sx / 2, cy + sy / 2, 0), (cx - sx / 2, cy + sy / 2, 0)], [], [(0, 1, 2, 3)])
    mesh.materials.append(material("Ground", color))
    ground = bpy.data.objects.new("Ground", mesh)
    scene.collection.objects.link(ground)
    return ground


def finish(scene, out):
    """Dim world, comparison render settings, then save to `out`."""
    world = bpy.data.worlds.new("World")
    world.use_nodes = True
    world.node_tree.nodes["Background"].inputs["Color"].default_value = (0.05, 0.05, 0.05, 1.0)
    scene.world = world
    scene.render.resolution_x, scene.render.resolution_y = 640, 360
    scene.render.resolution_percentage = 100
    scene.view_settings.view_transform = "Standard"
    scene.cycles.samples = 64
    scene.cycles.use_denoising = False
    scene.cycles.max_bounces = 0
    scene.eevee.use_soft_shadows = True
    scene.eevee.shadow_cascade_size = "4096"
    bpy.ops.wm.save_as_mainfile(filepath=out)
    print(f"wrote {out}")
