#!/usr/bin/python3
"""Draws one slice of an SDF stored in a .vdb as a PNG: distance in voxels,
colour-mapped, with the zero level and the +-1 voxel levels drawn as contours.

usage: sdf_slice.py FILE.vdb [--grid coarse] [--axis z] [--index N] --out FILE.png
By default the slice is the middle one along --axis (y: a vertical cut).
"""
import argparse

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import pyopenvdb as vdb  # noqa: E402


def dense(grid):
    lo, hi = grid.evalActiveVoxelBoundingBox()
    shape = tuple(h - l + 1 for l, h in zip(lo, hi))
    values = np.zeros(shape, dtype=np.float32)
    grid.copyToArray(values, ijk=lo)
    return values, lo  # values[i, j, k]


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("vdb")
    parser.add_argument("--grid", default="coarse")
    parser.add_argument("--axis", choices="xyz", default="y")
    parser.add_argument("--index", type=int, help="slice index along --axis (default: the middle one)")
    parser.add_argument("--out", required=True)
    args = parser.parse_args()

    grid = vdb.read(args.vdb, args.grid)
    voxel = grid.transform.voxelSize()[0]
    values, lo = dense(grid)
    axis = "xyz".index(args.axis)
    field = np.moveaxis(values, axis, 0) / voxel  # in voxels
    index = args.index - lo[axis] if args.index is not None else field.shape[0] // 2
    index = max(0, min(field.shape[0] - 1, index))
    plane = field[index].T  # rows = second remaining axis
    others = [a for a in "xyz" if a != args.axis]

    fig, ax = plt.subplots(figsize=(8, 8 * plane.shape[0] / plane.shape[1] + 0.8), dpi=110)
    limit = max(1.0, float(np.percentile(np.abs(plane), 99)))
    image = ax.imshow(plane, origin="lower", cmap="RdBu", vmin=-limit, vmax=limit, interpolation="nearest")
    ax.contour(plane, levels=[-1.0, 0.0, 1.0], colors=["#444444", "black", "#444444"],
               linewidths=[0.5, 1.2, 0.5], linestyles=["dotted", "solid", "dotted"])
    ax.set_xlabel(f"{others[0]} (voxels)")
    ax.set_ylabel(f"{others[1]} (voxels)")
    ax.set_title(f"'{args.grid}' SDF, {args.axis} = {index + lo[axis]} "
                 f"(voxel {voxel:.4g}); black: zero level")
    fig.colorbar(image, ax=ax, label="distance (voxels)", shrink=0.8)
    fig.tight_layout()
    fig.savefig(args.out)
    print(f"wrote {args.out}: slice {args.axis} = {index + lo[axis]} of {args.grid}")


if __name__ == "__main__":
    main()
