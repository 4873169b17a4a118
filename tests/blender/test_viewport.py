"""RTSDF's viewport in a real Blender window under Xvfb (tests/blender/viewport_driver.py
does the driving): Rendered shading through the camera puts the shadows where
Cycles puts them, an object moved from Python moves its shadow, and a hundred
frame changes leave memory flat.

RTSDF_SAMPLE_BLEND=build/samples/sphere_plane.blend BLENDER_USER_SCRIPTS=build/blender_user_scripts \
    python3 tests/blender/test_viewport.py
"""
import json
import os
import subprocess
import sys
import tempfile
import unittest

HERE = os.path.dirname(os.path.abspath(__file__))
SAMPLE = os.environ.get("RTSDF_SAMPLE_BLEND", os.path.join(HERE, "../../build/samples/sphere_plane.blend"))
FRAMES = 100


class Viewport(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.tmp = tempfile.TemporaryDirectory()
        command = ["xvfb-run", "-a", "-s", "-screen 0 1280x800x24",
                   "blender", "--window-geometry", "0", "0", "1200", "760", "--addons", "rtsdf", SAMPLE,
                   "--python", os.path.join(HERE, "viewport_driver.py"), "--", cls.tmp.name, "--frames", str(FRAMES)]
        cls.process = subprocess.run(command, capture_output=True, text=True, timeout=900)
        path = os.path.join(cls.tmp.name, "viewport.json")
        cls.results = json.load(open(path)) if os.path.exists(path) else None
        print(json.dumps(cls.results, indent=1), file=sys.stderr)

    @classmethod
    def tearDownClass(cls):
        cls.tmp.cleanup()

    def setUp(self):
        self.assertIsNotNone(self.results, f"the driver wrote no results:\n{self.process.stdout[-3000:]}\n{self.process.stderr[-3000:]}")
        self.assertEqual(self.results["errors"], [])

    def test_shadows_lie_where_cycles_puts_them(self):
        # Shadow masks (pixels of the ground far darker than its lit part) of
        # the 3D view's screenshot and of Cycles through the same camera.
        for state in ("before", "after"):
            with self.subTest(state=state):
                self.assertGreater(self.results[state]["cycles_pixels"], 100)
                self.assertGreater(self.results[state]["iou"], 0.75)

    def test_moving_an_object_moves_its_shadow(self):
        self.assertLess(self.results["moved_shadow_iou"], 0.5)

    def test_a_dimmed_light_dims_the_view(self):
        # (Display transforms are not linear: a quarter of the light is well under 0.8 of the brightness.)
        self.assertLess(self.results["dimmed_ground_luminance_ratio"], 0.8)

    def test_playback_frames_reuse_history(self):
        # Temporal reuse (the default): a frame change keeps the reprojected
        # history where nothing moved, so the pixels stand for more than the
        # one sample a restart would give.
        self.assertGreater(self.results["effective_samples_median"]["True"], 2.0)

    def test_frame_changes_leave_memory_flat(self):
        rss = self.results["rss_mib"]
        self.assertEqual(rss["frames"], FRAMES)
        self.assertLess(rss["after_all"] - rss["after_10"], 64.0, "resident memory grew over the frame changes")

    def test_no_validation_messages(self):
        self.assertEqual(self.results["validation_messages"], 0)


class FieldViewsInTheViewport(unittest.TestCase):
    """Each of RTSDF's field views draws in the viewport under Xvfb, and differs from the shaded view."""

    def test_each_field_view_draws_something_else(self):
        with tempfile.TemporaryDirectory() as out:
            command = ["xvfb-run", "-a", "-s", "-screen 0 1280x800x24", "blender", "--window-geometry", "0", "0",
                       "1200", "760", "--addons", "rtsdf", SAMPLE, "--python", os.path.join(HERE, "viewport_driver.py"),
                       "--", out, "--field-views"]
            process = subprocess.run(command, capture_output=True, text=True, timeout=600)
            path = os.path.join(out, "viewport.json")
            self.assertTrue(os.path.exists(path), process.stdout[-3000:] + process.stderr[-3000:])
            with open(path) as f:
                results = json.load(f)
        self.assertEqual(results["errors"], [])
        self.assertEqual(set(results["field_views"]), {"distance_slice", "march_steps", "field_resolution",
                                                       "exact_rays"})
        for view, figures in results["field_views"].items():
            self.assertGreater(figures["spread"], 0.02, view)
            self.assertGreater(figures["difference"], 0.002 if view == "exact_rays" else 0.01, view)


if __name__ == "__main__":
    unittest.main()
