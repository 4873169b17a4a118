"""The RTSDF render engine: F12 and animation renders with Combined, Depth and
Shadow passes."""

import bpy
import numpy as np

from . import native, sync


class RTSDFRenderEngine(bpy.types.RenderEngine):
    bl_idname = "RTSDF"
    bl_label = "RTSDF"
    bl_use_preview = False
    bl_use_postprocess = True
    # The viewport's Rendered shading uses EEVEE until RTSDF draws it itself.
    bl_use_eevee_viewport = True

    def update_render_passes(self, scene=None, renderlayer=None):
        self.register_pass(scene, renderlayer, "Combined", 4, "RGBA", "COLOR")
        if renderlayer.use_pass_z:
            self.register_pass(scene, renderlayer, "Depth", 1, "Z", "VALUE")
        self.register_pass(scene, renderlayer, "Shadow", 1, "X", "VALUE")

    def render(self, depsgraph):
        scene = depsgraph.scene
        width, height = sync.render_size(scene)
        session, error = native.session()
        if session is None:
            self.report({"ERROR"}, f"RTSDF: {error}")
            return
        try:
            self.update_stats("RTSDF", "Reading the scene")
            data = sync.extract(depsgraph)
            self.update_stats("RTSDF", f"Rendering on {session.device}")

            def progress(done, total):
                self.update_progress(done / total)
                self.update_stats("RTSDF", f"Sample {done}/{total} on {session.device}")
                return not self.test_break()

            out = session.render(data, scene.rtsdf.as_dict(), progress, scene.render.use_persistent_data)
        except sync.SceneError as e:
            self.report({"ERROR"}, f"RTSDF: {e}")
            return
        except RuntimeError as e:  # the native core's errors (bad input, device, memory)
            self.report({"ERROR"}, f"RTSDF: {e}")
            return
        if out["samples_done"] == 0:
            return

        self.add_pass("Shadow", 1, "X")
        result = self.begin_result(0, 0, width, height)
        layer = result.layers[0]
        # Blender stores rows bottom to top.
        combined = np.flipud(out["combined"]).copy()
        if not scene.render.film_transparent:
            combined[..., 3] = 1.0
        layer.passes["Combined"].rect = combined.reshape(-1, 4)
        if "Depth" in layer.passes:
            layer.passes["Depth"].rect = np.flipud(out["depth"]).reshape(-1, 1)
        if "Shadow" in layer.passes:
            layer.passes["Shadow"].rect = np.flipud(out["shadow"]).reshape(-1, 1)
        self.end_result(result)
        ms = out["ms"]
        self.update_stats("RTSDF", f"SDF {ms['sdf']:.0f} ms | fine {ms['fine']:.0f} ms | "
                                   f"shading {ms['shade']:.0f} ms | total {ms['total']:.0f} ms")
        print(f"RTSDF: frame {scene.frame_current} {width}x{height} in {ms['total']:.0f} ms "
              f"(SDF {ms['sdf']:.0f}, fine {ms['fine']:.0f}, shading {ms['shade']:.0f}) on {session.device}")


classes = (RTSDFRenderEngine,)


def register():
    for cls in classes:
        bpy.utils.register_class(cls)


def unregister():
    for cls in reversed(classes):
        bpy.utils.unregister_class(cls)
