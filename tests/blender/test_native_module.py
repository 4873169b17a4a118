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
