#!/usr/bin/python3
"""How far a playback frame is from the converged still frame, at a given
number of exact rays.

usage: bench/playback_error.py WORK_DIR SCENE[,SCENE...] [--exact-rays N[,N...]]
                               [--short-history-rays K] [--final] [--save DIR]

WORK_DIR is a bench/run output's work directory (DIR/work: each scene's
scene.pkl and Cycles references). bench/run's playback column plays its
move at the Preview setting, which casts no exact rays; the add-on's
viewport draws with the scene's Exact Rays (4 by default). For each scene
and each N (default 0 and 4) this plays bench/run's move with temporal
reuse (playback_frames), renders the still frame of the last pose, and
prints bench/run's playback figures (playback_figures): the playback
frame's shadow RMSE against Cycles and its ratio to the still frame's;
then what sets the two frames apart over the shadowed pixels, split into
lag (its smooth part: a shadow left behind or not yet arrived) and noise
(the rest), and where the playback frame's squared error against Cycles
exceeds the still frame's: at geometry edges (pixels within one of an edge
of Cycles' render without shadows: outlines, creases, fins) or elsewhere
(shadows on smooth surfaces). --short-history-rays sets the factor on the
exact rays where history is short (the native default, 4, otherwise; 1: as
in any frame). --final plays bench/run's Final row instead of Preview (16
samples, its own 4 exact rays unless --exact-rays is given): its playback
ratio is the one in results.csv. --save writes, for a look, each scene's
last playback frame, still frame and Cycles reference as PNGs into DIR
(SCENE_raysN_played.png, ..._still.png, SCENE_cycles.png).
"""
import argparse
import importlib.machinery
import importlib.util
import os

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
_loader = importlib.machinery.SourceFileLoader("bench_run", os.path.join(HERE, "run"))
_spec = importlib.util.spec_from_loader("bench_run", _loader)
bench = importlib.util.module_from_spec(_spec)
_loader.exec_module(bench)


def lag_and_noise(played, still, refs, window=7):
    """The RMS over Cycles' shadowed pixels of the playback frame's difference
    from the still frame, split into its smooth part (a window x window box
    mean) and the rest."""
    metrics = bench.metrics
    shadowed = metrics.visibility(refs["after_shadowed"], refs["after_unshadowed"]) < metrics.SHADOWED_BELOW
    difference = np.where(shadowed, played.mean(axis=-1) - still.mean(axis=-1), 0.0)
    smooth = metrics.box_mean(np.pad(difference, window // 2, mode="edge"), window)
    return float(np.sqrt(np.mean(smooth[shadowed] ** 2))), float(np.sqrt(np.mean((difference - smooth)[shadowed] ** 2)))


def geometry_edges(unshadowed, threshold=0.03):
    """(H, W) mask of the pixels within one of an edge of an image without
    shadows (its brightness's gradient above `threshold`)."""
    rows, cols = np.gradient(unshadowed.mean(axis=-1))
    edge = np.hypot(rows, cols) > threshold
    padded = np.pad(edge, 1)
    height, width = edge.shape
    return np.any([padded[1 + dy:1 + dy + height, 1 + dx:1 + dx + width] for dy in (-1, 0, 1) for dx in (-1, 0, 1)],
                  axis=0)


def excess_at_edges(played, still, refs):
    """The playback frame's mean squared error against Cycles over its
    shadowed pixels less the still frame's, split into what lies at geometry
    edges and elsewhere (the two add up to the whole excess)."""
    metrics = bench.metrics
    reference = refs["after_shadowed"][..., :3]
    shadowed = metrics.visibility(refs["after_shadowed"], refs["after_unshadowed"]) < metrics.SHADOWED_BELOW
    excess = ((played - reference) ** 2).mean(axis=-1) - ((still - reference) ** 2).mean(axis=-1)
    edges = geometry_edges(refs["after_unshadowed"][..., :3])
    count = max(int(shadowed.sum()), 1)
    return float(excess[shadowed & edges].sum() / count), float(excess[shadowed & ~edges].sum() / count)


def save_frames(directory, prefix, played, still, names=("played", "still")):
    """PNGs of the frames compared (display gamma, as bench/run's images)."""
    from PIL import Image
    os.makedirs(directory, exist_ok=True)
    for name, image in zip(names, (played, still)):
        Image.fromarray(bench.display(image)).save(os.path.join(directory, f"{prefix}_{name}.png"))


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("work")
    parser.add_argument("scenes")
    parser.add_argument("--exact-rays", help="exact rays per light and sample, comma-separated (default 0,4; "
                                             "with --final, the Final row's)")
    parser.add_argument("--short-history-rays", type=int, help="the factor on the exact rays where history is short")
    parser.add_argument("--final", action="store_true", help="bench/run's Final row, not its Preview row")
    parser.add_argument("--save", metavar="DIR", help="write the frames compared as PNGs into DIR")
    args = parser.parse_args()
    session = bench.sessions()[0]
    rows = bench.sweep("rtsdf", True, True)
    base = next(settings for label, settings in rows if label.startswith("preset=Final")) if args.final else rows[0][1]
    exact_rays = args.exact_rays or (str(base["exact_rays"]) if args.final else "0,4")
    for scene in args.scenes.split(","):
        data, refs = bench.prepared_scene(os.path.join(args.work, scene))
        if data["after"] is None or "after_shadowed" not in refs:
            print(f"{scene}: no mover, skipped")
            continue
        for rays in (int(n) for n in exact_rays.split(",")):
            settings = dict(base, exact_rays=rays)
            if args.short_history_rays is not None:
                settings["short_history_rays"] = args.short_history_rays
            session.forget_fields()
            played = bench.playback_frames(session, data, settings, temporal_reuse=True)
            still = session.render(data["after"], settings)["combined"][..., :3]
            figures = bench.playback_figures(played, still, refs)
            lag, noise = lag_and_noise(played[-1], still, refs)
            at_edges, elsewhere = excess_at_edges(played[-1], still, refs)
            if args.save:
                save_frames(args.save, f"{scene}_rays{rays}", played[-1], still)
                save_frames(args.save, scene, refs["after_shadowed"][..., :3], None, names=("cycles",))
            print(f"{scene}: exact rays {rays}: playback frame shadow RMSE {figures['playback_rmse']}, "
                  f"{figures['playback_ratio']}x the still frame's; from the still frame, lag {lag:.4f}, "
                  f"noise {noise:.4f}; squared error beyond the still frame's: {at_edges:.6f} at geometry "
                  f"edges, {elsewhere:.6f} elsewhere ({session.device})", flush=True)

if __name__ == "__main__":
    main()
