"""Render > Compare RTSDF with Cycles: renders the current frame with RTSDF
and with Cycles (direct light only, the same lights, no denoiser; full global
illumination as an option), shows RTSDF | Cycles | a difference heat map in
one image, and reports RMSE, SSIM, shadow-region RMSE and the time ratio."""

import os
import tempfile
import time

import bpy
import numpy as np
from bpy.props import BoolProperty, IntProperty

from . import metrics, native, sync

IMAGE_NAME = "RTSDF vs Cycles"


def render_cycles(scene, samples, full_light, shadows):
    """One Cycles render of the current frame, as linear RGB rows top to bottom, and its seconds."""
    saved = (scene.render.engine, scene.cycles.samples, scene.cycles.use_denoising, scene.cycles.max_bounces,
             [(light, sync.light_casts_shadow(light)) for light in bpy.data.lights])
    try:
        scene.render.engine = "CYCLES"
        scene.cycles.samples = samples
        scene.cycles.use_denoising = False
        if not full_light:
            scene.cycles.max_bounces = 0  # direct light only, as RTSDF computes it
        for light in bpy.data.lights:
            sync.set_light_casts_shadow(light, shadows)
        start = time.perf_counter()
        bpy.ops.render.render()
        seconds = time.perf_counter() - start
        with tempfile.TemporaryDirectory() as directory:
            path = os.path.join(directory, "cycles.exr")
            settings = scene.render.image_settings
            format_before = settings.file_format
            settings.file_format = "OPEN_EXR"
            try:
                bpy.data.images["Render Result"].save_render(path)
            finally:  # (the user's output format, whatever the save did)
                settings.file_format = format_before
            image = bpy.data.images.load(path)
            pixels = np.array(image.pixels[:], dtype=np.float32).reshape(image.size[1], image.size[0], 4)
            bpy.data.images.remove(image)
        return np.ascontiguousarray(pixels[::-1, :, :3]), seconds
    finally:
        engine, samples_before, denoising, bounces, casts = saved
        scene.render.engine, scene.cycles.samples, scene.cycles.use_denoising = engine, samples_before, denoising
        scene.cycles.max_bounces = bounces
        for light, cast in casts:
            sync.set_light_casts_shadow(light, cast)


def show(rgb):
    """Puts the display-ready RGB array into the image IMAGE_NAME, in an Image Editor if one is open."""
    height, width = rgb.shape[:2]
    image = bpy.data.images.get(IMAGE_NAME)
    if image is None or tuple(image.size) != (width, height):
        if image is not None:
            bpy.data.images.remove(image)
        image = bpy.data.images.new(IMAGE_NAME, width, height, alpha=False, float_buffer=True)
    image.colorspace_settings.name = "Non-Color"  # already display values
    rgba = np.concatenate([rgb, np.ones((height, width, 1), dtype=np.float32)], axis=-1)
    image.pixels.foreach_set(rgba[::-1].ravel())
    image.update()
    for window in getattr(bpy.context.window_manager, "windows", []):
        for area in window.screen.areas:
            if area.type == "IMAGE_EDITOR":
                area.spaces.active.image = image
                return image
    return image


class RTSDF_OT_compare_cycles(bpy.types.Operator):
    """Render the current frame with RTSDF and with Cycles and show them side by side with their difference"""
    bl_idname = "render.rtsdf_compare"
    bl_label = "Compare RTSDF with Cycles"
    bl_options = {"REGISTER"}

    cycles_samples: IntProperty(name="Cycles Samples", default=128, min=1, max=65536,
                                description="Samples of the Cycles reference (no denoiser)")
    full_light: BoolProperty(name="Full Global Illumination", default=False,
                             description="Cycles with all its light bounces, not only the direct light RTSDF computes")

    def execute(self, context):
        scene = context.scene
        session, error = native.session()
        if session is None:
            self.report({"ERROR"}, f"RTSDF: {error}")
            return {"CANCELLED"}
        try:
            start = time.perf_counter()
            out = session.render(sync.extract(context.evaluated_depsgraph_get()), scene.rtsdf.as_dict(), None, False)
            rtsdf_seconds = time.perf_counter() - start
        except (sync.SceneError, *native.errors()) as e:
            self.report({"ERROR"}, f"RTSDF: {e}")
            return {"CANCELLED"}
        rtsdf = out["combined"][..., :3]
        cycles, cycles_seconds = render_cycles(scene, self.cycles_samples, self.full_light, shadows=True)
        unshadowed, _ = render_cycles(scene, self.cycles_samples, self.full_light, shadows=False)
        figures = metrics.compare(rtsdf, cycles, unshadowed)
        figures.update(rtsdf_seconds=rtsdf_seconds, cycles_seconds=cycles_seconds,
                       time_ratio=cycles_seconds / max(rtsdf_seconds, 1e-9), cycles_samples=self.cycles_samples,
                       full_light=self.full_light)
        scene["rtsdf_compare"] = figures  # for scripts
        show(metrics.side_by_side(rtsdf, cycles))
        message = (f"RTSDF vs Cycles: RMSE {figures['rmse']:.4f}, SSIM {figures['ssim']:.3f}, shadow RMSE "
                   f"{figures['shadow_rmse']:.4f}; RTSDF {rtsdf_seconds:.2f} s, Cycles {cycles_seconds:.2f} s "
                   f"({figures['time_ratio']:.1f}x). Image: '{IMAGE_NAME}'")
        print(message)
        self.report({"INFO"}, message)
        return {"FINISHED"}


def menu_entry(self, context):
    self.layout.separator()
    self.layout.operator(RTSDF_OT_compare_cycles.bl_idname, icon="IMAGE_REFERENCE")


def register():
    bpy.utils.register_class(RTSDF_OT_compare_cycles)
    bpy.types.TOPBAR_MT_render.append(menu_entry)


def unregister():
    bpy.types.TOPBAR_MT_render.remove(menu_entry)
    bpy.utils.unregister_class(RTSDF_OT_compare_cycles)
