"""The cost of a still frame's shading in RTSDF's viewport: the scene's
camera view at a given size, drawn through the native viewport as the 3D
view draws it, its medians over 30 accumulation frames after 20 to warm up.

BLENDER_USER_SCRIPTS=build/blender_user_scripts blender -b SCENE.blend --addons rtsdf \\
    --python bench/shading_bench.py -- [--method M] [--size W H] [--no-world] [--no-lights] [--first-frame]

Prints the wall time of the shading stage (G-buffer and shading, submitted
and waited for), the device time of its passes (on lavapipe the G-buffer's
rasterization finishes inside the next pass's span) and the process's CPU
time per frame (on a CPU device, the work of every core). --no-world and
--no-lights leave out the world light or the lights, to see what each costs.
--first-frame times instead the first frame after a frame change (nothing
moves: the transforms are sent again, and the converged fields stay), as in
playback, with Quick First Frame off and on in turn, 15 of each.
"""
import resource
import sys

import bpy
import numpy as np
from rtsdf import native, sync

args = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
method = args[args.index("--method") + 1] if "--method" in args else "rtsdf"
width, height = (int(v) for v in args[args.index("--size") + 1:args.index("--size") + 3]) if "--size" in args else (1045, 666)

depsgraph = bpy.context.evaluated_depsgraph_get()
scene = sync.extract(depsgraph)
scene["camera"] = sync.camera_data(depsgraph, bpy.context.scene.camera.evaluated_get(depsgraph), width, height)
session, error = native.session()
if session is None:
    sys.exit(f"shading_bench: {error}")
viewport = session.viewport()
viewport.sync({"meshes": scene["meshes"], "instances": scene["instances"]})
view = {"camera": scene["camera"], "lights": [] if "--no-lights" in args else scene["lights"],
        "ambient": (0.0, 0.0, 0.0) if "--no-world" in args else scene["ambient"], "width": width, "height": height}
options = bpy.context.scene.rtsdf.as_dict()
options.update(samples=4096, sdf_updates=0, interleave=4, grid_slack=0.5, shadow_method=method)
for _ in range(20):  # the fields refine, the pipelines are made
    out = viewport.draw(view, options)
keys = ("shade", "gbuffer_gpu", "quad_gpu", "shade_gpu")


def report(label, per_frame, cpu_ms):
    print(f"shading_bench: {method} {width}x{height}{label} on {session.device}: shading "
          f"{np.median(per_frame['shade']):.1f} ms (device: G-buffer {np.median(per_frame['gbuffer_gpu']):.1f}, "
          f"shading {np.median(per_frame['shade_gpu']):.1f} of which the quad pass "
          f"{np.median(per_frame['quad_gpu']):.1f}), CPU {cpu_ms:.1f} ms a frame")


if "--first-frame" in args:
    matrices = [instance["matrix"] for instance in scene["instances"]]
    runs = {quick: ({k: [] for k in keys}, []) for quick in (False, True)}
    for _ in range(15):
        for quick, (per_frame, cpu) in runs.items():
            options["quick_first_frame"] = quick
            viewport.set_transforms(matrices)  # a frame change: the accumulation restarts
            start = resource.getrusage(resource.RUSAGE_SELF)
            out = viewport.draw(view, options)
            end = resource.getrusage(resource.RUSAGE_SELF)
            cpu.append((end.ru_utime + end.ru_stime - start.ru_utime - start.ru_stime) * 1000)
            for k in keys:
                per_frame[k].append(out["ms"][k])
    for quick, (per_frame, cpu) in runs.items():
        report(", first frame" + (", quick" if quick else ", full"), per_frame, float(np.median(cpu)))
    sys.exit(0)

last = {k: out["ms"][k] for k in keys}
per_frame = {k: [] for k in keys}
start = resource.getrusage(resource.RUSAGE_SELF)
for _ in range(30):
    out = viewport.draw(view, options)
    for k in keys:
        per_frame[k].append(out["ms"][k] - last[k])
        last[k] = out["ms"][k]
end = resource.getrusage(resource.RUSAGE_SELF)
report("", per_frame, (end.ru_utime + end.ru_stime - start.ru_utime - start.ru_stime) / 30 * 1000)
