"""bench/run's contract and figures: the leak and Pareto rules on made-up data, and a
quick run on one sample scene that must write results.csv (exactly the contract's
columns, a row per method), speed_accuracy.png and summary.md.

RTSDF_BUILD_DIR=build python3 -m unittest -v tests/bench/test_bench.py
"""
import csv
import importlib.machinery
import importlib.util
import os
import subprocess
import sys
import tempfile
import unittest

import numpy as np

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
BENCH = os.path.join(ROOT, "bench", "run")


def load_bench():
    loader = importlib.machinery.SourceFileLoader("rtsdf_bench", BENCH)
    spec = importlib.util.spec_from_loader("rtsdf_bench", loader)
    module = importlib.util.module_from_spec(spec)
    loader.exec_module(module)
    return module


bench = load_bench()


def load_playback_error():
    path = os.path.join(ROOT, "bench", "playback_error.py")
    spec = importlib.util.spec_from_file_location("rtsdf_playback_error", path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


class Figures(unittest.TestCase):
    def test_leak_counts_umbra_pixels_that_get_the_lights_light(self):
        world = np.full((10, 10, 3), 0.05, np.float32)
        unshadowed = world + 0.5  # the lights add 0.5 everywhere
        reference = unshadowed.copy()
        reference[:5] = world[:5]  # the top half is in Cycles' umbra
        image = reference.copy()
        self.assertEqual(bench.metrics.leak(image, reference, unshadowed, world), 0.0)
        image[:2] = unshadowed[:2]  # 20 of the 50 umbra pixels lit
        self.assertAlmostEqual(bench.metrics.leak(image, reference, unshadowed, world), 0.4)
        # Where the world's light dominates, there is no umbra to judge.
        self.assertIsNone(bench.metrics.leak(image, reference, world * 10 + 0.001, world * 10))

    def test_ssim_is_scikit_images_without_it(self):
        # (Blender bundles no scikit-image: metrics computes SSIM with numpy, as scikit-image does by default.)
        rng = np.random.default_rng(7)
        a = rng.random((40, 60))
        b = np.clip(a + rng.normal(0.0, 0.1, a.shape), 0.0, 1.0)
        self.assertAlmostEqual(bench.metrics.structural_similarity(a, a), 1.0)
        self.assertLess(bench.metrics.structural_similarity(a, b), 0.99)
        try:
            from skimage.metrics import structural_similarity
        except ImportError:
            self.skipTest("no scikit-image to compare with")
        self.assertAlmostEqual(bench.metrics.structural_similarity(a, b), structural_similarity(a, b, data_range=1.0),
                               places=9)

    def test_static_pixels_leave_out_the_movers_way_out_of_the_view(self):
        # A unit quad seen from 5 units away moves 3 units right, off the image, down and
        # to the right: its path crosses pixels that neither Cycles image changes.
        width, height = 64, 32
        focal = 2.0
        projection = [[focal * height / width, 0, 0, 0], [0, focal, 0, 0], [0, 0, -1, -0.2], [0, 0, -1, 0]]
        world_to_view = [[1, 0, 0, 0], [0, 1, 0, 0], [0, 0, 1, -5], [0, 0, 0, 1]]
        mesh = {"positions": np.array([0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0], np.float32)}

        def pose(x, y):
            matrix = np.eye(4, dtype=np.float32)
            matrix[:3, 3] = (x, y, 0.0)
            return {"width": width, "height": height, "meshes": [mesh],
                    "camera": {"world_to_view": world_to_view, "projection": projection, "orthographic": False},
                    "instances": [{"mesh": 0, "matrix": matrix}]}

        data = {"before": pose(-1.5, 0.0), "after": pose(3.0, -4.0)}
        refs = {"before_shadowed": np.zeros((height, width, 3), np.float32)}
        refs["after_shadowed"] = refs["before_shadowed"].copy()
        # Cycles sees the quad before the move only (after it, it is out of the view).
        self.assertEqual(bench.mover_screen_box(data, 0), (9, 16, 22, 29))
        self.assertIsNone(bench.mover_screen_box(data, bench.ANIMATION_STEPS))
        refs["after_shadowed"][9:17, 22:30] = 1.0
        # Half way, it is wholly below and right of those pixels.
        middle = bench.mover_screen_box(data, bench.ANIMATION_STEPS // 2)
        self.assertGreater(middle[0], 16)
        self.assertGreater(middle[2], 29)
        static = bench.static_pixels(refs, data, margin=0.0)
        self.assertFalse(static[middle[0]:middle[1] + 1, middle[2]:middle[3] + 1].any())
        self.assertFalse(static[9:17, 22:30].any())
        self.assertTrue(static[:8, 30:].all())  # (above the path, right of the start: left alone)
        # An instance that does not move has no path; one crossing the camera's plane takes the whole image.
        self.assertIsNone(bench.mover_screen_box({"before": data["before"], "after": data["before"]}, 4))
        mesh["positions"] = np.array([0, 0, 0, 1, 0, 0, 1, 0, 10, 0, 0, 10], np.float32)  # (upright, through z = 5)
        self.assertEqual(bench.mover_screen_box({"before": pose(0.0, 0.0), "after": pose(1.0, 0.0)}, 4),
                         (0, height - 1, 0, width - 1))

    def test_a_recorded_animation_plays_each_steps_pose(self):
        # A scene whose animation deforms a mesh: prepare recorded every step's
        # transforms and deformed meshes; a viewport is shown each step's, and a
        # mesh back in its first shape is put back.
        quad = {"positions": np.array([0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0], np.float32)}
        bent = {"positions": np.array([0, 0, 0, 1, 0, 1, 1, 1, 1, 0, 1, 0], np.float32)}
        moved = np.eye(4, dtype=np.float32)
        moved[0, 3] = 2.0
        still = {"instances": [{"mesh": 0, "matrix": np.eye(4, dtype=np.float32)}], "meshes": [quad]}
        steps = [{"transforms": [np.eye(4, dtype=np.float32)], "meshes": {0: bent}} for _ in range(bench.ANIMATION_STEPS)]
        steps[1] = {"transforms": [np.eye(4, dtype=np.float32)], "meshes": {}}
        steps[-1] = {"transforms": [moved], "meshes": {0: bent}}
        data = {"before": still, "after": {"instances": [{"mesh": 0, "matrix": moved}], "meshes": [bent]},
                "steps": steps}
        self.assertEqual(bench.moving_instances(data), [0])

        class Viewport:
            def __init__(self):
                self.calls = []

            def set_transforms(self, transforms):
                self.calls.append(("transforms", float(transforms[0][0, 3])))

            def set_mesh_geometry(self, index, mesh):
                self.calls.append(("mesh", index, mesh is bent))

        viewport, deformed = Viewport(), set()
        bench.show_pose(viewport, data, 1, deformed)
        self.assertEqual(viewport.calls, [("transforms", 0.0), ("mesh", 0, True)])
        bench.show_pose(viewport, data, 2, deformed)
        self.assertEqual(viewport.calls[2:], [("transforms", 0.0), ("mesh", 0, False)])  # (back in its first shape)
        self.assertEqual(deformed, set())
        bench.show_pose(viewport, data, bench.ANIMATION_STEPS, deformed)
        self.assertEqual(viewport.calls[4:], [("transforms", 2.0), ("mesh", 0, True)])
        # Without recorded steps (a rigid move), transforms in between and the last shape at the end.
        rigid = {"before": still, "after": data["after"]}
        transforms, meshes = bench.pose(rigid, bench.ANIMATION_STEPS // 2)
        self.assertAlmostEqual(float(transforms[0][0, 3]), 1.0)
        self.assertEqual(meshes, {})
        self.assertIs(bench.pose(rigid, bench.ANIMATION_STEPS)[1][0], bent)

    def test_playback_error_splits_the_excess_at_geometry_edges_from_the_rest(self):
        playback_error = load_playback_error()
        unshadowed = np.full((20, 20, 3), 0.8, np.float32)
        unshadowed[:, 10:] = 0.2  # an outline down the middle (columns 9 and 10; 8 to 11 with their neighbours)
        reference = unshadowed * 0.5  # all of it in shadow
        refs = {"after_shadowed": reference, "after_unshadowed": unshadowed}
        edges = playback_error.geometry_edges(unshadowed)
        self.assertTrue(edges[:, 8:12].all())
        self.assertFalse(edges[:, :7].any() or edges[:, 13:].any())
        still = reference.copy()
        played = reference.copy()
        played[:, 9] += 0.1  # off at the outline
        at_edges, elsewhere = playback_error.excess_at_edges(played, still, refs)
        self.assertAlmostEqual(at_edges, 0.01 * 20 / 400, places=6)
        self.assertAlmostEqual(elsewhere, 0.0, places=6)
        played[:, 2] += 0.1  # and on the flat part
        at_edges, elsewhere = playback_error.excess_at_edges(played, still, refs)
        self.assertAlmostEqual(elsewhere, 0.01 * 20 / 400, places=6)
        # The still frame's own error there is not counted again.
        still[:, 2] += 0.1
        self.assertAlmostEqual(playback_error.excess_at_edges(played, still, refs)[1], 0.0, places=6)

    def test_pareto_front(self):
        points = [(10.0, 0.5), (20.0, 0.2), (15.0, 0.6), (30.0, 0.1), (30.0, 0.3)]
        self.assertEqual(bench.pareto(points), [0, 1, 3])


class QuickRun(unittest.TestCase):
    def test_quick_run_on_one_scene_writes_the_contract(self):
        build = os.environ.get("RTSDF_BUILD_DIR", os.path.join(ROOT, "build"))
        if not os.path.exists(os.path.join(build, "samples", "sphere_plane.blend")):
            self.skipTest("no sample scenes built")
        with tempfile.TemporaryDirectory() as out:
            result = subprocess.run([sys.executable, BENCH, "--quick", "--out", out, "--scenes", "sphere_plane"],
                                    capture_output=True, text=True, timeout=600)
            self.assertEqual(result.returncode, 0, result.stdout[-3000:] + result.stderr[-3000:])
            with open(os.path.join(out, "results.csv"), newline="") as f:
                reader = csv.DictReader(f)
                self.assertEqual(reader.fieldnames, ["scene", "method", "setting", "ms_per_frame", "shadow_rmse",
                                                     "ssim", "flicker", "ghost_frames", "leak", "field_mb",
                                                     "dense_mb", "playback_rmse", "playback_ratio",
                                                     "playback_flicker", "playback_rmse_no_reuse", "device"])
                rows = list(reader)
            methods = {row["method"] for row in rows}
            self.assertEqual(methods, {"cycles", "rtsdf", "rtsdf_world", "rt_only", "jfa_only", "csm_evsm", "csm_jitter",
                                       "raytraced", "eevee"})
            for row in rows:
                self.assertGreater(float(row["ms_per_frame"]), 0.0)
                if row["method"] != "cycles":
                    self.assertTrue(0.0 <= float(row["shadow_rmse"]) < 1.0, row)
            # The still scene's default rtsdf setting: no ghost left after the move.
            first = next(row for row in rows if row["method"] == "rtsdf")
            # Its refined fields keep their bricks and far fields, not dense grids.
            self.assertLess(float(first["field_mb"]), float(first["dense_mb"]) / 4, first)
            self.assertEqual(first["ghost_frames"], "1", first)
            # Its playback figures, and EEVEE's: the shown frame's error, and its ratio to the still frame's.
            eevee = next(row for row in rows if row["method"] == "eevee")
            for row in (first, eevee):
                self.assertTrue(0.0 < float(row["playback_rmse"]) < 1.0, row)
                still = float(row["playback_rmse"]) / float(row["playback_ratio"])
                self.assertTrue(0.0 < still < 1.0, row)
                self.assertGreaterEqual(float(row["playback_flicker"]), 0.0, row)
            self.assertTrue(0.0 < float(first["playback_rmse_no_reuse"]) < 1.0, first)
            self.assertGreater(os.path.getsize(os.path.join(out, "speed_accuracy.png")), 10000)
            with open(os.path.join(out, "summary.md")) as f:
                self.assertIn("| sphere_plane |", f.read())
            # The shadow-map baselines at their best: csm_jitter (EEVEE's own soft shadows) within 1.5x of EEVEE.
            best = {m: min(float(r["shadow_rmse"]) for r in rows if r["method"] == m) for m in ("csm_jitter", "eevee")}
            self.assertLess(best["csm_jitter"], 1.5 * best["eevee"], best)
            # evaluation.md: the commit, the device, the command, and every method's image beside Cycles'.
            with open(os.path.join(out, "evaluation.md")) as f:
                evaluation = f.read()
            for needle in ("from commit", "--scenes sphere_plane", first["device"], "images/sphere_plane.jpg",
                           "frame cost"):
                self.assertIn(needle, evaluation)
            self.assertGreater(os.path.getsize(os.path.join(out, "images", "sphere_plane.jpg")), 20000)


if __name__ == "__main__":
    unittest.main()
