"""The RTSDF render engine: F12 and animation renders with Combined, Depth and
Shadow passes, and the viewport's Rendered shading (synced incrementally,
accumulating progressively)."""

import time

import bpy
import gpu
import numpy as np
from gpu_extras.presets import draw_texture_2d

from . import native, sync

# An F12 render shows its image so far this often (seconds).
PREVIEW_SECONDS = 1.0
# The latest viewport frame's state (frames, converged, ms, size), for
# scripts and tests that wait for the viewport to settle.
last_view_draw = {}


class RTSDFRenderEngine(bpy.types.RenderEngine):
    bl_idname = "RTSDF"
    bl_label = "RTSDF"
    bl_use_preview = False
    bl_use_postprocess = True
    # Materials are Blender's own node trees (the Shader Editor edits them),
    # and Material Preview shading is EEVEE's.
    bl_use_shading_nodes_custom = False
    bl_use_eevee_viewport = True

    def __init__(self):
        self.viewport = None      # native Viewport of this engine instance (viewport instances only)
        self.mesh_cache = {}      # mesh key -> arrays last sent
        self.view_synced = False  # the viewport holds a scene
        self.lighting = None      # lights and world colour, read at the latest view_update
        self.texture = None
        self.texture_frame = -1
        self.view_error = None
        self.last_ms = None
        self.last_draw = None
        self.view_warnings = set()  # printed once each

    def update_render_passes(self, scene=None, renderlayer=None):
        self.register_pass(scene, renderlayer, "Combined", 4, "RGBA", "COLOR")
        if renderlayer.use_pass_z:
            self.register_pass(scene, renderlayer, "Depth", 1, "Z", "VALUE")
        self.register_pass(scene, renderlayer, "Shadow", 1, "X", "VALUE")

    def render(self, depsgraph):
        scene = depsgraph.scene
        session, error = native.session()
        if session is None:
            self.report({"ERROR"}, f"RTSDF: {error}")
            return
        store_warning = native.use_field_store(session, addon_preferences())
        if store_warning:
            self.report({"WARNING"}, f"RTSDF: {store_warning}")
        self.add_pass("Shadow", 1, "X")
        shown = {"result": None, "at": time.perf_counter()}
        try:
            self.update_stats("RTSDF", "Reading the scene")
            data = sync.extract(depsgraph)
            for warning in data["warnings"]:
                self.report({"WARNING"}, f"RTSDF: {warning}")
            width, height = data["width"], data["height"]  # (the Render Region's, when set)
            self.update_stats("RTSDF", f"Rendering on {session.device}")

            def progress(done, total, preview):
                self.update_progress(done / total)
                self.update_stats("RTSDF", f"Sample {done}/{total} on {session.device}")
                # The image so far, every PREVIEW_SECONDS, as Cycles shows its samples.
                if done < total and time.perf_counter() - shown["at"] >= PREVIEW_SECONDS:
                    if shown["result"] is None:
                        shown["result"] = self.begin_result(0, 0, width, height)
                    self.write_combined(shown["result"], preview(), scene)
                    self.update_result(shown["result"])
                    shown["at"] = time.perf_counter()
                return not self.test_break()

            out = session.render(data, self.final_render_settings(scene), progress, scene.render.use_persistent_data)
        except (sync.SceneError, *native.errors()) as e:
            self.report({"ERROR"}, f"RTSDF: {e}")
            if shown["result"] is not None:
                self.end_result(shown["result"], cancel=True)
            return
        if out["samples_done"] == 0:
            if shown["result"] is not None:
                self.end_result(shown["result"], cancel=True)
            return

        result = shown["result"] or self.begin_result(0, 0, width, height)
        layer = result.layers[0]
        self.write_combined(result, out["combined"], scene)
        # Blender stores rows bottom to top.
        if "Depth" in layer.passes:
            layer.passes["Depth"].rect = np.flipud(out["depth"]).reshape(-1, 1)
        if "Shadow" in layer.passes:
            layer.passes["Shadow"].rect = np.flipud(out["shadow"]).reshape(-1, 1)
        self.end_result(result)
        ms = out["ms"]
        self.update_stats("RTSDF", f"SDF {ms['sdf']:.0f} ms | fine {ms['fine']:.0f} ms | "
                                   f"shading {ms['shade']:.0f} ms | total {ms['total']:.0f} ms | "
                                   f"{field_summary(out['stats'])}")
        reuse = f", {out['effective_samples']:.1f} samples with earlier frames'" if out["scene_reused"] and \
            out["effective_samples"] > out["samples_done"] else ""
        # (adaptive sampling: the pixels' samples shaded, of every pixel in every frame asked for)
        sampled = out["stats"]["sampled_share"]
        adaptive = f": {sampled:.0%} of {out['samples_done']} frames' pixels" if sampled < 0.995 else ""
        print(f"RTSDF: frame {scene.frame_current} {width}x{height} in {ms['total']:.0f} ms{reuse} "
              f"(SDF {ms['sdf']:.0f}, fine {ms['fine']:.0f}, shading {ms['shade']:.0f}{adaptive}) on {session.device}; "
              f"{field_summary(out['stats'])}")
        for line in field_lines(out["stats"], [mesh.get("key", "?") for mesh in data["meshes"]]):
            print(f"RTSDF:   {line}")
        warn_about_fields(self, out["stats"])

    @staticmethod
    def write_combined(result, combined, scene):
        """The Combined pass of `result` from an image with rows top to bottom (Blender's run bottom to top)."""
        combined = np.flipud(combined).copy()
        if not scene.render.film_transparent:
            combined[..., 3] = 1.0
        result.layers[0].passes["Combined"].rect = combined.reshape(-1, 4)

    def final_render_settings(self, scene):
        """The scene's settings; in an animation render with Persistent Data
        and Reuse Between Frames, Animation Samples per frame, with the
        earlier frames' samples reprojected for the rest of Samples."""
        settings = scene.rtsdf.as_dict()
        if settings["animation_reuse"] and self.is_animation and scene.render.use_persistent_data:
            fewer = min(settings["animation_samples"], settings["samples"])
            settings.update(temporal_reuse=True, samples=fewer,
                            history_samples=max(settings["samples"] - fewer, 1))
        return settings

    # --- Viewport -----------------------------------------------------------

    def view_update(self, context, depsgraph):
        """Blender calls this after any change: only what changed goes to the
        native side (new transforms, the new geometry of deformed meshes in
        place; anything else, e.g. objects added or materials changed, a new
        upload of the meshes already read)."""
        try:
            self.sync_view(depsgraph)
            self.view_error = None
        except (sync.SceneError, *native.errors()) as e:
            self.view_error = str(e)
            print(f"RTSDF viewport: {e}")

    def sync_view(self, depsgraph):
        session, error = native.session()
        if session is None:
            raise native.Unavailable(error)
        if self.viewport is None:
            store_warning = native.use_field_store(session, addon_preferences())
            if store_warning:
                print(f"RTSDF viewport: {store_warning}")
            self.viewport = session.viewport()
        first = not self.view_synced
        stale = None if first else {update.id.original.name for update in depsgraph.updates
                                    if isinstance(update.id, bpy.types.Object) and update.is_updated_geometry}
        notes = []
        meshes, instances, textures = sync.geometry(depsgraph, self.mesh_cache, stale, notes)
        self.lighting = sync.view_lighting(depsgraph, notes)
        for note in set(notes) - self.view_warnings:
            print(f"RTSDF viewport: {note}")
        self.view_warnings.update(notes)
        # The native side tells what changed (new transforms, a deformed
        # mesh in place, anything else afresh), as for final renders.
        self.viewport.update({"meshes": meshes, "instances": instances, "textures": textures})
        self.view_synced = True

    def view_draw(self, context, depsgraph):
        """One accumulation frame per call, at most: Blender's UI never waits
        for more. While the image is not converged, another redraw is asked for;
        after that the engine does nothing until something changes."""
        scene = depsgraph.scene
        if self.view_error is not None or self.viewport is None:
            self.update_stats("", f"RTSDF: {self.view_error or 'no scene'}")
            return
        region = context.region
        settings = scene.rtsdf
        width = max(1, round(region.width * settings.viewport_scale))
        height = max(1, round(region.height * settings.viewport_scale))
        options = settings.as_dict()
        # (the rest of the viewport's policy, the fields' history and room, is the native Viewport's)
        options.update(samples=settings.viewport_samples, interleave=settings.viewport_interleave,
                       quick_first_frame=settings.viewport_quick_first_frame,
                       temporal_reuse=settings.viewport_temporal_reuse)
        try:
            out = self.viewport.draw(sync.view_data(context.region_data, width, height, self.lighting), options)
        except native.errors() as e:
            self.view_error = str(e)
            self.update_stats("", f"RTSDF: {e}")
            print(f"RTSDF viewport: {e}")
            return

        if self.texture is None or out["advanced"] or self.texture.width != width or self.texture.height != height:
            # Blender's textures start at the bottom row.
            pixels = np.flipud(out["combined"]).astype(np.float32)
            if not scene.render.film_transparent:
                pixels[..., 3] = 1.0
            buffer = gpu.types.Buffer("FLOAT", width * height * 4, pixels.ravel())
            self.texture = gpu.types.GPUTexture((width, height), format="RGBA16F", data=buffer)

        gpu.state.blend_set("ALPHA_PREMULT")
        self.bind_display_space_shader(scene)
        draw_texture_2d(self.texture, (0, 0), region.width, region.height)
        self.unbind_display_space_shader()
        gpu.state.blend_set("NONE")

        self.report_view_stats(out, settings.viewport_samples)
        last_view_draw.update(frames=out["frames"], converged=out["converged"], ms=dict(self.last_draw or out["ms"]),
                              width=width, height=height, time=time.perf_counter(),
                              validation_messages=out["validation_messages"], draw_ms=out["draw_ms"],
                              effective_samples=out["effective_samples"],
                              stats=dict(out["stats"]))
        if not out["converged"]:
            self.tag_redraw()

    def report_view_stats(self, out, samples):
        """Per-stage milliseconds in the viewport's text info: the SDF rebuild
        after the latest change, fine update and shading of the latest frame."""
        ms = out["ms"]
        if out["advanced"]:
            if out["frames"] == 1 or self.last_ms is None:
                frame_ms = dict(ms)
            else:
                frame_ms = {k: ms[k] - self.last_ms.get(k, 0.0) for k in ms}
            frame_ms["sdf"] = ms["sdf"]  # (built once per change, in the first frame)
            self.last_draw = frame_ms
            self.last_ms = dict(ms)
        frame_ms = self.last_draw or ms
        state = "converged" if out["converged"] else f"frame {out['frames']}/{samples}"
        # With temporal reuse, the samples the pixels stand for on average, history included.
        state += f" ({out['effective_samples']:.1f} spp)"
        # A playback step draws only where its change can reach on screen.
        if out["frames"] == 1 and out["stats"].get("drawn_share", 1.0) < 0.995:
            state += f", drew {out['stats']['drawn_share']:.0%} of the image"
        # (where a moved shadow or a disocclusion left little history, the exact rays were more)
        if out["frames"] == 1 and out["stats"].get("short_history_share", 0.0) > 0.0:
            state += f", {out['stats']['short_history_share']:.0%} short of history"
        self.update_stats("", f"RTSDF {state} | SDF {frame_ms['sdf']:.0f} ms | fine {frame_ms['fine']:.0f} ms | "
                              f"shading {frame_ms['shade']:.0f} ms | {field_summary(out['stats'], per_frame=True)}")


def addon_preferences():
    """The add-on's preferences (None where the add-on is not enabled by name)."""
    addon = bpy.context.preferences.addons.get(__package__)
    return addon.preferences if addon else None


def field_summary(stats, per_frame=False):
    """The distance fields in a few words: how many (shared by how many
    instances), their memory (and the share of bricks stored near surfaces),
    and the work done (meshes rebuilt, texels traced)."""
    traced = stats["last_frame_traced_texels"] if per_frame else stats["traced_texels"]
    bricks = stats["brick_count"]
    occupancy = f" ({stats['stored_bricks'] / bricks:.0%} of bricks)" if bricks else ""
    loaded = f" ({stats['fields_loaded']} from disk)" if stats.get("fields_loaded") else ""
    return (f"{stats['fields']} fields for {stats['field_instances']} instances, {stats['field_mb']:.1f} MB{occupancy} | "
            f"{stats['fields_regenerated']} rebuilt, {stats['fields_reused']} kept from before{loaded}, {traced:,} texels traced")


def field_lines(stats, mesh_names):
    """One line per mesh's field for the render log: its memory, the bricks
    it stores near its surfaces, and its voxel (with the factor its thin
    parts put on its resolution, where they did)."""
    return [f"{mesh_names[f['mesh']] if f['mesh'] < len(mesh_names) else f['mesh']}: {f['mb']:.2f} MB, "
            f"{f['stored_bricks']} of {f['brick_count']} bricks, voxel {f['voxel_size']:.4g}"
            + (f" ({f['detail']:.2f}x for its thin parts)" if f.get("detail", 1.0) > 1.0 else "")
            for f in stats.get("per_field", [])]


def warn_about_fields(engine, stats):
    """Reports what the fields coarsened, once per render (instances they
    leave out, scaled flat, sync names before the render)."""
    if stats["resolution_scale"] < 1.0 and stats.get("resolution_limited_by") == "surface":
        # (many meshes' fields together: a model imported as its parts)
        print(f"RTSDF: field resolutions lowered to {stats['resolution_scale']:.0%}: the fields of "
              f"{stats['fields']} meshes hold more surface detail than a scene's fields may trace")
    elif stats["resolution_scale"] < 1.0:
        engine.report({"WARNING"}, f"RTSDF: field resolutions lowered to {stats['resolution_scale']:.0%} to fit "
                                   "the field memory budget")


classes = (RTSDFRenderEngine,)


def register():
    for cls in classes:
        bpy.utils.register_class(cls)


def unregister():
    for cls in reversed(classes):
        bpy.utils.unregister_class(cls)
