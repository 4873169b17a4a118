"""Drives RTSDF's viewport in a real Blender window (under Xvfb): Rendered
shading of a .blend through its camera, screenshots of the 3D view compared
with Cycles, an object moved from Python, and frame changes (memory, and
the time of a frame change plus redraw against EEVEE's in the same run).

xvfb-run -a -s "-screen 0 1280x800x24" blender --window-geometry 0 0 1200 760 --addons rtsdf \
    SCENE.blend --python tests/blender/viewport_driver.py -- OUT_DIR [--moving OBJECT] [--also-moving OBJECT,...]
    [--ground OBJECT] [--frames N] [--compare-eevee] [--scale S] [--pixel-size N] [--compare-full-first-frame] [--compare-no-temporal-reuse] [--field-views]

--also-moving names more objects animated in the frame changes, each along
a circle as the moving object, half a turn behind it (several objects
animated at once).
--ground names the receiver whose shadow masks are compared with Cycles'
(default Ground: the sample scenes' ground plane; a terrain, say, elsewhere).
--compare-full-first-frame times the frame changes again with Quick First
Frame off (every pixel marches its lights), after EEVEE's;
--compare-no-temporal-reuse with Temporal Reuse off (each frame change starts
from one sample). --scale sets RTSDF's Viewport Scale (the share of the region's width and
height it renders); --pixel-size sets Blender's viewport Pixel Size
(render.preview_pixel_size: 1, 2, 4 or 8), which the engines that honour it
(Cycles, EEVEE) use. Compare engines at the same pixel count.

--field-views only screenshots the viewport in each of RTSDF's field views
(OUT_DIR/field_view_NAME.png; the slice at the mean height of the scene's
objects other than the ground), and checks each differs from the shaded view.

Opening the .blend from the command line keeps the splash screen away. It
writes OUT_DIR/viewport.json with the figures and the screenshots as PNGs;
tests/blender/test_viewport.py checks them.
"""
import json
import math
import os
import sys
import time
import traceback

import bpy
import numpy as np
from bpy_extras.object_utils import world_to_camera_view
from bpy_extras.view3d_utils import location_3d_to_region_2d

args = sys.argv[sys.argv.index("--") + 1:]
OUT = args[0]
MOVING = args[args.index("--moving") + 1] if "--moving" in args else "Sphere"
ALSO_MOVING = args[args.index("--also-moving") + 1].split(",") if "--also-moving" in args else []
GROUND = args[args.index("--ground") + 1] if "--ground" in args else "Ground"
FRAMES = int(args[args.index("--frames") + 1]) if "--frames" in args else 100
COMPARE_EEVEE = "--compare-eevee" in args
SCALE = float(args[args.index("--scale") + 1]) if "--scale" in args else None
PIXEL_SIZE = args[args.index("--pixel-size") + 1] if "--pixel-size" in args else None
# Frame changes timed again with one viewport setting off: (flag, setting, result key).
COMPARE_SETTING_OFF = [(flag, setting, key) for flag, setting, key in (
    ("--compare-full-first-frame", "viewport_quick_first_frame", "full_first_frame_change_ms"),
    ("--compare-no-temporal-reuse", "viewport_temporal_reuse", "no_temporal_reuse_frame_change_ms")) if flag in args]
FIELD_VIEWS = "--field-views" in args
TIMEOUT = 120.0
os.makedirs(OUT, exist_ok=True)
results = {"errors": []}


def view3d():
    window = bpy.context.window_manager.windows[0]
    area = max((a for a in window.screen.areas if a.type == "VIEW_3D"), key=lambda a: a.width * a.height)
    region = next(r for r in area.regions if r.type == "WINDOW")
    return window, area, region, area.spaces.active


def rss_mib():
    with open("/proc/self/status") as f:
        for line in f:
            if line.startswith("VmRSS:"):
                return int(line.split()[1]) / 1024.0
    return 0.0


def read_png(path):
    image = bpy.data.images.load(path, check_existing=False)
    pixels = np.array(image.pixels[:], dtype=np.float32).reshape(image.size[1], image.size[0], 4)
    bpy.data.images.remove(image)
    return pixels[::-1, :, :3]  # rows top to bottom


def luminance(rgb):
    return rgb @ np.array([0.2126, 0.7152, 0.0722], dtype=np.float32)


def shadow_mask(rgb, ground):
    """Pixels much darker than the lit ground (its bright percentile)."""
    lum = luminance(rgb)
    lit = np.percentile(lum[ground], 90)
    return (lum < 0.6 * lit) & ground


def camera_frame_in_region(scene, region, rv3d):
    """The camera frame's corners as region pixels: (x0, y0, x1, y1), y up."""
    camera = scene.camera
    corners = [camera.matrix_world @ c for c in camera.data.view_frame(scene=scene)]
    points = [location_3d_to_region_2d(region, rv3d, c) for c in corners]
    xs, ys = [p.x for p in points], [p.y for p in points]
    return min(xs), min(ys), max(xs), max(ys)


def viewport_in_camera_pixels(shot, area, region, frame, width, height):
    """Resamples the screenshot (of the area) onto the camera's image grid."""
    x0, y0, x1, y1 = frame
    rows, cols = np.mgrid[0:height, 0:width]
    # Camera image pixel centres -> region pixels (y up) -> area screenshot rows.
    rx = x0 + (cols + 0.5) / width * (x1 - x0) + (region.x - area.x)
    ry = y1 - (rows + 0.5) / height * (y1 - y0) + (region.y - area.y)
    sy = np.clip((shot.shape[0] - 1 - ry).astype(int), 0, shot.shape[0] - 1)
    sx = np.clip(rx.astype(int), 0, shot.shape[1] - 1)
    return shot[sy, sx]


def ground_mask(scene, width, height):
    """Camera pixels whose ray meets the ground (GROUND) first, inside its square (the middle 98%)."""
    depsgraph = bpy.context.evaluated_depsgraph_get()
    camera = scene.camera
    frame = [camera.matrix_world @ c for c in camera.data.view_frame(scene=scene)]
    origin = camera.matrix_world.translation
    ground = bpy.data.objects[GROUND]
    half = max(ground.dimensions.x, ground.dimensions.y) / 2
    mask = np.zeros((height, width), dtype=bool)
    # view_frame: top right, bottom right, bottom left, top left.
    for row in range(0, height):
        for col in range(0, width):
            u, v = (col + 0.5) / width, (row + 0.5) / height
            top = frame[3].lerp(frame[0], u)
            bottom = frame[2].lerp(frame[1], u)
            direction = (top.lerp(bottom, v) - origin).normalized()
            hit, location, _, _, obj, _ = scene.ray_cast(depsgraph, origin, direction)
            mask[row, col] = hit and obj.name == GROUND and abs(location.x) < half * 0.98 and abs(location.y) < half * 0.98
    return mask


def render_cycles(scene, path, width, height):
    engine = scene.render.engine
    scene.render.engine = "CYCLES"
    scene.cycles.samples = 16
    scene.cycles.use_denoising = False
    scene.render.resolution_x, scene.render.resolution_y, scene.render.resolution_percentage = width, height, 100
    scene.render.image_settings.file_format = "PNG"
    scene.render.filepath = path
    bpy.ops.render.render(write_still=True)
    scene.render.engine = engine
    return read_png(path)


def steps():
    """A sequence of steps; each yield hands control back to Blender's event loop for that many seconds."""
    from rtsdf import engine as rtsdf_engine

    scene = bpy.context.scene
    if SCALE is not None:
        scene.rtsdf.viewport_scale = SCALE
    if PIXEL_SIZE is not None:
        scene.render.preview_pixel_size = PIXEL_SIZE
    results["rtsdf_viewport_scale"] = scene.rtsdf.viewport_scale
    results["preview_pixel_size"] = scene.render.preview_pixel_size
    width, height = 160, 90
    window, area, region, space = view3d()

    def wait_converged(since):
        start = time.perf_counter()
        while True:
            state = rtsdf_engine.last_view_draw
            if state.get("converged") and state.get("time", 0) > since:
                return
            if time.perf_counter() - start > TIMEOUT:
                raise RuntimeError(f"the viewport did not converge in {TIMEOUT} s: {state}")
            yield 0.2

    def screenshot(name):
        path = os.path.join(OUT, name)
        with bpy.context.temp_override(window=window, area=area):
            bpy.ops.screen.screenshot_area(filepath=path)
        return read_png(path)

    if FIELD_VIEWS:
        yield from field_views(scene, space, window, area, region, wait_converged, screenshot)
        return

    # Cycles through the scene camera: the reference shadows, before and after the move.
    ground = ground_mask(scene, width, height)
    cycles_before = render_cycles(scene, os.path.join(OUT, "cycles_before.png"), width, height)
    moving = bpy.data.objects[MOVING]
    start_location = moving.location.copy()
    moving.location.x += 0.8
    cycles_after = render_cycles(scene, os.path.join(OUT, "cycles_after.png"), width, height)
    moving.location = start_location

    show_rendered_through_camera(scene, space, window, area, region)
    rv3d = space.region_3d
    started = time.perf_counter()
    yield from wait_converged(started)
    frame = camera_frame_in_region(scene, region, rv3d)
    results["region"] = [region.width, region.height]
    results["first_image_s"] = time.perf_counter() - started

    def compare(shot, cycles, name):
        view = viewport_in_camera_pixels(shot, area, region, frame, width, height)
        mine, theirs = shadow_mask(view, ground), shadow_mask(cycles, ground)
        union = (mine | theirs).sum()
        results[name] = {"iou": float((mine & theirs).sum() / max(union, 1)), "rtsdf_pixels": int(mine.sum()),
                         "cycles_pixels": int(theirs.sum())}
        return mine

    before = compare(screenshot("viewport_before.png"), cycles_before, "before")

    # Moved from Python: the viewport follows (view_update, then new frames).
    moving.location.x += 0.8
    started = time.perf_counter()
    yield from wait_converged(started)
    results["converged_after_move_s"] = time.perf_counter() - started
    after = compare(screenshot("viewport_after.png"), cycles_after, "after")
    results["moved_shadow_iou"] = float((before & after).sum() / max((before | after).sum(), 1))
    moving.location = start_location

    # A light dimmed from Python: the viewport reads lights when the scene
    # changes, not at each redraw, and still follows.
    yield from wait_converged(time.perf_counter())
    lit = viewport_in_camera_pixels(screenshot("viewport_lit.png"), area, region, frame, width, height)
    lights = [o.data for o in scene.objects if o.type == "LIGHT"]
    for light in lights:
        light.energy *= 0.25
    yield from wait_converged(time.perf_counter())
    dimmed = viewport_in_camera_pixels(screenshot("viewport_dimmed.png"), area, region, frame, width, height)
    results["dimmed_ground_luminance_ratio"] = float(luminance(dimmed)[ground].mean() / luminance(lit)[ground].mean())
    for light in lights:
        light.energy *= 4.0

    # Frame changes: the moving object animated along a circle; each change is
    # followed by one synchronous redraw (view_update + view_draw).
    scene.frame_start, scene.frame_end = 1, FRAMES
    movers = [(moving, 0.0)] + [(bpy.data.objects[name], math.pi) for name in ALSO_MOVING]
    for mover, phase in movers:
        start = mover.location.copy()
        for f in range(1, FRAMES + 1):
            angle = 2 * math.pi * f / FRAMES + phase
            mover.location = start + type(start)((0.5 * math.cos(angle) - 0.5 * math.cos(phase), 0.5 * math.sin(angle), 0))
            mover.keyframe_insert("location", frame=f)

    def frame_changes(engine_name, record=True):
        scene.render.engine = engine_name
        yield 1.0
        if engine_name == "RTSDF":
            # A new engine starts its fields afresh: timed from where a user
            # who had the viewport open would be, with them refined.
            yield from wait_converged(time.perf_counter())
        times, memory, draws, stages, field_stats, samples = [], [], [], [], [], []
        for f in range(1, FRAMES + 1):
            start = time.perf_counter()
            scene.frame_set(f)
            with bpy.context.temp_override(window=window, area=area, region=region):
                bpy.ops.wm.redraw_timer(type="DRAW", iterations=1)
            times.append(time.perf_counter() - start)
            if engine_name == "RTSDF":
                draws.append(dict(rtsdf_engine.last_view_draw.get("draw_ms", {})))
                stages.append(dict(rtsdf_engine.last_view_draw.get("ms", {})))
                field_stats.append(dict(rtsdf_engine.last_view_draw.get("stats", {})))
                samples.append(rtsdf_engine.last_view_draw.get("effective_samples", 0.0))
            memory.append(rss_mib())
            if f % 10 == 0:
                yield 0.0
        if draws and record:
            results["draw_ms_median"] = {k: float(np.median([d.get(k, 0.0) for d in draws])) for k in draws[-1]}
            results["stages_ms_median"] = {k: float(np.median([s.get(k, 0.0) for s in stages])) for k in stages[-1]}
            results["stages_ms_frames"] = stages
            results["field_stats_frames"] = field_stats
        if samples:
            results.setdefault("effective_samples_median", {})[str(scene.rtsdf.viewport_temporal_reuse)] = \
                float(np.median(samples))
        return times, memory

    times, memory = yield from frame_changes("RTSDF")
    results["frame_change_ms"] = {"median": 1000 * float(np.median(times)), "max": 1000 * float(np.max(times))}
    results["rss_mib"] = {"after_10": memory[min(9, len(memory) - 1)], "after_all": memory[-1], "frames": FRAMES}
    results["stages_ms"] = rtsdf_engine.last_view_draw.get("ms", {})
    results["validation_messages"] = rtsdf_engine.last_view_draw.get("validation_messages", -1)
    screenshot("viewport_animated.png")
    if COMPARE_EEVEE:
        eevee_times, _ = yield from frame_changes("BLENDER_EEVEE")
        results["eevee_frame_change_ms"] = {"median": 1000 * float(np.median(eevee_times)),
                                            "max": 1000 * float(np.max(eevee_times))}
    for _, setting, key in COMPARE_SETTING_OFF:
        setattr(scene.rtsdf, setting, False)
        off_times, _ = yield from frame_changes("RTSDF", record=False)
        results[key] = {"median": 1000 * float(np.median(off_times)), "max": 1000 * float(np.max(off_times))}
        setattr(scene.rtsdf, setting, True)


def show_rendered_through_camera(scene, space, window, area, region):
    """The 3D view in Rendered shading with RTSDF, through the camera, nothing drawn over it."""
    scene.render.engine = "RTSDF"
    space.shading.type = "RENDERED"
    space.overlay.show_overlays = False
    space.show_gizmo = False
    for name in ("show_region_toolbar", "show_region_ui", "show_region_header", "show_region_tool_header"):
        setattr(space, name, False)
    space.region_3d.view_perspective = "CAMERA"
    with bpy.context.temp_override(window=window, area=area, region=region):
        bpy.ops.view3d.view_center_camera()


def field_views(scene, space, window, area, region, wait_converged, screenshot):
    show_rendered_through_camera(scene, space, window, area, region)
    yield from wait_converged(time.perf_counter())
    shaded = screenshot("field_view_none.png")
    heights = [o.matrix_world.translation.z for o in scene.objects if o.type == "MESH" and o.name != GROUND]
    scene.rtsdf.field_view_height = float(np.mean(heights)) if heights else 0.0
    results["field_views"] = {}
    for view in ("distance_slice", "march_steps", "field_resolution", "exact_rays"):
        scene.rtsdf.field_view = view
        yield from wait_converged(time.perf_counter())
        shot = screenshot(f"field_view_{view}.png")
        results["field_views"][view] = {"difference": float(np.abs(shot - shaded).mean()), "spread": float(shot.std())}
    scene.rtsdf.field_view = "none"


def run():
    sequence = steps()

    def tick():
        try:
            delay = next(sequence)
            return max(delay, 0.0)
        except StopIteration:
            pass
        except Exception:
            results["errors"].append(traceback.format_exc())
        with open(os.path.join(OUT, "viewport.json"), "w") as f:
            json.dump(results, f, indent=2)
        bpy.ops.wm.quit_blender()
        return None

    bpy.app.timers.register(tick, first_interval=1.0)


run()
