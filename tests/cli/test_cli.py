"""The `rtsdf sdf` command-line contract: outputs, figures and one-line errors."""
import json
import os
import subprocess
import tempfile
import unittest

import numpy as np
import pyopenvdb as vdb

RTSDF = os.environ["RTSDF_BIN"]
SAMPLE = os.environ["RTSDF_SAMPLE_MESH"]


def run(*args):
    return subprocess.run([RTSDF, *args], capture_output=True, text=True, timeout=300)


class SdfCommand(unittest.TestCase):
    def setUp(self):
        self.tmp = tempfile.TemporaryDirectory()
        self.dir = self.tmp.name

    def tearDown(self):
        self.tmp.cleanup()

    def path(self, name):
        return os.path.join(self.dir, name)

    def write(self, name, text):
        with open(self.path(name), "w") as f:
            f.write(text)
        return self.path(name)

    def assert_one_line_error(self, result, fragment):
        self.assertNotEqual(result.returncode, 0)
        self.assertGreater(result.returncode, 0, "killed by a signal: " + result.stderr)
        lines = result.stderr.strip().splitlines()
        self.assertEqual(len(lines), 1, result.stderr)
        self.assertIn("error", lines[0])
        self.assertIn(fragment, lines[0])

    def test_writes_vdb_and_json(self):
        out, js = self.path("c.vdb"), self.path("c.json")
        result = run("sdf", SAMPLE, "--coarse-res", "48", "--beta", "0.75", "--out", out, "--json", js)
        self.assertEqual(result.returncode, 0, result.stderr)
        self.assertNotIn("validation", result.stderr.lower())
        with open(js) as f:
            report = json.load(f)
        for key in ("device", "triangles", "voxel_size", "dims", "beta", "ms"):
            self.assertIn(key, report)
        for key in ("voxelize", "jump_flood", "total"):
            self.assertGreater(report["ms"][key], 0.0)
        self.assertEqual(max(report["dims"]), 48)
        self.assertAlmostEqual(report["beta"], 0.75 * report["voxel_size"], places=6)
        self.assertGreater(report["triangles"], 15000)

        grid = vdb.read(out, "coarse")
        self.assertEqual(grid.name, "coarse")
        self.assertEqual(grid.gridClass, vdb.GridClass.LEVEL_SET)
        dims = report["dims"]
        values = np.zeros((dims[0], dims[1], dims[2]), dtype=np.float32)
        grid.copyToArray(values, ijk=(0, 0, 0))
        # Negative (inside the thickened surface) somewhere, positive far away, in world units.
        self.assertLess(values.min(), 0.0)
        self.assertGreater(values.max(), 5 * report["voxel_size"])
        self.assertAlmostEqual(values.min(), -report["beta"], places=5)
        # Index (0,0,0) sits half a voxel inside the grid's corner.
        world = grid.transform.indexToWorld((0, 0, 0))
        for axis in range(3):
            self.assertAlmostEqual(world[axis], report["origin"][axis] + 0.5 * report["voxel_size"], places=5)

    def test_fine_sdf_flags_grids_and_figures(self):
        out, js = self.path("f.vdb"), self.path("f.json")
        result = run("sdf", SAMPLE, "--coarse-res", "32", "--fine-res", "64", "--frames", "3", "--d", "1.5",
                     "--alpha", "0.8", "--rays", "4", "--out", out, "--json", js)
        self.assertEqual(result.returncode, 0, result.stderr)
        with open(js) as f:
            report = json.load(f)
        for key in ("fine_trace", "bvh_build"):
            self.assertGreater(report["ms"][key], 0.0)
        self.assertEqual(len(report["ms"]["fine_frames"]), 3)
        self.assertGreater(report["texels_traced"], 0)
        self.assertEqual(report["rays_per_frame"], 4 * report["texels_traced"])
        self.assertEqual(max(report["fine_dims"]), 64)
        # Only the band is traced: far fewer texels than the fine grid holds.
        fine_voxels = report["fine_dims"][0] * report["fine_dims"][1] * report["fine_dims"][2]
        self.assertLess(report["texels_traced"], fine_voxels)
        names = [g.name for g in vdb.readAllGridMetadata(out)]
        self.assertEqual(sorted(names), ["coarse", "fine"])
        fine = vdb.read(out, "fine")
        self.assertEqual(fine.gridClass, vdb.GridClass.LEVEL_SET)
        self.assertAlmostEqual(fine.transform.voxelSize()[0], report["fine_voxel_size"], places=6)
        for bad in (["--alpha", "1.0"], ["--rays", "0"], ["--fine-res", "16"], ["--frames", "0"], ["--interleave", "0"]):
            self.assert_one_line_error(run("sdf", SAMPLE, "--coarse-res", "32", "--fine-res", "64", *bad,
                                           "--out", self.path("x.vdb")), "")

    def test_help_documents_every_flag(self):
        result = run("sdf", "--help")
        self.assertEqual(result.returncode, 0)
        for flag in ("--coarse-res", "--beta", "--out", "--json", "MESH", "--fine-res", "--frames", "--d", "--alpha",
                     "--rays", "--interleave"):
            self.assertIn(flag, result.stdout)

    def test_missing_file(self):
        self.assert_one_line_error(run("sdf", self.path("none.obj"), "--out", self.path("x.vdb")), "cannot open")

    def test_unreadable_file(self):
        bad = self.write("bad.obj", "this is not\x00 a mesh \x01\x02\n")
        self.assert_one_line_error(run("sdf", bad, "--out", self.path("x.vdb")), "")

    def test_no_triangles(self):
        points = self.write("points.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nl 1 2\n")
        self.assert_one_line_error(run("sdf", points, "--out", self.path("x.vdb")), "")

    def test_nan_and_infinite_coordinates(self):
        for value in ("nan", "inf"):
            mesh = self.write(value + ".ply", "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\n"
                              "property float y\nproperty float z\nelement face 1\n"
                              "property list uchar int vertex_indices\nend_header\n"
                              f"0 0 0\n1 0 0\n0 {value} 0\n3 0 1 2\n")
            self.assert_one_line_error(run("sdf", mesh, "--out", self.path("x.vdb")), "")

    def test_resolution_out_of_range(self):
        for res in ("0", "1025", "-5", "abc"):
            self.assert_one_line_error(run("sdf", SAMPLE, "--coarse-res", res, "--out", self.path("x.vdb")), "")

    def test_unwritable_output(self):
        self.assert_one_line_error(run("sdf", SAMPLE, "--coarse-res", "16", "--out", "/nonexistent/dir/x.vdb"),
                                   "cannot write")

    def test_unknown_device(self):
        result = subprocess.run([RTSDF, "sdf", SAMPLE, "--out", self.path("x.vdb")], capture_output=True, text=True,
                                env={**os.environ, "RTSDF_DEVICE": "no-such-gpu"})
        self.assert_one_line_error(result, "no-such-gpu")

    def test_no_vulkan_driver(self):
        env = {**os.environ, "VK_ICD_FILENAMES": self.path("none.json"), "VK_DRIVER_FILES": self.path("none.json")}
        result = subprocess.run([RTSDF, "sdf", SAMPLE, "--out", self.path("x.vdb")], capture_output=True,
                                text=True, env=env)
        self.assert_one_line_error(result, "Vulkan")


if __name__ == "__main__":
    unittest.main()
