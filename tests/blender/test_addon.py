"""Run inside Blender with the staged add-on: it enables, finds its native
module and device, and disables and re-enables cleanly.

BLENDER_USER_SCRIPTS=build/blender_user_scripts blender -b --factory-startup \
    --python-exit-code 1 --python tests/blender/test_addon.py
"""
import sys
import unittest

import addon_utils
import bpy


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


result = unittest.main(argv=["blender"], exit=False, verbosity=2).result
sys.exit(0 if result.wasSuccessful() else 1)
