#!/usr/bin/python3
"""Renders every model of a folder of third-party files with RTSDF in Blender,
each in a Blender of its own, and lists what happened to each.

usage: bench/model_sweep.py OUT [--models DIR] [--limit N] [--timeout S]

For each file Blender 3.4 imports (glTF, OBJ, FBX, Collada, PLY, STL, and
.blend files, which it opens), under DIR (default: Debian's
assimp-testmodels, /usr/share/assimp/models): a new Blender imports it, puts
it on a ground plane under a sun, frames it with a camera and renders one
frame with RTSDF (F12, 192x108, the Final preset's settings at 4 samples).
Writes OUT/sweep.csv (file, outcome, seconds, triangles, fields, instances,
field_mb: from RTSDF's render log, the fields built for the instances that
cast shadows and their memory; message) and each
image as OUT/images/N.png, and prints a tally of the outcomes:
- ok: an image (its pixels are not checked for NaN: Blender clamps them in
  a PNG, and an OpenEXR written and read back through Blender lost them
  too: this sweep cannot see them);
- reported: no image, and RTSDF's report says why (bad input, a scene
  too big): the user is told;
- no_mesh: the file holds no mesh (an animation, a camera), or Blender
  could not import it (Blender's importers, not RTSDF, fail on it);
- crashed: Blender died or hung (past --timeout): a bug.
Run with the add-on installed as the README's setup installs it (Blender
finds it in BLENDER_USER_SCRIPTS, which this sets to the build's copy when
RTSDF_BUILD_DIR is given, default build/).
"""
import argparse
import csv
import os
import re
import subprocess
import sys
import time

HERE = os.path.dirname(os.path.abspath(__file__))
FORMATS = {".gltf", ".glb", ".obj", ".fbx", ".dae", ".ply", ".stl", ".blend"}
MARK = "RTSDF_SWEEP:"
FIELDS = re.compile(r"(\d+) fields for (\d+) instances, ([\d.]+) MB")  # (the render log's line)


def blender_side(path, image_path):
    """Inside Blender: import `path`, stage it, render it, print one MARK line."""
    import bpy
    import numpy as np
    from mathutils import Vector

    def say(outcome, message="", triangles=0):
        print(f"\n{MARK} {outcome}\t{triangles}\t{message}", flush=True)

    extension = os.path.splitext(path)[1].lower()
    try:
        if extension == ".blend":
            bpy.ops.wm.open_mainfile(filepath=path, load_ui=False)
        else:
            bpy.ops.wm.read_factory_settings(use_empty=True)
            if extension in (".gltf", ".glb"):
                np.bool = bool  # (Blender 3.4's glTF importer still uses it; Debian's numpy 1.24 removed it)
                bpy.ops.import_scene.gltf(filepath=path)
            elif extension == ".obj":
                bpy.ops.wm.obj_import(filepath=path)
            elif extension == ".fbx":
                bpy.ops.import_scene.fbx(filepath=path)
            elif extension == ".dae":
                bpy.ops.wm.collada_import(filepath=path)
            elif extension == ".ply":
                bpy.ops.import_mesh.ply(filepath=path)
            elif extension == ".stl":
                bpy.ops.import_mesh.stl(filepath=path)
    except Exception as e:  # (Blender's importer refused it: not RTSDF's to judge)
        lines = [line.strip() for line in str(e).splitlines() if line.strip() and not line.strip().startswith("Location:")]
        say("no_mesh", f"import failed: {lines[-1] if lines else type(e).__name__}")
        return
    scene = bpy.context.scene
    depsgraph = bpy.context.evaluated_depsgraph_get()
    corners, triangles = [], 0
    for obj in scene.objects:
        if obj.type != "MESH" or obj.hide_render:
            continue
        evaluated = obj.evaluated_get(depsgraph)
        mesh = evaluated.to_mesh()
        if mesh is not None and len(mesh.vertices):
            mesh.calc_loop_triangles()
            triangles += len(mesh.loop_triangles)
            corners += [evaluated.matrix_world @ Vector(c) for c in evaluated.bound_box]
        evaluated.to_mesh_clear()
    if not corners:
        say("no_mesh", "no mesh with vertices")
        return
    lo = Vector([min(c[i] for c in corners) for i in range(3)])
    hi = Vector([max(c[i] for c in corners) for i in range(3)])
    centre, size = (lo + hi) / 2, max((hi - lo).length, 1e-6)
    # A ground under it, a sun, a camera looking down at it from the front.
    bpy.ops.mesh.primitive_plane_add(size=3 * size, location=(centre.x, centre.y, lo.z))
    bpy.ops.object.light_add(type="SUN", rotation=(0.6, 0.2, 0.8))
    bpy.context.object.data.angle = 0.05
    bpy.ops.object.camera_add(location=centre + Vector((0.0, -1.2, 0.8)) * size)
    camera = bpy.context.object
    camera.rotation_euler = (centre - camera.location).to_track_quat("-Z", "Y").to_euler()
    camera.data.clip_start, camera.data.clip_end = size * 1e-3, size * 10
    scene.camera = camera
    scene.render.engine = "RTSDF"
    scene.render.resolution_x, scene.render.resolution_y, scene.render.resolution_percentage = 192, 108, 100
    scene.render.image_settings.file_format = "PNG"
    scene.render.filepath = image_path
    scene.rtsdf.samples = 4
    if os.path.exists(image_path):
        os.remove(image_path)
    bpy.ops.render.render(write_still=True)
    if not os.path.exists(image_path):
        say("reported", "no image", triangles)
        return
    say("ok", "", triangles)


def driver():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("out")
    parser.add_argument("--models", default="/usr/share/assimp/models")
    parser.add_argument("--limit", type=int, default=0)
    parser.add_argument("--timeout", type=float, default=180.0)
    args = parser.parse_args()
    build = os.path.abspath(os.environ.get("RTSDF_BUILD_DIR", os.path.join(HERE, "..", "build")))
    # (every model's fields built by this build, none taken from the disk)
    env = dict(os.environ, BLENDER_USER_SCRIPTS=os.path.join(build, "blender_user_scripts"), RTSDF_FIELD_STORE="off")
    env.setdefault("XDG_RUNTIME_DIR", "/tmp")
    files = sorted(os.path.join(root, name) for root, _, names in os.walk(args.models) for name in names
                   if os.path.splitext(name)[1].lower() in FORMATS)
    if args.limit:
        files = files[:args.limit]
    os.makedirs(os.path.join(args.out, "images"), exist_ok=True)
    rows, tally = [], {}
    for number, path in enumerate(files):
        image = os.path.join(args.out, "images", f"{number:03d}.png")
        command = ["blender", "-b", "--factory-startup", "--addons", "rtsdf", "--python", os.path.abspath(__file__),
                   "--", "--blender-side", path, image]
        start = time.perf_counter()
        try:
            run = subprocess.run(command, env=env, capture_output=True, text=True, errors="replace",
                                 timeout=args.timeout)
            # (a line of Blender's own may run into the mark, without its newline)
            lines = [l[l.index(MARK):] for l in run.stdout.splitlines() if MARK in l]
            reports = [l.strip() for l in (run.stdout + run.stderr).splitlines() if "RTSDF:" in l and
                       ("rror" in l or "arning" in l) and MARK not in l]
            if lines:
                outcome, triangles, message = (lines[-1][len(MARK):].strip().split("\t") + ["", ""])[:3]
                if outcome == "reported":
                    message = reports[-1] if reports else message
                    if not reports:
                        outcome = "crashed"  # (no image and nothing said: the user is left guessing)
            else:  # (Blender died, or this script did: either leaves the user without a frame)
                outcome, triangles, message = "crashed", "", f"exit {run.returncode}: " + \
                    " | ".join((run.stderr + run.stdout).strip().splitlines()[-2:])
        except subprocess.TimeoutExpired:
            outcome, triangles, message = "crashed", "", f"hung past {args.timeout:.0f} s"
        seconds = time.perf_counter() - start
        tally[outcome] = tally.get(outcome, 0) + 1
        relative = os.path.relpath(path, args.models)
        found = FIELDS.findall(run.stdout) if outcome == "ok" else []
        fields = list(found[-1]) if found else ["", "", ""]
        rows.append([relative, outcome, f"{seconds:.1f}", triangles] + fields + [message])
        print(f"{number:3d} {outcome:9s} {seconds:6.1f} s {relative} {message}", flush=True)
    with open(os.path.join(args.out, "sweep.csv"), "w", newline="") as f:
        writer = csv.writer(f)
        writer.writerow(["file", "outcome", "seconds", "triangles", "fields", "instances", "field_mb", "message"])
        writer.writerows(rows)
    print(", ".join(f"{k} {v}" for k, v in sorted(tally.items())), f"of {len(files)} files")
    return 1 if tally.get("crashed") else 0


if __name__ == "__main__":
    if "--blender-side" in sys.argv:
        arguments = sys.argv[sys.argv.index("--blender-side") + 1:]
        blender_side(*arguments[:2])
    else:
        sys.exit(driver())
