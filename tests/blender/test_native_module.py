"""Run inside Blender: the native module imports in Blender's Python and works.

blender -b --factory-startup --python-exit-code 1 --python tests/blender/test_native_module.py
"""
import os
import sys
import unittest

import bpy  # noqa: F401  (proves we are inside Blender)
import numpy as np

native_dir = os.environ.get("RTSDF_NATIVE_DIR")
if native_dir:
    sys.path.insert(0, native_dir)
import rtsdf_native  # noqa: E402


def cube_scene():
    """A 2-unit cube at the origin, seen by a camera 6 units along +z looking down -z, 16x16 pixels."""
    corners = np.array([[x, y, z] for z in (-1, 1) for y in (-1, 1) for x in (-1, 1)], np.float32)
    faces = np.array([[0, 2, 1], [1, 2, 3], [4, 5, 6], [5, 7, 6], [0, 1, 4], [1, 5, 4],
                      [2, 6, 3], [3, 6, 7], [0, 4, 2], [2, 4, 6], [1, 3, 5], [3, 7, 5]], np.uint32)
    eye = np.eye(4, dtype=np.float32)
    view_matrix = eye.copy()
    view_matrix[2, 3] = -6.0
    projection = np.array([[1, 0, 0, 0], [0, 1, 0, 0], [0, 0, -1, -0.2], [0, 0, -1, 0]], np.float32)
    return {"meshes": [{"positions": corners, "indices": faces}], "instances": [{"mesh": 0, "matrix": eye}],
            "lights": [], "ambient": (0.5, 0.5, 0.5), "width": 16, "height": 16,
            "camera": {"world_to_view": view_matrix, "projection": projection}}


class NativeModuleInBlender(unittest.TestCase):
    def test_version_and_device(self):
        self.assertTrue(rtsdf_native.__version__)
        devices = rtsdf_native.devices()
        self.assertGreater(len(devices), 0)
        info = rtsdf_native.device_info()
        self.assertIn(info["name"], [d["name"] for d in devices])

    def test_coarse_sdf_of_a_blender_mesh(self):
        mesh = bpy.data.meshes.new("cube")
        import bmesh
        bm = bmesh.new()
        bmesh.ops.create_cube(bm, size=2.0)
        bmesh.ops.triangulate(bm, faces=bm.faces)
        bm.to_mesh(mesh)
        bm.free()
        positions = np.empty(len(mesh.vertices) * 3, dtype=np.float32)
        mesh.vertices.foreach_get("co", positions)
        mesh.loop_triangles.update() if hasattr(mesh.loop_triangles, "update") else mesh.calc_loop_triangles()
        indices = np.empty(len(mesh.loop_triangles) * 3, dtype=np.int32)
        mesh.loop_triangles.foreach_get("vertices", indices)
        result = rtsdf_native.coarse_sdf(positions.reshape(-1, 3), indices.reshape(-1, 3).astype(np.uint32), 32, 0.5)
        d = result["distance"]
        self.assertEqual(d.shape, tuple(reversed(result["dims"])))
        vs = result["voxel_size"]
        # The centre of the cube is 1 unit from every face; the coarse distance is within a voxel of that.
        centre = tuple(n // 2 for n in d.shape)
        self.assertAlmostEqual(float(d[centre]) + result["beta"], 1.0, delta=1.0 * vs)

    def test_a_viewport_sees_a_small_view_change_whatever_numpys_print_options(self):
        # The viewport restarts its accumulation when the view changes; a camera
        # moved by a hundred-thousandth of a unit is a change even where numpy
        # prints two decimals (an add-on may set that for the whole process).
        scene = cube_scene()
        view_matrix = scene["camera"]["world_to_view"]
        viewport = rtsdf_native.Session().viewport()
        viewport.sync(scene)
        view = {key: scene[key] for key in ("camera", "lights", "ambient", "width", "height")}
        settings = {"samples": 2, "coarse_resolution": 16, "fine_resolution": 32}
        before = np.get_printoptions()
        np.set_printoptions(precision=2)
        try:
            for _ in range(64):
                if viewport.draw(view, settings)["converged"]:
                    break
            self.assertFalse(viewport.draw(view, settings)["advanced"], "converged: nothing more to do")
            moved = dict(view, camera=dict(view["camera"], world_to_view=view_matrix.copy()))
            moved["camera"]["world_to_view"][2, 3] -= 1e-5  # (-6.00001: numpy prints "-6.")
            out = viewport.draw(moved, settings)
            self.assertTrue(out["advanced"])
            self.assertEqual(out["frames"], 1, "a new accumulation")
        finally:
            np.set_printoptions(**before)

    def test_a_viewport_reports_the_samples_of_each_pixel(self):
        # With temporal reuse the draw hands back each pixel's samples (history's
        # included): their mean over the pixels that show something is the
        # effective sample count, and none stands for more than the setting's.
        scene = cube_scene()
        viewport = rtsdf_native.Session().viewport()
        viewport.sync(scene)
        view = {key: scene[key] for key in ("camera", "lights", "ambient", "width", "height")}
        settings = {"samples": 4, "coarse_resolution": 16, "fine_resolution": 32, "temporal_reuse": True}
        for _ in range(3):
            out = viewport.draw(view, settings)
        samples = out["samples"]
        self.assertEqual(samples.shape, (scene["height"], scene["width"]))
        shown = out["combined"][..., 3] > 0.0
        self.assertTrue(shown.any())
        self.assertAlmostEqual(float(samples[shown].mean()), out["effective_samples"], places=3)
        self.assertLessEqual(float(samples.max()), settings["samples"])
        self.assertEqual(float(samples[shown].min()), 3.0, "three frames drawn")

    def test_viewport_fine_sdf_reads_back(self):
        # A 2-unit cube: the fine SDF just inside its face is negative, just outside it the distance to the face.
        scene = cube_scene()
        eye = scene["instances"][0]["matrix"]
        viewport = rtsdf_native.Session().viewport()
        viewport.sync(scene)
        self.assertIsNone(viewport.fine_sdf())
        view = {key: scene[key] for key in ("camera", "lights", "ambient", "width", "height")}
        # sdf_updates 0 (the viewport's): the field refines over 4 passes of its band, 8 updates at interleave 2.
        settings = {"samples": 3, "coarse_resolution": 32, "fine_resolution": 64, "sdf_updates": 0, "interleave": 2}
        for _ in range(3):
            viewport.draw(view, settings)
        fine = viewport.fine_sdf()
        self.assertEqual(fine["space"], "object")  # (the cube's own field; its instance is untransformed)
        distance, origin, voxel = fine["distance"], np.array(fine["origin"]), fine["voxel_size"]
        self.assertEqual(distance.ndim, 3)

        def at(point):
            index = np.floor((np.array(point) - origin) / voxel).astype(int)
            return float(distance[index[2], index[1], index[0]]), origin + (index + 0.5) * voxel

        inside, centre = at((0.0, 0.0, 1.0 - 1.5 * voxel))
        self.assertLess(inside, 0.0)
        outside, centre = at((0.0, 0.0, 1.0 + 1.5 * voxel))
        self.assertAlmostEqual(outside, centre[2] - 1.0, delta=0.5 * voxel)

        # Moved after 3 of its at most 8 updates: the field keeps refining (a
        # move costs it nothing), and the viewport keeps drawing past its 3
        # samples until the field is done (its 8 updates, or sooner once a
        # whole round of turns found nothing closer), then stops.
        moved = eye.copy()
        moved[0, 3] = 0.5
        viewport.set_transforms([moved])
        draws = [viewport.draw(view, settings) for _ in range(12)]
        advanced = sum(d["advanced"] for d in draws)
        self.assertTrue(1 <= advanced <= 5, advanced)
        self.assertEqual([d["advanced"] for d in draws], [True] * advanced + [False] * (12 - advanced))
        self.assertEqual([d["converged"] for d in draws], [False] * (advanced - 1) + [True] * (13 - advanced))
        self.assertGreater(draws[0]["stats"]["last_frame_traced_texels"], 0)
        self.assertEqual([d["stats"]["fields_regenerated"] for d in draws], [0] * 12)
        viewport.set_transforms([eye])
        still = viewport.draw(view, settings)["stats"]
        self.assertEqual(still["last_frame_traced_texels"], 0, "refined: moves trace nothing")
        # Refined: the cube's field keeps only its bricks near the faces and its far field.
        [cube] = still["per_field"]
        self.assertEqual(cube["mesh"], 0)
        self.assertAlmostEqual(cube["mb"], still["field_mb"], places=6)
        self.assertTrue(0 < cube["stored_bricks"] < cube["brick_count"], cube)
        self.assertLess(still["field_mb"], still["field_dense_mb"] / 4)
        self.assertAlmostEqual(cube["voxel_size"], fine["voxel_size"], places=6)
        self.assertEqual(cube["detail"], 1.0, "a cube has no part thinner than its voxel")

        # New geometry in place: the same again changes nothing; triangles
        # split along other diagonals rebuild the cube's field.
        viewport.set_mesh_geometry(0, scene["meshes"][0])
        self.assertEqual(viewport.draw(view, settings)["stats"]["fields_regenerated"], 0)
        flipped = dict(scene["meshes"][0], indices=np.array([[0, 2, 3], [0, 3, 1], [4, 5, 7], [4, 7, 6], [0, 1, 5],
                                                             [0, 5, 4], [2, 6, 7], [2, 7, 3], [0, 4, 6], [0, 6, 2],
                                                             [1, 3, 7], [1, 7, 5]], np.uint32))
        viewport.set_mesh_geometry(0, flipped)
        self.assertEqual(viewport.draw(view, settings)["stats"]["fields_regenerated"], 1)

    def assert_panel_range_is_the_native_one(self, name, valid, refused, message, **others):
        """The panel offers `valid`'s values as its range ends; the native side takes them and refuses
        `refused`'s with `message`."""
        scene = cube_scene()
        viewport = rtsdf_native.Session().viewport()
        viewport.sync(scene)
        view = {key: scene[key] for key in ("camera", "lights", "ambient", "width", "height")}
        for value in valid:
            viewport.draw(view, {name: value, "samples": 1, **others})
        for value in refused:
            with self.assertRaisesRegex(rtsdf_native.Error, message):
                viewport.draw(view, {name: value, "samples": 1, **others})

    def test_shadow_map_sizes_outside_the_panels_range_are_refused(self):
        self.assert_panel_range_is_the_native_one("shadow_map_size", (64, 4096), (32, 8192),
                                                  "shadow_map_size must be 64 to 4096", shadow_method="csm_evsm")

    def test_exact_rays_while_playing_outside_the_panels_range_are_refused(self):
        self.assert_panel_range_is_the_native_one("short_history_rays", (1, 16), (0, 17),
                                                  "short_history_rays must be 1", exact_rays=4)

    def test_noise_thresholds_outside_the_panels_range_are_refused(self):
        self.assert_panel_range_is_the_native_one("noise_threshold", (0.0, 1.0), (-0.01, 1.5),
                                                  "noise_threshold must be 0")

    def test_a_field_store_outside_the_preferences_range_or_on_a_file_is_refused(self):
        import tempfile
        session = rtsdf_native.Session()
        with tempfile.TemporaryDirectory() as directory:
            for capacity_mb in (16, 1 << 20):  # (the add-on's Disk Space)
                session.set_field_store(directory, capacity_mb)
                self.assertEqual(session.field_store["capacity_mb"], capacity_mb)
            for capacity_mb in (15, (1 << 20) + 1, float("nan")):
                with self.assertRaisesRegex(rtsdf_native.Error, "capacity_mb must be 16 to 1048576"):
                    session.set_field_store(directory, capacity_mb)
            a_file = os.path.join(directory, "a_file")
            open(a_file, "w").close()
            with self.assertRaisesRegex(rtsdf_native.Error, "cannot use .*a_file"):
                session.set_field_store(a_file, 64)
            session.set_field_store("")
            self.assertIsNone(session.field_store)

    def test_bad_input_raises(self):
        with self.assertRaises(rtsdf_native.Error):
            rtsdf_native.coarse_sdf(np.zeros((3, 3), np.float32), np.zeros((0, 3), np.uint32), 32, 0.5)
        with self.assertRaises(rtsdf_native.Error):
            rtsdf_native.coarse_sdf(np.array([[0, 0, 0], [1, 0, 0], [np.nan, 1, 0]], np.float32),
                                    np.array([[0, 1, 2]], np.uint32), 32, 0.5)
        with self.assertRaises(rtsdf_native.Error):
            rtsdf_native.coarse_sdf(np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0]], np.float32),
                                    np.array([[0, 1, 2]], np.uint32), 0, 0.5)


result = unittest.main(argv=["blender"], exit=False, verbosity=2).result
if not result.wasSuccessful():
    sys.exit(1)
