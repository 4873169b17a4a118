"""F12 animation of a rigid motion: each frame's render time with RTSDF and
with EEVEE, in one Blender under Xvfb (EEVEE needs a display). OBJECT turns
a full 60 degrees about z over FRAMES frames; both engines render 16 samples
at half resolution. RTSDF's log shows, per frame, the fields rebuilt and
those kept from the frames before (the session's FieldCache).

xvfb-run -a -s "-screen 0 1280x800x24" blender -b build/samples/cad_on_ground.blend \\
    --python bench/f12_animation.py -- Part 6
"""
import math
import os
import sys
import tempfile
import time

import addon_utils
import bpy

# Each run builds its fields: none are taken from the disk (RTSDF_FIELD_STORE=DIR times a warm one).
os.environ.setdefault("RTSDF_FIELD_STORE", "off")
addon_utils.enable("rtsdf", default_set=True, handle_error=None)
name, frames = sys.argv[sys.argv.index("--") + 1], int(sys.argv[sys.argv.index("--") + 2])
scene = bpy.context.scene
scene.render.resolution_percentage = 50
scene.frame_start, scene.frame_end = 1, frames
mover = bpy.data.objects[name]
mover.animation_data_clear()
for frame, angle in ((1, 0.0), (frames, 60.0)):
    mover.rotation_euler.z = math.radians(angle)
    mover.keyframe_insert("rotation_euler", frame=frame)
scene.rtsdf.samples = 16
scene.eevee.taa_render_samples = 16
scene.eevee.use_soft_shadows = True

started = {}


def pre(scene, *args):
    started["at"] = time.perf_counter()


def post(scene, *args):
    seconds.append(time.perf_counter() - started["at"])


bpy.app.handlers.render_pre.append(pre)
bpy.app.handlers.render_post.append(post)
out = tempfile.mkdtemp()
for engine in ("RTSDF", "BLENDER_EEVEE"):
    seconds = []
    scene.render.engine = engine
    scene.render.filepath = os.path.join(out, engine + "_")
    whole = time.perf_counter()
    bpy.ops.render.render(animation=True)
    whole = time.perf_counter() - whole
    print(f"F12 ANIMATION {engine}: {frames} frames in {whole:.1f} s; per frame (s): " +
          ", ".join(f"{s:.2f}" for s in seconds))
