"""How well a mesh's fine field knows inside from outside: the sign of the
field RTSDF's viewport builds for mesh 0 (converged), against the
generalized winding number (Jacobson et al. 2013: inside where its magnitude
exceeds 1/2, robust to holes and overlaps) at texels near the surface.

BLENDER_USER_SCRIPTS=build/blender_user_scripts blender -b SCENE.blend --addons rtsdf \\
    --python bench/field_sign_check.py -- [--texels N] [--mesh M]

Prints, for N random texels within a voxel of the surface (|field| < 1 voxel)
and N beyond 5 voxels, how the field's sign and the winding number agree.
The winding number is summed over every triangle by brute force (numpy):
about a minute for 1,000 texels of a 100,000-triangle mesh.
"""
import sys

import bpy
import numpy as np
from rtsdf import native, sync

args = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
count = int(args[args.index("--texels") + 1]) if "--texels" in args else 1000
mesh_index = int(args[args.index("--mesh") + 1]) if "--mesh" in args else 0

depsgraph = bpy.context.evaluated_depsgraph_get()
scene = sync.extract(depsgraph)
scene["camera"] = sync.camera_data(depsgraph, bpy.context.scene.camera.evaluated_get(depsgraph), 160, 90)
session, error = native.session()
if session is None:
    sys.exit(f"field_sign_check: {error}")
viewport = session.viewport()
viewport.sync({"meshes": scene["meshes"], "instances": scene["instances"]})
options = bpy.context.scene.rtsdf.as_dict()
options.update(samples=64, sdf_updates=0, grid_slack=0.5)
view = {"camera": scene["camera"], "lights": scene["lights"], "ambient": scene["ambient"], "width": 160, "height": 90}
for _ in range(40):  # the field converges
    viewport.draw(view, options)
field = viewport.fine_sdf(mesh_index)
if field is None or field["space"] != "object":
    sys.exit("field_sign_check: no object-space field for that mesh (method rtsdf, a mesh that casts shadows)")
voxel = float(field["voxel_size"])
distance = field["distance"] / voxel  # (z, y, x), in voxels
origin = np.asarray(field["origin"], dtype=np.float64)

mesh = scene["meshes"][mesh_index]
positions = np.asarray(mesh["positions"], dtype=np.float64)
triangles = np.asarray(mesh["indices"], dtype=np.int64).reshape(-1, 3)
corners = [positions[triangles[:, k]] for k in range(3)]


def winding_numbers(points):
    """Sum of the triangles' signed solid angles over 4 pi (Van Oosterom and Strackee's formula)."""
    result = []
    for start in range(0, len(points), 16):
        p = points[start:start + 16, None, :]
        a, b, c = (corner[None] - p for corner in corners)
        la, lb, lc = (np.linalg.norm(v, axis=2) for v in (a, b, c))
        dot = lambda u, v: np.einsum("ijk,ijk->ij", u, v)
        numerator = dot(a, np.cross(b, c))
        denominator = la * lb * lc + dot(a, b) * lc + dot(b, c) * la + dot(c, a) * lb
        result.append(np.arctan2(numerator, denominator).sum(axis=1) / (2.0 * np.pi))
    return np.concatenate(result)


rng = np.random.default_rng(0)
for label, mask in (("within a voxel of the surface", np.abs(distance) < 1.0), ("beyond 5 voxels", distance > 5.0)):
    texels = np.argwhere(mask)
    texels = texels[rng.choice(len(texels), min(count, len(texels)), replace=False)]
    centres = origin + (texels[:, ::-1] + 0.5) * voxel  # texel (z, y, x) -> its centre (x, y, z)
    inside = np.abs(winding_numbers(centres)) > 0.5
    negative = distance[tuple(texels.T)] < 0.0
    print(f"field_sign_check: {len(texels)} texels {label}: negative and inside {np.sum(negative & inside)}, "
          f"negative but outside {np.sum(negative & ~inside)}, positive but inside {np.sum(~negative & inside)}, "
          f"positive and outside {np.sum(~negative & ~inside)}")
