"""Run inside Blender with no Vulkan driver (VK_ICD_FILENAMES and
VK_DRIVER_FILES point at nothing): the add-on still enables, and an RTSDF
render ends in a clear report instead of a crash.
"""
import sys
import unittest

import addon_utils
import bpy

SAMPLE = sys.argv[sys.argv.index("--") + 1]


class NoVulkan(unittest.TestCase):
    def test_render_reports_missing_driver(self):
        addon_utils.enable("rtsdf", default_set=True, handle_error=None)
        bpy.ops.wm.open_mainfile(filepath=SAMPLE)
        scene = bpy.context.scene
        scene.render.engine = "RTSDF"
        scene.render.resolution_percentage = 10
        with self.assertRaises(RuntimeError) as caught:
            bpy.ops.render.render()
        message = str(caught.exception)
        print("reported:", message)
        self.assertIn("RTSDF", message)
        self.assertIn("Vulkan", message)


result = unittest.main(argv=["blender"], exit=False, verbosity=2).result
sys.exit(0 if result.wasSuccessful() else 1)
