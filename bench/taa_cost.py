#!/usr/bin/python3
"""What temporal reuse (the viewport's TAA) adds to a playback step.

usage: bench/taa_cost.py WORK_DIR SCENE[,SCENE...] [--runs N] [--size WxH] [--stages]
                        [--exact-rays N] [--quick-first-frame] [--interleave K] [--apart I,J,...]

WORK_DIR is a bench/run output's work directory (DIR/work: each scene's
scene.pkl from Blender). For each scene a native viewport with rtsdf's
default setting converges on the still scene, then plays bench/run's move
(ANIMATION_STEPS steps, one frame drawn per step), with temporal reuse on
and off, alternating, N runs each. Prints the median step (begin + frame,
native wall time) of each and their ratio, and the ratio of the fastest
runs' medians: on a shared machine a slow spell lengthens some runs by a
third, and the fastest run of each is the one least touched by it.

--size draws at WxH instead of the scene's size (a Blender viewport of a
1045x666 region at Resolution Scale 0.5 draws 522x333). --stages prints
too where the steps with and without temporal reuse went: the medians of the
viewport's stage timings (the GPU's G-buffer, quad pass, temporal passes (and
of those the keep pass) and all shading; the SDF and fine updates; the frame's wall time).
--exact-rays, --quick-first-frame and --interleave set those settings as
the add-on's viewport has them (4, on and 4; bench/run's Preview row, which
the script draws otherwise, leaves the native defaults, and traces every
texel of a changing field at each update). A deforming mesh's field keeps
the native viewport's room around it (bench/run's in_viewport), as in
Blender: the row's tight grid would be fitted anew, and traced afresh, at
every step.
--apart plays another move in place of bench/run's: the instances listed
(indices into the scene's instances) move apart at once, alternately along
+x and -x, each step by a tenth of their mean size (several objects
animated together, as a scene's animation has them).
"""
import argparse
import importlib.machinery
import importlib.util
import os
import pickle

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
_loader = importlib.machinery.SourceFileLoader("bench_run", os.path.join(HERE, "run"))
_spec = importlib.util.spec_from_loader("bench_run", _loader)
bench = importlib.util.module_from_spec(_spec)
_loader.exec_module(bench)


def apart_poses(data, movers):
    """show_pose's stand-in for --apart: step -> every instance's transform,
    the instances `movers` moved apart along x (alternately + and -), each
    step by a tenth of their mean size (the diagonal of their placed
    vertices' box)."""
    instances = data["before"]["instances"]
    before = [np.array(instance["matrix"], np.float32) for instance in instances]
    sizes = []
    for i in movers:
        points = np.asarray(data["before"]["meshes"][instances[i]["mesh"]]["positions"], np.float32)
        placed = points @ before[i][:3, :3].T + before[i][:3, 3]
        sizes.append(float(np.linalg.norm(placed.max(axis=0) - placed.min(axis=0))))
    step_length = 0.1 * float(np.mean(sizes))

    def pose(step):
        transforms = [m.copy() for m in before]
        for k, i in enumerate(movers):
            transforms[i][0, 3] += (step_length if k % 2 == 0 else -step_length) * step
        return transforms
    return pose


def playback_steps(session, data, settings, temporal_reuse, size=None, apart=None):
    """Median ms of a playback step in a viewport that had converged on the
    still scene, and the medians of its stage timings (Viewport.draw's ms).
    apart: apart_poses' pose, played in place of bench/run's move."""
    viewport = session.viewport()
    viewport.sync(data["before"])
    view = bench.view_of(data["before"])
    if size:
        view.update(width=size[0], height=size[1])
    settings = dict(settings, temporal_reuse=temporal_reuse)
    for _ in range(settings["samples"] + 64):
        if viewport.draw(view, settings)["converged"]:
            break
    times, stages, deformed = [], {}, set()
    for step in range(1, bench.ANIMATION_STEPS + 1):
        if apart:
            viewport.set_transforms(apart(step))
        else:
            bench.show_pose(viewport, data, step, deformed)
        drawn = viewport.draw(view, settings)
        times.append(drawn["draw_ms"]["begin"] + drawn["draw_ms"]["frame"])
        for stage, ms in drawn["ms"].items():
            stages.setdefault(stage, []).append(ms)
        stages.setdefault("drawn_share", []).append(drawn["stats"]["drawn_share"])
    return float(np.median(times)), {stage: float(np.median(ms)) for stage, ms in stages.items()}


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("work")
    parser.add_argument("scenes")
    parser.add_argument("--runs", type=int, default=2)
    parser.add_argument("--size", help="WxH to draw at (default: the scene's)")
    parser.add_argument("--stages", action="store_true", help="print the stage timings of the steps with reuse too")
    parser.add_argument("--exact-rays", type=int, help="exact rays per light and sample (the viewport's: 4)")
    parser.add_argument("--quick-first-frame", action="store_true", help="as the viewport draws a frame after a change")
    parser.add_argument("--interleave", type=int, help="fine texels traced every K-th update (the viewport's: 4)")
    parser.add_argument("--apart", help="instances (I,J,...) that move apart at once, in place of bench/run's move")
    parser.add_argument("--whole-image", action="store_true",
                        help="draw each playback step over the whole image (changed_region_only off), to compare")
    args = parser.parse_args()
    size = tuple(int(n) for n in args.size.lower().split("x")) if args.size else None
    session = bench.sessions()[0]
    _, settings = bench.sweep("rtsdf", True, True)[0]
    settings = dict(bench.in_viewport(settings), samples=16)  # (the viewport's samples, and its room around a deforming mesh)
    if args.exact_rays is not None:
        settings["exact_rays"] = args.exact_rays
    if args.quick_first_frame:
        settings["quick_first_frame"] = True
    if args.interleave is not None:
        settings["interleave"] = args.interleave
    if args.whole_image:
        settings["changed_region_only"] = False
    for scene in args.scenes.split(","):
        with open(os.path.join(args.work, scene, "scene.pkl"), "rb") as f:
            data = pickle.load(f)
        movers = [int(i) for i in args.apart.split(",")] if args.apart else []
        if any(not 0 <= i < len(data["before"]["instances"]) for i in movers):
            parser.error(f"--apart {args.apart}: {scene} has instances 0 to {len(data['before']['instances']) - 1}")
        apart = apart_poses(data, movers) if movers else None
        if data["after"] is None and not apart:
            print(f"{scene}: no mover, skipped")
            continue
        session.forget_fields()
        session.render(data["before"], settings)  # (the fields refined, as in a viewport open a while)
        runs = {False: [], True: []}
        stages = {False: {}, True: {}}
        for _ in range(args.runs):
            for reuse in (False, True):
                ms, run_stages = playback_steps(session, data, settings, reuse, size, apart)
                runs[reuse].append(ms)
                for stage, stage_ms in run_stages.items():
                    stages[reuse].setdefault(stage, []).append(stage_ms)
        off, on = float(np.median(runs[False])), float(np.median(runs[True]))
        print(f"{scene}: step {off:.1f} ms without temporal reuse, {on:.1f} ms with it: {on / off:.3f}x; "
              f"fastest runs {min(runs[False]):.1f} and {min(runs[True]):.1f} ms: {min(runs[True]) / min(runs[False]):.3f}x "
              f"({session.device})", flush=True)
        if args.stages:
            shown = ("gbuffer_gpu", "quad_gpu", "temporal_gpu", "keep_gpu", "shade_gpu", "sdf", "fine", "total")
            for reuse in (True, False):
                taken = stages[reuse]
                print(f"{scene}: stages {'with' if reuse else 'without'} reuse, median over runs: " +
                      ", ".join(f"{stage} {np.median(taken[stage]):.1f}" for stage in shown if stage in taken) +
                      f" ms; drawn share of the image {np.median(taken['drawn_share']):.2f}", flush=True)


if __name__ == "__main__":
    main()
