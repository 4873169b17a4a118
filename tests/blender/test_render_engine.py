"""Run inside Blender with the staged add-on (see tests/CMakeLists.txt):
the RTSDF engine renders the sample scene close to Cycles, writes its passes,
renders animations, and reports bad scenes instead of failing.

BLENDER_USER_SCRIPTS=build/blender_user_scripts blender -b --factory-startup \
    --python-exit-code 1 --python tests/blender/test_render_engine.py -- build/samples/sphere_plane.blend [-k PATTERN]
"""
import os
import sys
import tempfile
import unittest

import addon_utils
import bpy
import numpy as np
from mathutils import Vector

SAMPLE = sys.argv[sys.argv.index("--") + 1]
LIGHTS = os.path.join(os.path.dirname(SAMPLE), "lights.blend")
# Stated tolerance: RMSE of the whole image against Cycles (direct light, no
# denoiser) at half resolution. Measured about 0.02 at full resolution.
RMSE_TOLERANCE = 0.04


def render(engine, directory, name, **settings):
    scene = bpy.context.scene
    scene.render.engine = engine
    scene.render.resolution_percentage = 50
    for key, value in settings.items():
        setattr(scene.rtsdf, key, value)
    bpy.ops.render.render()
    scene.render.image_settings.file_format = "OPEN_EXR"
    path = os.path.join(directory, name + ".exr")
    bpy.data.images["Render Result"].save_render(path)
    image = bpy.data.images.load(path)
    pixels = np.array(image.pixels[:], dtype=np.float32).reshape(image.size[1], image.size[0], 4)
    return image, pixels


class RenderEngine(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        addon_utils.enable("rtsdf", default_set=True, handle_error=None)
        cls.tmp = tempfile.TemporaryDirectory()

    @classmethod
    def tearDownClass(cls):
        cls.tmp.cleanup()

    def setUp(self):
        bpy.ops.wm.open_mainfile(filepath=SAMPLE)

    def test_engine_is_registered_with_settings(self):
        self.assertIn("RTSDF", {e.bl_idname for e in bpy.types.RenderEngine.__subclasses__()})
        self.assertEqual(bpy.context.scene.rtsdf.coarse_resolution, 64)

    def test_compare_operator_shows_both_renders_and_their_figures(self):
        scene = bpy.context.scene
        scene.render.resolution_percentage = 25
        scene.rtsdf.samples = 4
        self.assertIn("FINISHED", bpy.ops.render.rtsdf_compare(cycles_samples=16))
        figures = scene["rtsdf_compare"]
        for name in ("rmse", "ssim", "shadow_rmse", "time_ratio"):
            self.assertIn(name, figures)
        self.assertLess(figures["rmse"], 2 * RMSE_TOLERANCE)  # (16 noisy Cycles samples at quarter size)
        self.assertGreater(figures["shadow_pixels"], 0)
        image = bpy.data.images["RTSDF vs Cycles"]
        width = scene.render.resolution_x * 25 // 100
        self.assertEqual(tuple(image.size), (3 * width, scene.render.resolution_y * 25 // 100))
        # The engine and the lights' shadow flags are as they were.
        self.assertNotEqual(scene.render.engine, "CYCLES")
        self.assertTrue(all(light.cycles.cast_shadow for light in bpy.data.lights))

    def test_sample_scene_close_to_cycles_with_passes(self):
        bpy.context.view_layer.use_pass_z = True
        image, rtsdf = render("RTSDF", self.tmp.name, "rtsdf_", samples=8)
        _, cycles = render("CYCLES", self.tmp.name, "cycles_")
        self.assertEqual(rtsdf.shape, cycles.shape)
        rmse = float(np.sqrt(np.mean((rtsdf[..., :3] - cycles[..., :3]) ** 2)))
        print(f"RTSDF against Cycles: RMSE {rmse:.4f} (tolerance {RMSE_TOLERANCE})")
        self.assertLess(rmse, RMSE_TOLERANCE)
        # The shadows are there: some of the ground is much darker than the lit ground.
        luminance = rtsdf[..., :3].mean(axis=-1)
        self.assertGreater(np.percentile(luminance, 99) - np.percentile(luminance, 5), 0.4)

    def test_geometry_nodes_instances_share_one_mesh_and_render_as_in_cycles(self):
        """A modifier instancing a generated sphere on a 3x3 grid of points:
        every instance carries the name of the object holding the modifier,
        and each must still render, all sharing one mesh."""
        import rtsdf
        bpy.ops.mesh.primitive_plane_add(size=0.1, location=(0.0, 0.0, 1.2))
        spawner = bpy.context.object
        tree = bpy.data.node_groups.new("Spheres on a grid", "GeometryNodeTree")
        tree.outputs.new("NodeSocketGeometry", "Geometry")
        spawner.modifiers.new("Spheres", "NODES").node_group = tree
        grid = tree.nodes.new("GeometryNodeMeshGrid")
        for name, value in (("Size X", 2.4), ("Size Y", 2.4), ("Vertices X", 3), ("Vertices Y", 3)):
            grid.inputs[name].default_value = value
        sphere = tree.nodes.new("GeometryNodeMeshIcoSphere")
        sphere.inputs["Radius"].default_value = 0.25
        sphere.inputs["Subdivisions"].default_value = 3
        on_points = tree.nodes.new("GeometryNodeInstanceOnPoints")
        tree.links.new(grid.outputs["Mesh"], on_points.inputs["Points"])
        tree.links.new(sphere.outputs["Mesh"], on_points.inputs["Instance"])
        tree.links.new(on_points.outputs["Instances"], tree.nodes.new("NodeGroupOutput").inputs[0])

        data = rtsdf.sync.extract(bpy.context.evaluated_depsgraph_get())
        owners = [data["meshes"][i["mesh"]]["owner"] for i in data["instances"]]
        spheres = {i["mesh"] for i in data["instances"] if data["meshes"][i["mesh"]]["owner"] == spawner.name}
        self.assertEqual(owners.count(spawner.name), 9)
        self.assertEqual(len(spheres), 1, "the nine instances share one mesh")

        _, rtsdf_image = render("RTSDF", self.tmp.name, "gn_rtsdf", samples=8)
        _, cycles = render("CYCLES", self.tmp.name, "gn_cycles")
        rmse = float(np.sqrt(np.mean((rtsdf_image[..., :3] - cycles[..., :3]) ** 2)))
        spawner.hide_render = True
        _, without = render("RTSDF", self.tmp.name, "gn_without", samples=8)
        print(f"Geometry Nodes instances, RTSDF against Cycles: RMSE {rmse:.4f}")
        self.assertLess(rmse, RMSE_TOLERANCE)
        self.assertGreater(np.abs(rtsdf_image - without).max(), 0.2, "the instances show")

    def test_a_particle_emitter_shows_only_where_set_as_in_cycles(self):
        """Particles instancing a small cube from a plane over the sphere; the
        plane itself shows only with Show Emitter (instance.show_self)."""
        from rtsdf import sync
        bpy.ops.mesh.primitive_plane_add(size=1.6, location=(0.0, 0.0, 1.7))
        emitter = bpy.context.object
        bpy.ops.mesh.primitive_cube_add(size=0.2, location=(0.0, 0.0, -30.0))  # (out of view: its copies show)
        cube = bpy.context.object
        emitter.modifiers.new("Particles", "PARTICLE_SYSTEM")
        particles = emitter.particle_systems[0].settings
        particles.count, particles.frame_start, particles.frame_end = 16, 1, 1
        particles.physics_type, particles.render_type, particles.instance_object = "NO", "OBJECT", cube
        particles.particle_size = 1.0
        bpy.context.scene.frame_set(1)

        def owners():
            data = sync.extract(bpy.context.evaluated_depsgraph_get())
            return [data["meshes"][i["mesh"]]["owner"] for i in data["instances"]]
        # (the context's depsgraph is the viewport's; F12's reads the render flag)
        emitter.show_instancer_for_viewport = emitter.show_instancer_for_render = True
        self.assertIn(emitter.name, owners())
        emitter.show_instancer_for_viewport = emitter.show_instancer_for_render = False
        shown = owners()
        self.assertNotIn(emitter.name, shown)
        self.assertEqual(shown.count(cube.name), 1 + 16, "the cube and its 16 copies")

        _, rtsdf_image = render("RTSDF", self.tmp.name, "particles_rtsdf", samples=8)
        _, cycles = render("CYCLES", self.tmp.name, "particles_cycles")
        rmse = float(np.sqrt(np.mean((rtsdf_image[..., :3] - cycles[..., :3]) ** 2)))
        print(f"particles without their emitter, RTSDF against Cycles: RMSE {rmse:.4f}")
        self.assertLess(rmse, RMSE_TOLERANCE)

    def test_lights_with_their_shadow_off_cast_none_as_in_cycles(self):
        _, shadowed = render("RTSDF", self.tmp.name, "shadow_on", samples=4)
        for light in bpy.data.lights:
            light.cycles.cast_shadow = False  # (use_shadow in Blender 4.x)
        _, rtsdf_image = render("RTSDF", self.tmp.name, "shadow_off", samples=4)
        _, cycles = render("CYCLES", self.tmp.name, "shadow_off_cycles")
        rmse = float(np.sqrt(np.mean((rtsdf_image[..., :3] - cycles[..., :3]) ** 2)))
        print(f"lights' shadows off, RTSDF against Cycles: RMSE {rmse:.4f}")
        self.assertLess(rmse, RMSE_TOLERANCE)
        self.assertGreater((rtsdf_image - shadowed)[..., :3].max(), 0.2, "where the shadows were is lit now")

    def test_objects_hidden_from_the_camera_still_cast_shadows_as_in_cycles(self):
        _, seen = render("RTSDF", self.tmp.name, "camera_on", samples=4)
        bpy.data.objects["Sphere"].visible_camera = False  # (Ray Visibility > Camera)
        _, rtsdf_image = render("RTSDF", self.tmp.name, "camera_off", samples=4)
        _, cycles = render("CYCLES", self.tmp.name, "camera_off_cycles")
        rmse = float(np.sqrt(np.mean((rtsdf_image[..., :3] - cycles[..., :3]) ** 2)))
        print(f"sphere hidden from the camera, RTSDF against Cycles: RMSE {rmse:.4f}")
        self.assertLess(rmse, RMSE_TOLERANCE)
        self.assertGreater(np.abs(rtsdf_image - seen)[..., :3].max(), 0.2, "the sphere is gone from the image")

    def test_holdout_objects_are_transparent_holes_as_in_cycles(self):
        bpy.context.scene.render.film_transparent = True
        _, plain = render("RTSDF", self.tmp.name, "no_holdout", samples=4)
        bpy.data.objects["Sphere"].is_holdout = True
        _, rtsdf_image = render("RTSDF", self.tmp.name, "holdout", samples=4)
        _, cycles = render("CYCLES", self.tmp.name, "holdout_cycles")
        alpha = float(np.mean(np.abs(rtsdf_image[..., 3] - cycles[..., 3])))
        covered = cycles[..., 3] > 0.5
        rmse = float(np.sqrt(np.mean((rtsdf_image[..., :3][covered] - cycles[..., :3][covered]) ** 2)))
        hole = float(np.mean(rtsdf_image[..., 3] < 0.5) - np.mean(plain[..., 3] < 0.5))
        print(f"holdout sphere, RTSDF against Cycles: alpha difference {alpha:.4f}, RMSE where covered {rmse:.4f}; "
              f"the hole is {hole:.1%} of the image")
        self.assertLess(alpha, 0.02)
        self.assertLess(rmse, RMSE_TOLERANCE)
        self.assertGreater(hole, 0.01, "the sphere's pixels are a hole")

    def test_render_region_renders_the_region_as_cycles_does(self):
        from bpy_extras.object_utils import world_to_camera_view
        scene = bpy.context.scene
        at = world_to_camera_view(scene, scene.camera, bpy.data.objects["Sphere"].matrix_world.translation)
        scene.render.use_border = True
        scene.render.border_min_x, scene.render.border_max_x = max(at.x - 0.2, 0.0), min(at.x + 0.15, 1.0)
        scene.render.border_min_y, scene.render.border_max_y = max(at.y - 0.25, 0.0), min(at.y + 0.2, 1.0)
        for crop in (False, True):
            with self.subTest(crop=crop):
                scene.render.use_crop_to_border = crop
                _, rtsdf_image = render("RTSDF", self.tmp.name, f"region_{crop}", samples=4)
                _, cycles = render("CYCLES", self.tmp.name, f"region_{crop}_cycles")
                self.assertEqual(rtsdf_image.shape, cycles.shape)
                rmse = float(np.sqrt(np.mean((rtsdf_image[..., :3] - cycles[..., :3]) ** 2)))
                print(f"render region (cropped: {crop}), RTSDF against Cycles: RMSE {rmse:.4f}")
                self.assertLess(rmse, RMSE_TOLERANCE)

    def test_a_panoramic_camera_is_reported(self):
        scene = bpy.context.scene
        scene.camera.data.type = "PANO"
        scene.render.engine = "RTSDF"
        scene.render.resolution_percentage = 10
        self.assertIn("Panoramic cameras are not supported", self.assert_reports_error())

    def test_smooth_and_flat_faces_mixed_shade_as_in_cycles(self):
        # A coarse sphere (12 x 6 faces, so flat faces show), its lower half flat and its
        # upper half smooth: Cycles shades each face as marked.
        import bmesh
        from bpy_extras.object_utils import world_to_camera_view
        scene = bpy.context.scene
        sphere = bpy.data.objects["Sphere"]
        coarse = bmesh.new()
        radius = max(vertex.co.length for vertex in sphere.data.vertices)
        bmesh.ops.create_uvsphere(coarse, u_segments=12, v_segments=6, radius=radius)
        sphere.data = bpy.data.meshes.new("coarse sphere")
        coarse.to_mesh(sphere.data)
        coarse.free()
        for polygon in sphere.data.polygons:
            polygon.use_smooth = polygon.center.z > 0.0
        _, mixed = render("RTSDF", self.tmp.name, "mixed", samples=4)
        _, cycles = render("CYCLES", self.tmp.name, "mixed_cycles")
        for polygon in sphere.data.polygons:
            polygon.use_smooth = False
        _, flat = render("RTSDF", self.tmp.name, "all_flat", samples=4)
        # Over the sphere's box on screen (rows from the bottom, as Blender stores them).
        corners = [world_to_camera_view(scene, scene.camera, sphere.matrix_world @ Vector(c)) for c in sphere.bound_box]
        height, width = mixed.shape[:2]
        x0, x1 = int(min(c.x for c in corners) * width), int(np.ceil(max(c.x for c in corners) * width))
        y0, y1 = int(min(c.y for c in corners) * height), int(np.ceil(max(c.y for c in corners) * height))

        def box_rmse(image):
            return float(np.sqrt(np.mean((image[y0:y1, x0:x1, :3] - cycles[y0:y1, x0:x1, :3]) ** 2)))

        print(f"smooth and flat faces mixed, RTSDF against Cycles over the sphere: RMSE {box_rmse(mixed):.4f} "
              f"(all flat: {box_rmse(flat):.4f})")
        self.assertLess(box_rmse(mixed), RMSE_TOLERANCE)
        self.assertLess(box_rmse(mixed), 0.8 * box_rmse(flat), "the smooth half shades smooth")

    def test_material_slots_and_an_image_texture_shade_as_in_cycles(self):
        # The ground cut into 4 x 4 faces that alternate between a red and a blue
        # slot, and the sphere's Diffuse colour from an Image Texture (Blender's
        # colour grid) by its UVs, behind a Mix Shader.
        import bmesh
        ground, sphere = bpy.data.objects["Ground"], bpy.data.objects["Sphere"]
        grid = bmesh.new()
        grid.from_mesh(ground.data)
        bmesh.ops.subdivide_edges(grid, edges=grid.edges[:], cuts=3, use_grid_fill=True)
        grid.to_mesh(ground.data)
        grid.free()
        ground.data.materials.clear()
        for name, color in (("Red", (0.8, 0.1, 0.1)), ("Blue", (0.1, 0.2, 0.8))):
            material = bpy.data.materials["Ground"].copy()
            material.name = name
            material.node_tree.nodes["Diffuse BSDF"].inputs["Color"].default_value = (*color, 1.0)
            ground.data.materials.append(material)
        for polygon in ground.data.polygons:
            polygon.material_index = (int(polygon.center.x // 2) + int(polygon.center.y // 2)) % 2
        image = bpy.data.images.new("grid", 256, 256)
        image.generated_type = "COLOR_GRID"
        tree = sphere.active_material.node_tree
        texture = tree.nodes.new("ShaderNodeTexImage")
        texture.image = image
        tree.links.new(texture.outputs["Color"], tree.nodes["Diffuse BSDF"].inputs["Color"])
        mix = tree.nodes.new("ShaderNodeMixShader")
        mix.inputs["Fac"].default_value = 0.0
        tree.links.new(tree.nodes["Diffuse BSDF"].outputs["BSDF"], mix.inputs[1])
        tree.links.new(mix.outputs["Shader"], tree.nodes["Material Output"].inputs["Surface"])

        _, rtsdf_image = render("RTSDF", self.tmp.name, "materials", samples=4)
        _, cycles = render("CYCLES", self.tmp.name, "materials_cycles")
        rmse = float(np.sqrt(np.mean((rtsdf_image[..., :3] - cycles[..., :3]) ** 2)))
        print(f"material slots and an image texture, RTSDF against Cycles: RMSE {rmse:.4f}")
        self.assertLess(rmse, RMSE_TOLERANCE)
        red = (rtsdf_image[..., 0] > 2 * rtsdf_image[..., 2]).mean()
        blue = (rtsdf_image[..., 2] > 2 * rtsdf_image[..., 0]).mean()
        self.assertGreater(min(red, blue), 0.1, "both slots of the ground show")
        # The grid's cells differ in hue: its green ones show on the sphere, in both.
        green = [int((image[..., 1] > 2 * image[..., 0] + 0.05).sum()) for image in (rtsdf_image, cycles)]
        print(f"green pixels: RTSDF {green[0]}, Cycles {green[1]}")
        self.assertGreater(min(green), 50)

    def test_colour_attributes_shade_as_in_cycles(self):
        # The ground's Diffuse colour from a Color Attribute node (the render
        # default: a byte colour per face corner, red to green across x), the
        # sphere's from an Attribute node naming a float colour per vertex
        # (blue below, yellow above).
        from rtsdf import sync
        ground, sphere = bpy.data.objects["Ground"], bpy.data.objects["Sphere"]
        corners = ground.data.color_attributes.new("Paint", "BYTE_COLOR", "CORNER")
        ground.data.color_attributes.render_color_index = ground.data.color_attributes.find("Paint")
        extent = max(abs(v.co.x) for v in ground.data.vertices)
        for loop in ground.data.loops:
            t = 0.5 + 0.5 * ground.data.vertices[loop.vertex_index].co.x / extent
            corners.data[loop.index].color = (1.0 - t, t, 0.1, 1.0)
        points = sphere.data.color_attributes.new("Height", "FLOAT_COLOR", "POINT")
        for vertex in sphere.data.vertices:
            t = 0.5 + vertex.co.z
            points.data[vertex.index].color = (t, t, 1.0 - t, 1.0)
        for obj, node_type, name in ((ground, "ShaderNodeVertexColor", None), (sphere, "ShaderNodeAttribute", "Height")):
            tree = obj.active_material.node_tree
            node = tree.nodes.new(node_type)
            if name is not None:
                node.attribute_name = name
            tree.links.new(node.outputs["Color"], tree.nodes["Diffuse BSDF"].inputs["Color"])

        meshes, instances, _ = sync.geometry(bpy.context.evaluated_depsgraph_get())
        self.assertTrue(all("colors" in m for m in meshes if m["key"] in ("Ground", "Sphere")))
        _, rtsdf_image = render("RTSDF", self.tmp.name, "attributes", samples=4)
        _, cycles = render("CYCLES", self.tmp.name, "attributes_cycles")
        rmse = float(np.sqrt(np.mean((rtsdf_image[..., :3] - cycles[..., :3]) ** 2)))
        print(f"colour attributes, RTSDF against Cycles: RMSE {rmse:.4f}")
        self.assertLess(rmse, RMSE_TOLERANCE)
        for image in (rtsdf_image, cycles):
            red = (image[..., 0] > 2 * image[..., 1] + 0.02).mean()
            green = (image[..., 1] > 2 * image[..., 0] + 0.02).mean()
            self.assertGreater(min(red, green), 0.05, "both ends of the ground's gradient show")

        # A material reading an attribute the mesh lacks: noted, its socket's colour stands in.
        sphere.active_material.node_tree.nodes["Attribute"].attribute_name = "Missing"
        warnings = []
        _, instances, _ = sync.geometry(bpy.context.evaluated_depsgraph_get(), warnings=warnings)
        self.assertTrue(any("'Missing'" in w for w in warnings), warnings)

    def test_a_missing_image_and_a_material_without_a_bsdf_are_reported(self):
        from rtsdf import sync
        tree = bpy.data.materials["Sphere"].node_tree
        texture = tree.nodes.new("ShaderNodeTexImage")
        texture.image = bpy.data.images.new("wood", 4, 4)  # (then pointed at a file that is not there)
        texture.image.source = "FILE"
        texture.image.filepath = "/nonexistent/wood.png"
        texture.image.reload()
        tree.links.new(texture.outputs["Color"], tree.nodes["Diffuse BSDF"].inputs["Color"])
        box = bpy.data.materials["Box"]
        box.node_tree.nodes.remove(box.node_tree.nodes["Diffuse BSDF"])
        box.diffuse_color = (0.0, 1.0, 0.0, 1.0)
        warnings = []
        _, instances, textures = sync.geometry(bpy.context.evaluated_depsgraph_get(), warnings=warnings)
        self.assertEqual(textures, [])
        self.assertTrue(any("wood.png" in w for w in warnings), warnings)
        self.assertTrue(any("'Box' has no BSDF" in w for w in warnings), warnings)
        colors = {tuple(np.round(i["color"], 3)) for i in instances}
        self.assertIn((0.0, 1.0, 0.0), colors, "the viewport colour stands in")
        _, image = render("RTSDF", self.tmp.name, "missing_image", samples=2)
        self.assertGreater(image[..., :3].max(), 0.1, "and the render goes on")

    def test_an_environment_texture_lights_as_its_mean_and_a_sky_is_reported(self):
        from rtsdf import sync
        scene = bpy.context.scene
        world = scene.world
        world.use_nodes = True
        tree = world.node_tree
        background = next(node for node in tree.nodes if node.type == "BACKGROUND")
        background.inputs["Strength"].default_value = 2.0
        # The upper half of the sphere of directions white, the lower black: a mean of one half.
        image = bpy.data.images.new("environment", 64, 32, float_buffer=True)
        pixels = np.zeros((32, 64, 4), np.float32)
        pixels[16:] = 1.0
        pixels[..., 3] = 1.0
        image.pixels.foreach_set(pixels.ravel())
        texture = tree.nodes.new("ShaderNodeTexEnvironment")
        texture.image = image
        tree.links.new(texture.outputs["Color"], background.inputs["Color"])
        np.testing.assert_allclose(sync.world_color(scene), (1.0, 1.0, 1.0), atol=1e-3)
        # A uniform image lights as its colour does, in Cycles too.
        pixels[..., :3] = 0.15
        image.pixels.foreach_set(pixels.ravel())
        image.update()
        _, rtsdf_image = render("RTSDF", self.tmp.name, "environment", samples=4)
        _, cycles = render("CYCLES", self.tmp.name, "environment_cycles")
        rmse = float(np.sqrt(np.mean((rtsdf_image[..., :3] - cycles[..., :3]) ** 2)))
        print(f"uniform environment texture, RTSDF against Cycles: RMSE {rmse:.4f}")
        self.assertLess(rmse, RMSE_TOLERANCE)
        sky = tree.nodes.new("ShaderNodeTexSky")
        tree.links.new(sky.outputs["Color"], background.inputs["Color"])
        warnings = []
        self.assertEqual(sync.world_color(scene, warnings), tuple(2.0 * c for c in world.color))
        self.assertIn("Sky Texture", warnings[0])

    def test_f12_shows_the_image_so_far(self):
        from rtsdf import engine, native, sync
        scene = bpy.context.scene
        scene.render.resolution_percentage = 25
        session, _ = native.session()
        data = sync.extract(bpy.context.evaluated_depsgraph_get())
        previews = []

        def progress(done, total, preview):
            previews.append(preview())
            return True

        out = session.render(data, dict(scene.rtsdf.as_dict(), samples=4), progress)
        self.assertEqual(len(previews), 4)
        self.assertEqual(previews[0].shape, out["combined"].shape)
        np.testing.assert_allclose(previews[-1], out["combined"], atol=1e-6)
        self.assertGreater(np.abs(previews[0] - previews[-1]).max(), 0.0, "the first preview holds one sample")
        # The engine shows them (here after every sample) and still ends with the whole render.
        engine.PREVIEW_SECONDS = 0.0
        try:
            _, shown = render("RTSDF", self.tmp.name, "progressive", samples=4)
        finally:
            engine.PREVIEW_SECONDS = 1.0
        _, whole = render("RTSDF", self.tmp.name, "whole", samples=4)
        self.assertLess(float(np.abs(shown - whole).max()), 1e-4)

    def test_point_spot_and_area_lights_close_to_cycles(self):
        # Light units, falloff, spot cone and area cosine as Cycles has them
        # (measured about 0.06 at full resolution and 256 Cycles samples).
        bpy.ops.wm.open_mainfile(filepath=LIGHTS)
        bpy.context.scene.cycles.samples = 64
        _, rtsdf = render("RTSDF", self.tmp.name, "lights_rtsdf", samples=4)
        _, cycles = render("CYCLES", self.tmp.name, "lights_cycles")
        rmse = float(np.sqrt(np.mean((rtsdf[..., :3] - cycles[..., :3]) ** 2)))
        print(f"lights scene, RTSDF against Cycles: RMSE {rmse:.4f}")
        self.assertLess(rmse, 0.1)

    def test_passes_in_the_render_result(self):
        bpy.context.view_layer.use_pass_z = True
        scene = bpy.context.scene
        scene.render.engine = "RTSDF"
        scene.render.resolution_percentage = 25
        scene.rtsdf.samples = 2
        bpy.ops.render.render()
        path = os.path.join(self.tmp.name, "passes.exr")
        scene.render.image_settings.file_format = "OPEN_EXR_MULTILAYER"
        bpy.data.images["Render Result"].save_render(path)
        header = open(path, "rb").read(4096)
        for name in (b"Combined", b"Depth", b"Shadow"):
            self.assertIn(name, header)

    def test_three_frame_animation(self):
        scene = bpy.context.scene
        sphere = bpy.data.objects["Sphere"]
        for frame, x in ((1, -1.0), (3, 0.5)):
            sphere.location.x = x
            sphere.keyframe_insert("location", frame=frame)
        scene.frame_start, scene.frame_end = 1, 3
        scene.render.engine = "RTSDF"
        scene.render.resolution_percentage = 20
        scene.render.use_persistent_data = True
        scene.rtsdf.samples = 2
        scene.render.image_settings.file_format = "PNG"
        scene.render.filepath = os.path.join(self.tmp.name, "anim_")
        bpy.ops.render.render(animation=True)
        frames = [os.path.join(self.tmp.name, f"anim_{f:04d}.png") for f in (1, 2, 3)]
        for path in frames:
            self.assertTrue(os.path.exists(path), path)
        first, last = (np.array(bpy.data.images.load(p).pixels[:]) for p in (frames[0], frames[2]))
        self.assertGreater(np.abs(first - last).max(), 0.1, "the moving sphere changes the image")

    def test_animation_reuse_between_frames_is_closer_to_full_frames_where_nothing_moves(self):
        """Reuse Between Frames: 2 samples a frame plus the earlier frames'
        come closer to rendering every frame with all 16 samples than 2
        samples a frame alone where nothing moves (where the sphere and its
        shadow pass, history is clipped or dropped and the frame has about its
        own samples), and the frames after the first keep their scene."""
        import time
        scene = bpy.context.scene
        sphere = bpy.data.objects["Sphere"]
        for frame, x in ((1, sphere.location.x - 0.2), (8, sphere.location.x + 0.2)):
            sphere.location.x = x
            sphere.keyframe_insert("location", frame=frame)
        scene.frame_start, scene.frame_end = 1, 8
        scene.render.engine = "RTSDF"
        scene.render.resolution_percentage = 20
        scene.render.image_settings.file_format = "OPEN_EXR"
        scene.rtsdf.animation_samples = 2

        def animation(name, reuse, samples):
            scene.render.use_persistent_data = False
            bpy.ops.render.render(write_still=False)  # (drops the scene kept from before: no history at frame 1)
            scene.render.use_persistent_data = True
            scene.rtsdf.animation_reuse = reuse
            scene.rtsdf.samples = samples
            scene.render.filepath = os.path.join(self.tmp.name, name + "_")
            started = time.perf_counter()
            bpy.ops.render.render(animation=True)
            seconds = time.perf_counter() - started
            frames = []
            for f in range(1, 9):
                image = bpy.data.images.load(os.path.join(self.tmp.name, f"{name}_{f:04d}.exr"))
                frames.append(np.array(image.pixels[:], np.float32).reshape(image.size[1], image.size[0], 4)[..., :3])
            return np.array(frames), seconds

        full, full_s = animation("full", False, 16)
        reused, reused_s = animation("reused", True, 16)
        few, few_s = animation("few", False, 2)
        still = np.abs(np.diff(full, axis=0)).max(axis=(0, 3)) < 0.02  # (pixels no frame changes)

        def rmse(frames, where):  # over the frames after the first, which carry history when reusing
            return float(np.sqrt(np.mean((frames[1:] - full[1:])[:, where] ** 2)))

        print(f"animation, 8 frames at {full.shape[2]}x{full.shape[1]}: 16 samples {full_s:.1f} s; 2 samples and "
              f"reuse {reused_s:.1f} s, RMSE from the full frames {rmse(reused, still):.4f} where nothing moves "
              f"({still.mean():.0%} of the pixels), {rmse(reused, ~still):.4f} elsewhere; 2 samples {few_s:.1f} s, "
              f"{rmse(few, still):.4f} and {rmse(few, ~still):.4f}")
        self.assertGreater(still.mean(), 0.5)
        self.assertLess(rmse(reused, still), 0.85 * rmse(few, still))

    def test_persistent_data_keeps_the_scene_where_its_structure_stays(self):
        import rtsdf
        session, error = rtsdf.native.session()
        self.assertIsNone(error)
        depsgraph = bpy.context.evaluated_depsgraph_get()
        bpy.context.scene.render.resolution_percentage = 10
        data = rtsdf.sync.extract(depsgraph)
        settings = {"samples": 1}
        session.render(data, settings, None, False)  # (drops a scene an earlier render kept)
        self.assertFalse(session.render(data, settings, None, True)["scene_reused"])
        self.assertTrue(session.render(data, settings, None, True)["scene_reused"])
        data["instances"][0]["matrix"] = data["instances"][0]["matrix"].copy()
        data["instances"][0]["matrix"][0, 3] += 0.5  # a rigid move
        self.assertTrue(session.render(data, settings, None, True)["scene_reused"])
        # Smooth normals evaluated again (Blender's differ in their last bits from frame to frame): no new shape.
        smooth = next(m for m in data["meshes"] if "normals" in m)
        smooth["normals"] = smooth["normals"] * np.float32(1.0 + 1e-6)
        self.assertTrue(session.render(data, settings, None, True)["scene_reused"])
        data["meshes"][0]["positions"] = data["meshes"][0]["positions"] * 1.1  # a deformation: that mesh in place
        self.assertTrue(session.render(data, settings, None, True)["scene_reused"])
        data["instances"][0]["casts_shadow"] = not data["instances"][0].get("casts_shadow", True)  # another structure
        self.assertFalse(session.render(data, settings, None, True)["scene_reused"])
        self.assertFalse(session.render(data, settings, None, False)["scene_reused"])

    def test_fields_kept_on_disk_are_taken_by_a_later_render(self):
        import rtsdf
        session, error = rtsdf.native.session()
        self.assertIsNone(error)
        preferences = bpy.context.preferences.addons["rtsdf"].preferences
        directory = os.path.join(self.tmp.name, "fields")
        forced = os.environ.pop("RTSDF_FIELD_STORE", None)  # (the tests' environment turns the store off)
        try:
            preferences.keep_fields_on_disk = True
            preferences.field_store_directory = directory
            bpy.context.scene.render.engine = "RTSDF"
            bpy.context.scene.render.resolution_percentage = 10
            bpy.context.scene.rtsdf.fine_resolution = 64
            session.forget_fields()
            bpy.ops.render.render()
            self.assertEqual(session.field_store["directory"], directory)
            self.assertGreater(session.field_store["saved"], 0)
            files, megabytes = rtsdf.native.field_store_usage(directory)
            self.assertEqual(files, session.field_store["files"])
            self.assertGreater(megabytes, 0.0)
            session.forget_fields()  # (as a Blender started afresh has none in memory)
            bpy.ops.render.render()
            self.assertEqual(session.field_store["loaded"], files, "every field taken from disk")

            self.assertEqual(bpy.ops.rtsdf.clear_field_store(), {"FINISHED"})
            self.assertEqual(rtsdf.native.field_store_usage(directory)[0], 0)
            # A directory that cannot be made: a warning, and the render goes on with fields in memory.
            blocker = os.path.join(self.tmp.name, "a_file")
            open(blocker, "w").close()
            preferences.field_store_directory = os.path.join(blocker, "fields")
            bpy.ops.render.render()
            self.assertIsNone(session.field_store)
            preferences.keep_fields_on_disk = False
            bpy.ops.render.render()
            self.assertIsNone(session.field_store)
        finally:
            preferences.keep_fields_on_disk = True
            preferences.field_store_directory = ""
            if forced is not None:
                os.environ["RTSDF_FIELD_STORE"] = forced

    def assert_reports_error(self):
        # Blender turns an ERROR report from the engine into a failed operator.
        with self.assertRaises(RuntimeError) as caught:
            bpy.ops.render.render()
        return str(caught.exception)

    def test_empty_scene_is_reported(self):
        scene = bpy.context.scene
        for obj in list(scene.objects):
            if obj.type != "CAMERA":
                bpy.data.objects.remove(obj)
        scene.render.engine = "RTSDF"
        self.assertIn("no objects with faces", self.assert_reports_error())

    def test_mesh_without_faces_and_nan_vertices_are_reported(self):
        scene = bpy.context.scene
        scene.render.engine = "RTSDF"
        scene.render.resolution_percentage = 10
        scene.rtsdf.samples = 1
        points = bpy.data.meshes.new("points")
        points.from_pydata([(0, 0, 0), (1, 0, 0)], [(0, 1)], [])
        scene.collection.objects.link(bpy.data.objects.new("Points", points))
        bpy.ops.render.render()  # an edge-only object is skipped; the rest renders
        bad = bpy.data.meshes.new("bad")
        bad.from_pydata([(0, 0, 0), (1, 0, 0), (0, float("nan"), 0)], [], [(0, 1, 2)])
        scene.collection.objects.link(bpy.data.objects.new("Bad", bad))
        self.assertIn("NaN", self.assert_reports_error())

    def test_points_only_geometry_flat_instances_and_negative_lights_are_reported(self):
        """Each is left out with a warning, and the rest still renders."""
        from rtsdf import sync
        scene = bpy.context.scene
        scene.render.engine = "RTSDF"
        scene.render.resolution_percentage = 10
        scene.rtsdf.samples = 1
        # Geometry Nodes trees that output only points, or only curves.
        for name, node_type, output in (("Cloud", "GeometryNodeMeshToPoints", "Points"),
                                        ("Wire", "GeometryNodeMeshToCurve", "Curve")):
            bpy.ops.mesh.primitive_plane_add(size=1.0, location=(1.5, 0.0, 1.0))
            bpy.context.object.name = name
            tree = bpy.data.node_groups.new(name, "GeometryNodeTree")
            tree.inputs.new("NodeSocketGeometry", "Geometry")
            tree.outputs.new("NodeSocketGeometry", "Geometry")
            bpy.context.object.modifiers.new(name, "NODES").node_group = tree
            convert = tree.nodes.new(node_type)
            tree.links.new(tree.nodes.new("NodeGroupInput").outputs[0], convert.inputs["Mesh"])
            tree.links.new(convert.outputs[output], tree.nodes.new("NodeGroupOutput").inputs[0])
        # An object scaled flat, and a light of negative power.
        bpy.ops.mesh.primitive_cube_add(size=0.5, location=(-1.5, 0.0, 1.0))
        bpy.context.object.name = "Flat"
        bpy.context.object.scale = (1.0, 0.0, 1.0)
        light = bpy.data.lights.new("Negative", "POINT")
        light.energy = -100.0
        scene.collection.objects.link(bpy.data.objects.new("Negative", light))

        data = sync.extract(bpy.context.evaluated_depsgraph_get())
        warnings = " | ".join(data["warnings"])
        for name in ("Cloud", "Wire", "Flat", "Negative"):
            self.assertIn(f"'{name}'", warnings)
        self.assertEqual(len(data["lights"]), len([o for o in scene.objects if o.type == "LIGHT"]) - 1)
        bpy.ops.render.render()  # (warnings, no error: the rest renders)

    def test_no_camera_is_reported(self):
        scene = bpy.context.scene
        scene.render.engine = "RTSDF"
        scene.camera = None
        for obj in list(scene.objects):
            if obj.type == "CAMERA":
                bpy.data.objects.remove(obj)
        self.assertIn("camera", self.assert_reports_error())


# (after the sample, unittest's own arguments: -k PATTERN runs the matching tests only)
result = unittest.main(argv=["blender"] + sys.argv[sys.argv.index("--") + 2:], exit=False, verbosity=2).result
sys.exit(0 if result.wasSuccessful() else 1)
