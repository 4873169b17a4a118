#!/usr/bin/python3
"""What temporal reuse (the viewport's TAA) adds to a playback step.

usage: bench/taa_cost.py WORK_DIR SCENE[,SCENE...] [--runs N]

WORK_DIR is a bench/run output's work directory (DIR/work: each scene's
scene.pkl from Blender). For each scene a native viewport with rtsdf's
default setting converges on the still scene, then plays bench/run's move
(ANIMATION_STEPS steps, one frame drawn per step), with temporal reuse on
and off, alternating, N runs each. Prints the median step (begin + frame,
native wall time) of each and their ratio, and the ratio of the fastest
runs' medians: on a shared machine a slow spell lengthens some runs by a
third, and the fastest run of each is the one least touched by it.
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


def step_ms(session, data, settings, temporal_reuse):
    """Median ms of a playback step in a viewport that had converged on the still scene."""
    viewport = session.viewport()
    viewport.sync(data["before"])
    view = bench.view_of(data["before"])
    settings = dict(settings, temporal_reuse=temporal_reuse)
    for _ in range(settings["samples"] + 64):
        if viewport.draw(view, settings)["converged"]:
            break
    times = []
    for step in range(1, bench.ANIMATION_STEPS + 1):
        viewport.set_transforms(bench.mover_transforms(data, step))
        draw_ms = viewport.draw(view, settings)["draw_ms"]
        times.append(draw_ms["begin"] + draw_ms["frame"])
    return float(np.median(times))


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("work")
    parser.add_argument("scenes")
    parser.add_argument("--runs", type=int, default=2)
    args = parser.parse_args()
    session = bench.sessions()[0]
    _, settings = bench.sweep("rtsdf", True, True)[0]
    settings = dict(settings, samples=16)  # (the viewport's samples)
    for scene in args.scenes.split(","):
        with open(os.path.join(args.work, scene, "scene.pkl"), "rb") as f:
            data = pickle.load(f)
        if data["after"] is None:
            print(f"{scene}: no mover, skipped")
            continue
        session.forget_fields()
        session.render(data["before"], settings)  # (the fields refined, as in a viewport open a while)
        runs = {False: [], True: []}
        for _ in range(args.runs):
            for reuse in (False, True):
                runs[reuse].append(step_ms(session, data, settings, reuse))
        off, on = float(np.median(runs[False])), float(np.median(runs[True]))
        print(f"{scene}: step {off:.1f} ms without temporal reuse, {on:.1f} ms with it: {on / off:.3f}x; "
              f"fastest runs {min(runs[False]):.1f} and {min(runs[True]):.1f} ms: {min(runs[True]) / min(runs[False]):.3f}x "
              f"({session.device})", flush=True)


if __name__ == "__main__":
    main()
