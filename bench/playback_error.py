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
prints bench/run's playback figures (playback_figures): the playback
frame's shadow RMSE against Cycles and its ratio to the still frame's.
"""
import argparse
import importlib.machinery
import importlib.util
import os

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
        data, refs = bench.prepared_scene(os.path.join(args.work, scene))
        if data["after"] is None or "after_shadowed" not in refs:
            print(f"{scene}: no mover, skipped")
            continue
        for rays in (int(n) for n in args.exact_rays.split(",")):
            settings = dict(preview, exact_rays=rays)
            session.forget_fields()
            played = bench.playback_frames(session, data, settings, temporal_reuse=True)
            still = session.render(data["after"], settings)["combined"][..., :3]
            figures = bench.playback_figures(played, still, refs)
            print(f"{scene}: exact rays {rays}: playback frame shadow RMSE {figures['playback_rmse']}, "
                  f"{figures['playback_ratio']}x the still frame's ({session.device})", flush=True)

if __name__ == "__main__":
    main()
