"""Run inside Blender with the staged add-on: it enables, finds its native
module and device, and disables and re-enables cleanly.

BLENDER_USER_SCRIPTS=build/blender_user_scripts blender -b --factory-startup \
    --python-exit-code 1 --python tests/blender/test_addon.py
"""
import os
import sys
import types
import unittest

import addon_utils
import bpy
import numpy as np


class AddonInBlender(unittest.TestCase):
    def test_enable_disable_repeatedly(self):
        for _ in range(3):
            addon_utils.enable("rtsdf", default_set=True, handle_error=None)
            self.assertIn("rtsdf", bpy.context.preferences.addons)
            addon_utils.disable("rtsdf", default_set=True, handle_error=None)
            self.assertNotIn("rtsdf", bpy.context.preferences.addons)

    def test_native_module_and_device(self):
        addon_utils.enable("rtsdf", default_set=True, handle_error=None)
        import rtsdf
        module, error = rtsdf.native.load()
        self.assertIsNone(error)
        self.assertEqual(module.__version__, ".".join(map(str, rtsdf.bl_info["version"])))
        device, error = rtsdf.native.device()
        self.assertIsNone(error)
        self.assertTrue(device["name"])

    def test_one_light_panel(self):
        addon_utils.enable("rtsdf", default_set=True, handle_error=None)
        light_panels = [panel.__name__ for panel in bpy.types.Panel.__subclasses__()
                        if "RTSDF" in getattr(panel, "COMPAT_ENGINES", ()) and getattr(panel, "bl_context", "") == "data"
                        and getattr(panel, "bl_label", "") == "Light" and panel.bl_space_type == "PROPERTIES"]
        self.assertEqual(light_panels, ["DATA_PT_EEVEE_light"])
        addon_utils.disable("rtsdf", default_set=True, handle_error=None)
        self.assertFalse(any("RTSDF" in getattr(panel, "COMPAT_ENGINES", ()) for panel in bpy.types.Panel.__subclasses__()
                             if panel.__name__ == "DATA_PT_EEVEE_light"))

    def test_the_engine_leaves_material_nodes_and_material_preview_to_blender(self):
        addon_utils.enable("rtsdf", default_set=True, handle_error=None)
        engine = next(e for e in bpy.types.RenderEngine.__subclasses__() if e.bl_idname == "RTSDF")
        self.assertFalse(engine.bl_use_shading_nodes_custom, "the Shader Editor edits this engine's materials")
        self.assertTrue(engine.bl_use_eevee_viewport, "Material Preview runs EEVEE")
        self.assertFalse(engine.bl_use_preview, "no material preview of its own, so no stray preview panels")

    def test_the_panels_defaults_are_the_native_ones(self):
        # One default per setting: what a user gets in Blender is what the
        # native API, the CLI and bench/run get when they leave it out.
        # Exact Rays is the one deliberate difference: Blender's default is
        # the recommended 4 (the Final preset's), the native default the
        # paper's method (0), which bench/run sweeps from.
        addon_utils.enable("rtsdf", default_set=True, handle_error=None)
        import rtsdf
        module, error = rtsdf.native.load()
        self.assertIsNone(error)
        native_defaults = module.default_settings()
        properties = bpy.context.scene.rtsdf.bl_rna.properties
        shared = [key for key in native_defaults if key in properties]
        self.assertGreaterEqual(len(shared), 15, "the keys the panel and the native side share")
        for key in shared:
            with self.subTest(setting=key):
                expected = 4 if key == "exact_rays" else native_defaults[key]
                self.assertAlmostEqual(properties[key].default, expected, places=5) \
                    if isinstance(expected, float) else self.assertEqual(properties[key].default, expected)
        self.assertEqual(native_defaults["exact_rays"], 0)

    def test_manifest_agrees_with_bl_info(self):
        # Blender 4.2 installs an extension from its manifest; 3.x reads bl_info.
        import tomllib
        addon_utils.enable("rtsdf", default_set=True, handle_error=None)
        import rtsdf
        with open(os.path.join(os.path.dirname(rtsdf.__file__), "blender_manifest.toml"), "rb") as f:
            manifest = tomllib.load(f)
        for key in ("schema_version", "id", "version", "name", "tagline", "maintainer", "type", "blender_version_min",
                    "license"):
            self.assertIn(key, manifest)
        self.assertEqual(manifest["type"], "add-on")
        self.assertEqual(manifest["version"], ".".join(map(str, rtsdf.bl_info["version"])))
        self.assertEqual(manifest["name"], rtsdf.bl_info["name"])

    def test_the_blender_4_api_paths(self):
        """The add-on's Python where Blender 4.x's API differs from 3.4's, run
        against stand-ins with 4.x's shape: a light's shadow toggle is
        `use_shadow` (no Cycles `cast_shadow`), a mesh has `normals_domain`
        and `corner_normals` (no `calc_normals_split`, no `use_auto_smooth`)."""
        addon_utils.enable("rtsdf", default_set=True, handle_error=None)
        from rtsdf import sync
        light = types.SimpleNamespace(use_shadow=False)  # (4.x: no light.cycles.cast_shadow)
        self.assertFalse(sync.light_casts_shadow(light))
        sync.set_light_casts_shadow(light, True)
        self.assertTrue(light.use_shadow)

        class Values:  # (a bpy collection's foreach_get over one flat array)
            def __init__(self, values):
                self.values = np.asarray(values, np.float32).ravel()

            def __len__(self):
                return len(self.values)

            def foreach_get(self, name, out):
                out[:] = self.values

        normals = [(0, 0, 1), (0, 1, 0), (1, 0, 0), (0, 0, -1)]  # one per face corner
        mesh = types.SimpleNamespace(normals_domain="CORNER", loops=[None] * 4, corner_normals=Values(normals),
                                     loop_triangles=Triangles([0, 1, 2, 0, 2, 3]))
        self.assertEqual(sync.normals_domain(mesh), "CORNER")
        corners = sync.corner_normals(mesh)
        np.testing.assert_array_equal(corners, np.array(normals, np.float32)[[0, 1, 2, 0, 2, 3]])


class Triangles:
    """A stand-in for Mesh.loop_triangles: their corners' loops."""
    def __init__(self, loops):
        self.loops = np.asarray(loops, np.int32)

    def __len__(self):
        return len(self.loops) // 3

    def foreach_get(self, name, out):
        assert name == "loops"
        out[:] = self.loops


result = unittest.main(argv=["blender"], exit=False, verbosity=2).result
sys.exit(0 if result.wasSuccessful() else 1)
