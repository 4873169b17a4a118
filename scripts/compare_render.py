#!/usr/bin/python3
"""Renders one frame of a .blend with RTSDF and with Cycles (direct light only,
no denoiser), and writes RTSDF | Cycles | difference side by side with the
figures: RMSE and SSIM of the image, RMSE in the shadowed region, and the time
ratio of the two whole Blender runs.

usage: compare_render.py SCENE.blend --out DIR [--frame N] [--cycles-samples N] [--percent P]
                         [--set NAME=VALUE ...] [--reuse-cycles]

--set overrides an RTSDF setting (scene.rtsdf.NAME); --reuse-cycles keeps the
Cycles renders already in DIR (same scene, frame, samples and size).

The shadowed region is where Cycles' own visibility is below 0.98, measured as
the ratio of a Cycles render to one with shadow casting turned off.
"""
import argparse
import json
import os
import shutil
import subprocess
import sys
import tempfile
import time

import importlib.util

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402


def load_metrics():
    """The add-on's figures (addon/rtsdf/metrics.py: no bpy), shared with the compare operator and bench/run."""
    path = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "addon", "rtsdf", "metrics.py")
    spec = importlib.util.spec_from_file_location("rtsdf_metrics", path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


metrics = load_metrics()

# Runs inside Blender: sets up the engine and writes a float EXR of the frame.
BLENDER_SIDE = r"""
import bpy, sys
args = sys.argv[sys.argv.index("--") + 1:]
engine, out, frame, samples, percent, shadows = args[0], args[1], int(args[2]), int(args[3]), int(args[4]), args[5] == "1"
scene = bpy.context.scene
for assignment in args[6:]:
    name, value = assignment.split("=", 1)
    setattr(scene.rtsdf, name, type(getattr(scene.rtsdf, name))(value))
scene.frame_set(frame)
scene.render.engine = engine
scene.render.resolution_percentage = percent
scene.view_settings.view_transform = "Standard"
if engine == "CYCLES":
    scene.cycles.samples = samples
    scene.cycles.use_denoising = False
    scene.cycles.max_bounces = 0
    for light in bpy.data.lights:
        light.cycles.cast_shadow = shadows
bpy.ops.render.render()
scene.render.image_settings.file_format = "OPEN_EXR"
bpy.data.images["Render Result"].save_render(out)
"""


# Helper scripts and arrays go here, not into the output folder.
WORK = tempfile.mkdtemp(prefix="rtsdf_compare_")


def blender_render(scene, engine, out, frame, samples, percent, shadows=True, settings=()):
    script = os.path.join(WORK, "render.py")
    with open(script, "w") as f:
        f.write(BLENDER_SIDE)
    command = ["blender", "-b", scene, "--python-exit-code", "1"]
    if engine == "RTSDF":
        command += ["--addons", "rtsdf"]
    command += ["--python", script, "--", engine, out, str(frame), str(samples), str(percent),
                "1" if shadows else "0", *settings]
    start = time.perf_counter()
    # RTSDF's time includes building its fields, as on a first render: none come from the disk
    # (set RTSDF_FIELD_STORE=DIR to time a render that takes them from DIR).
    env = dict(os.environ, RTSDF_FIELD_STORE=os.environ.get("RTSDF_FIELD_STORE", "off"))
    result = subprocess.run(command, capture_output=True, text=True, env=env)
    seconds = time.perf_counter() - start
    if result.returncode != 0 or not os.path.exists(out):
        sys.exit(f"compare_render: {engine} render failed:\n{result.stdout[-2000:]}\n{result.stderr[-2000:]}")
    return seconds


def load(path):
    # Blender writes the EXR; read it back through a tiny Blender call to stay dependency-free.
    npy = os.path.join(WORK, os.path.basename(path) + ".npy")
    code = ("import bpy, numpy as np; im = bpy.data.images.load(%r); "
            "a = np.array(im.pixels[:], dtype=np.float32).reshape(im.size[1], im.size[0], 4); "
            "np.save(%r, a[::-1, :, :3])" % (path, npy))
    subprocess.run(["blender", "-b", "--factory-startup", "--python-expr", code], capture_output=True, check=True)
    return np.load(npy)


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("scene")
    parser.add_argument("--out", required=True)
    parser.add_argument("--frame", type=int, default=1)
    parser.add_argument("--cycles-samples", type=int, default=256)
    parser.add_argument("--percent", type=int, default=100)
    parser.add_argument("--set", action="append", default=[], metavar="NAME=VALUE",
                        help="override an RTSDF setting, e.g. --set fine_resolution=256")
    parser.add_argument("--reuse-cycles", action="store_true", help="keep Cycles renders already in --out")
    args = parser.parse_args()
    os.makedirs(args.out, exist_ok=True)
    name = os.path.splitext(os.path.basename(args.scene))[0]
    path = lambda suffix: os.path.join(args.out, f"{name}_{suffix}.exr")  # noqa: E731

    rtsdf_s = blender_render(args.scene, "RTSDF", path("rtsdf"), args.frame, 0, args.percent, settings=args.set)
    timing = os.path.join(args.out, f"{name}_cycles_seconds.txt")
    if args.reuse_cycles and os.path.exists(path("cycles_unshadowed")) and os.path.exists(timing):
        cycles_s = float(open(timing).read())
    else:
        cycles_s = blender_render(args.scene, "CYCLES", path("cycles"), args.frame, args.cycles_samples, args.percent)
        blender_render(args.scene, "CYCLES", path("cycles_unshadowed"), args.frame, args.cycles_samples,
                       args.percent, shadows=False)
        with open(timing, "w") as f:
            f.write(str(cycles_s))
    rtsdf, cycles, unshadowed = load(path("rtsdf")), load(path("cycles")), load(path("cycles_unshadowed"))

    difference = np.abs(rtsdf - cycles).mean(axis=-1)
    figures = {"scene": args.scene, "frame": args.frame, "settings": args.set,
               **metrics.compare(rtsdf, cycles, unshadowed),
               "rtsdf_seconds": rtsdf_s, "cycles_seconds": cycles_s,
               "cycles_samples": args.cycles_samples, "time_ratio_cycles_over_rtsdf": cycles_s / rtsdf_s}
    rmse, ssim, shadow_rmse = figures["rmse"], figures["ssim"], figures["shadow_rmse"]
    with open(os.path.join(args.out, f"{name}_figures.json"), "w") as f:
        json.dump(figures, f, indent=2)

    fig, axes = plt.subplots(1, 3, figsize=(18, 18 * rtsdf.shape[0] / rtsdf.shape[1] / 3 + 1.2))
    axes[0].imshow(metrics.to_display(rtsdf))
    axes[0].set_title(f"RTSDF ({rtsdf_s:.1f} s whole run)")
    axes[1].imshow(metrics.to_display(cycles))
    axes[1].set_title(f"Cycles, {args.cycles_samples} samples, direct light ({cycles_s:.1f} s)")
    image = axes[2].imshow(difference, cmap="inferno", vmin=0.0, vmax=0.25)
    axes[2].set_title(f"|RTSDF - Cycles|: RMSE {rmse:.4f}, SSIM {ssim:.3f}, shadow RMSE {shadow_rmse:.4f}")
    fig.colorbar(image, ax=axes[2], fraction=0.03)
    for axis in axes:
        axis.axis("off")
    fig.tight_layout()
    out_png = os.path.join(args.out, f"{name}_compare.png")
    fig.savefig(out_png, dpi=80)
    print(json.dumps(figures, indent=2))
    print(f"wrote {out_png}")
    shutil.rmtree(WORK, ignore_errors=True)


if __name__ == "__main__":
    main()
