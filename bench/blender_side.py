"""The part of bench/run that runs inside Blender (with the rtsdf add-on):

  prepare: the scene as RTSDF takes it (before and after a move of one
           object), and the Cycles references (with and without shadows) of both,
           and of the world's light alone before the move;
  eevee:   EEVEE renders (run under Xvfb) over a sweep of its shadow settings,
           and the frames its viewport shows while the mover plays prepare's move.

blender -b --addons rtsdf --python bench/blender_side.py -- MODE PERCENT CYCLES_SAMPLES STEPS quick|full \
    SCENE.blend OUT_DIR [SCENE.blend OUT_DIR ...]
(STEPS: the playback's steps, bench/run's ANIMATION_STEPS)
One Blender for every scene (each opened in turn), so that Blender's start and
EEVEE's built-in shaders are paid once. Writes pickles of plain data and numpy
arrays (linear RGB, rows top to bottom) into each OUT_DIR, and
OUT_DIR/MODE.error where that scene failed (the others still run).
"""
import json
import os
import pickle
import sys
import tempfile
import time
import traceback

import bpy
import numpy as np
from mathutils import Vector

from rtsdf import sync

ARGS = sys.argv[sys.argv.index("--") + 1:]
MODE, PERCENT, CYCLES_SAMPLES, PLAYBACK_STEPS, QUICK = ARGS[0], int(ARGS[1]), int(ARGS[2]), int(ARGS[3]), ARGS[4] == "quick"
SCENES = list(zip(ARGS[5::2], ARGS[6::2]))  # (blend file, its output directory)
OUT = None  # the output directory of the scene open now


def render_pixels():
    """Renders the current frame with the scene's engine: (linear RGB, seconds)."""
    start = time.perf_counter()
    bpy.ops.render.render()
    seconds = time.perf_counter() - start
    with tempfile.TemporaryDirectory() as directory:
        path = os.path.join(directory, "frame.exr")
        bpy.context.scene.render.image_settings.file_format = "OPEN_EXR"
        bpy.data.images["Render Result"].save_render(path)
        image = bpy.data.images.load(path)
        pixels = np.array(image.pixels[:], dtype=np.float32).reshape(image.size[1], image.size[0], 4)
        bpy.data.images.remove(image)
    return np.ascontiguousarray(pixels[::-1, :, :3]), seconds


def cycles(shadows, lights=True):
    """Cycles' direct light; with the lights' shadows or without; lights=False: the world's light alone."""
    scene = bpy.context.scene
    scene.render.engine = "CYCLES"
    scene.cycles.samples = CYCLES_SAMPLES
    scene.cycles.use_denoising = False
    scene.cycles.max_bounces = 0  # direct light only, as RTSDF computes it
    for light in bpy.data.lights:
        sync.set_light_casts_shadow(light, shadows)
    hidden = [o for o in scene.objects if o.type == "LIGHT" and not o.hide_render]
    if not lights:
        for o in hidden:
            o.hide_render = True
    try:
        return render_pixels()
    finally:
        for o in hidden:
            o.hide_render = False


def moving_object():
    """The object whose move the ghosting test follows: the one a sample script marked with the
    property rtsdf_bench_mover, else 'Sphere' if there is one, else the largest shadow-casting mesh
    that is not flat (a ground or a wall)."""
    objects = bpy.data.objects
    marked = [o for o in objects if o.get("rtsdf_bench_mover")]
    if marked:
        return marked[0]
    if "Sphere" in objects:
        return objects["Sphere"]
    candidates = [o for o in objects if o.type == "MESH" and o.name != "Ground" and o.visible_shadow
                  and min(o.dimensions) > 0.01 * max(o.dimensions)]
    return max(candidates, key=lambda o: max(o.dimensions)) if candidates else None


class Move:
    """prepare()'s move, which the playback plays in PLAYBACK_STEPS steps: the
    mover crosses its own size along x (so that its old shadow is clear of the
    new one), and where the scene's animation deforms a mesh (a skinned
    character) the animation plays on a frame a step too. A mover only
    translated would leave a deforming mesh's per-frame field unmeasured.
    The mover's own transform keys are dropped (they would undo the move);
    its pose and the rest of the scene's keys are kept."""

    def __init__(self, mover):
        scene = bpy.context.scene
        self.mover, self.frame = mover, scene.frame_current
        action = mover.animation_data.action if mover.animation_data else None
        if action is not None:
            for curve in [c for c in action.fcurves if c.data_path in ("location", "rotation_euler",
                                                                       "rotation_quaternion", "scale")]:
                action.fcurves.remove(curve)
        self.start = mover.location.copy()
        self.step = Vector((max(mover.dimensions) / PLAYBACK_STEPS, 0.0, 0.0))
        self.plays_animation = scene.frame_end > scene.frame_start and self._deforms()
        self.go(0)

    def go(self, n):
        """The scene at step n of the move (0: before it)."""
        if self.plays_animation or n == 0:
            bpy.context.scene.frame_set(self.frame + (n if self.plays_animation else 0))
        self.mover.location = self.start + self.step * n

    def _deforms(self):
        """Whether a mesh's evaluated shape changes over the move's frames."""
        def shapes():
            depsgraph = bpy.context.evaluated_depsgraph_get()
            found = []
            for o in bpy.context.scene.objects:
                if o.type == "MESH":
                    vertices = o.evaluated_get(depsgraph).data.vertices
                    found.append(np.empty(3 * len(vertices), np.float32))
                    vertices.foreach_get("co", found[-1])
            return found
        scene = bpy.context.scene
        first = shapes()
        scene.frame_set(self.frame + PLAYBACK_STEPS)
        last = shapes()
        scene.frame_set(self.frame)
        return any(a.shape != b.shape or not np.array_equal(a, b) for a, b in zip(first, last))


def prepare():
    scene = bpy.context.scene
    scene.render.resolution_percentage = PERCENT
    scene.view_settings.view_transform = "Standard"
    if scene.frame_end > scene.frame_start:  # animated: a frame in the middle
        scene.frame_set((scene.frame_start + scene.frame_end) // 2)
    mover = moving_object()
    move = Move(mover) if mover is not None else None
    depsgraph = bpy.context.evaluated_depsgraph_get()
    before = sync.extract(depsgraph)
    references = {"before": {}, "after": {}}
    references["before"]["shadowed"], seconds = cycles(True)
    references["before"]["unshadowed"], _ = cycles(False)
    references["before"]["world"], _ = cycles(True, lights=False)  # for the leak figure

    after, steps = None, None
    if move is not None:
        if move.plays_animation:
            # Each step's pose as a viewport takes it: every instance's
            # transform, and the meshes whose shape differs from before.
            steps = []
            for n in range(1, PLAYBACK_STEPS + 1):
                move.go(n)
                now = sync.extract(bpy.context.evaluated_depsgraph_get())
                steps.append({"transforms": [instance["matrix"] for instance in now["instances"]],
                              "meshes": {index: mesh for index, (old, mesh) in enumerate(zip(before["meshes"], now["meshes"]))
                                         if not np.array_equal(old["positions"], mesh["positions"])}})
        move.go(PLAYBACK_STEPS)
        after = sync.extract(bpy.context.evaluated_depsgraph_get())
        references["after"]["shadowed"], _ = cycles(True)
        references["after"]["unshadowed"], _ = cycles(False)
    with open(os.path.join(OUT, "scene.pkl"), "wb") as f:
        pickle.dump({"before": before, "after": after, "steps": steps, "mover": mover.name if mover else None,
                     "cycles_seconds": seconds, "cycles_samples": CYCLES_SAMPLES}, f)
    for state, images in references.items():
        for kind, image in images.items():
            np.save(os.path.join(OUT, f"cycles_{state}_{kind}.npy"), image)


def eevee():
    scene = bpy.context.scene
    scene.render.resolution_percentage = PERCENT
    scene.view_settings.view_transform = "Standard"
    if scene.frame_end > scene.frame_start:
        scene.frame_set((scene.frame_start + scene.frame_end) // 2)
    scene.render.engine = "BLENDER_EEVEE"
    scene.eevee.use_soft_shadows = True
    scene.eevee.use_gtao = False
    scene.eevee.use_ssr = False
    # EEVEE at its best: 32-bit shadow maps, and its lights' shadow bias
    # swept as well as the maps' size (each row says its setting; bench/run
    # takes each scene's best). Blender's default bias (1.0) detaches
    # shadows from small or thin casters: on the 15 bench scenes 0.05 was as
    # good or better on all but landscape (0.0067 against 0.0064), and gave
    # the engine 0.0265 against 0.0919, the ivy 0.0247 against 0.1142 and
    # the bolts 0.0268 against 0.1102; 0.02 was better again on some and
    # worse on others; contact shadows made 12 of 15 worse; fitting the sun's
    # cascades to the scene's depth, no better (bias 0.05: the tree 0.0284
    # against 0.0259). The first setting is the one its playback is drawn at.
    scene.eevee.use_shadow_high_bitdepth = True
    best = [("4096", 16, 0.05), ("4096", 16, 1.0), ("4096", 16, 0.02)]
    sweep = best if QUICK else [("1024", 16, 0.05), ("2048", 16, 0.05)] + best + [("4096", 64, 0.05), ("4096", 16, 0.2)]

    def set_shadow_maps(cascade, bias):
        scene.eevee.shadow_cascade_size = cascade
        scene.eevee.shadow_cube_size = cascade
        for light in bpy.data.lights:
            light.shadow_buffer_bias = bias
            light.use_contact_shadow = False
            if light.type == "SUN":
                light.shadow_cascade_count = 4

    # Playback first, at the sweep's first setting: prepare()'s move, one TAA
    # sample a frame as EEVEE's viewport draws while playing (it restarts its
    # samples on every change), then the moved pose converged. Its first frame
    # also compiles the shaders and fills the shadow maps that the sweep's
    # first timed render would otherwise pay for (the warm-up the other
    # settings render).
    playback = {}
    mover = moving_object()
    if mover is not None:
        cascade, _, bias = sweep[0]
        set_shadow_maps(cascade, bias)
        move = Move(mover)
        scene.eevee.taa_render_samples = 1
        frames = []
        # The last two steps only: each of EEVEE's playback frames depends on
        # its pose alone (no history), so they give the last frame's error and
        # the change between consecutive frames as all the steps would (over
        # all eight, its flicker where nothing moves was 0 on all 12 scenes),
        # in a quarter of the renders.
        for n in range(PLAYBACK_STEPS - 1, PLAYBACK_STEPS + 1):
            move.go(n)
            image, _ = render_pixels()
            frames.append(f"eevee_playback_{n}.npy")
            np.save(os.path.join(OUT, frames[-1]), image)
        scene.eevee.taa_render_samples = sweep[0][1]
        image, _ = render_pixels()
        np.save(os.path.join(OUT, "eevee_still_after.npy"), image)
        playback = {"playback": frames, "still_after": "eevee_still_after.npy"}
        move.go(0)
    results = []
    for index, (cascade, samples, bias) in enumerate(sweep):
        set_shadow_maps(cascade, bias)
        if index > 0 or not playback:
            # One sample warms up the shaders and shadow maps: the timed render then compiles nothing.
            scene.eevee.taa_render_samples = 1
            render_pixels()
        scene.eevee.taa_render_samples = samples
        image, seconds = render_pixels()
        name = f"eevee_{cascade}_{samples}_{bias}"
        np.save(os.path.join(OUT, name + ".npy"), image)
        results.append({"setting": f"cascade={cascade} samples={samples} bias={bias}", "file": name + ".npy",
                        "ms_per_frame": 1000.0 * seconds / samples, "seconds": seconds})
    results[0].update(playback)
    with open(os.path.join(OUT, "eevee.json"), "w") as f:
        json.dump(results, f, indent=1)


for blend, OUT in SCENES:
    os.makedirs(OUT, exist_ok=True)
    error = os.path.join(OUT, MODE + ".error")
    if os.path.exists(error):
        os.remove(error)  # (an earlier run's, in a reused output directory)
    started = time.perf_counter()
    try:
        bpy.ops.wm.open_mainfile(filepath=blend, load_ui=False)
        {"prepare": prepare, "eevee": eevee}[MODE]()
    except Exception:  # (one broken scene must not cost the others their figures)
        with open(error, "w") as f:
            f.write(traceback.format_exc())
    with open(os.path.join(OUT, MODE + ".seconds"), "w") as f:
        f.write(f"{time.perf_counter() - started:.1f}\n")
