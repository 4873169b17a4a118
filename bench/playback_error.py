#!/usr/bin/python3
"""How far a playback frame is from the converged still frame, at a given
number of exact rays.

usage: bench/playback_error.py WORK_DIR SCENE[,SCENE...] [--exact-rays N[,N...]]

WORK_DIR is a bench/run output's work directory (DIR/work: each scene's
scene.pkl and Cycles references). bench/run's playback column plays its
move at the Preview setting, which casts no exact rays; the add-on's
viewport draws with the scene's Exact Rays (4 by default). For each scene
and each N (default 0 and 4) this plays bench/run's move with temporal
reuse (playback_frames), renders the still frame of the last pose, and
prints both shadow RMSEs against Cycles and their ratio (bench/run's
playback_ratio at that setting).
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


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("work")
    parser.add_argument("scenes")
    parser.add_argument("--exact-rays", default="0,4", help="exact rays per light and sample, comma-separated")
    args = parser.parse_args()
    session = bench.sessions()[0]
    _, preview = bench.sweep("rtsdf", True, True)[0]
    for scene in args.scenes.split(","):
        work = os.path.join(args.work, scene)
        with open(os.path.join(work, "scene.pkl"), "rb") as f:
            data = pickle.load(f)
        reference = os.path.join(work, "cycles_after_shadowed.npy")
        if data["after"] is None or not os.path.exists(reference):
            print(f"{scene}: no mover, skipped")
            continue
        shadowed_image = np.load(reference)
        unshadowed = np.load(os.path.join(work, "cycles_after_unshadowed.npy"))
        for rays in (int(n) for n in args.exact_rays.split(",")):
            settings = dict(preview, exact_rays=rays)
            session.forget_fields()
            played = bench.playback_frames(session, data, settings, temporal_reuse=True)[-1]
            still = session.render(data["after"], settings)["combined"][..., :3]
            shown = bench.metrics.compare(played, shadowed_image, unshadowed)["shadow_rmse"]
            converged = bench.metrics.compare(still, shadowed_image, unshadowed)["shadow_rmse"]
            print(f"{scene}: exact rays {rays}: playback frame shadow RMSE {shown:.4f}, still frame {converged:.4f}: "
                  f"{shown / max(converged, 1e-6):.2f}x ({session.device})", flush=True)


if __name__ == "__main__":
    main()
