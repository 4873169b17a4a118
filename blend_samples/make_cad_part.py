#!/usr/bin/env python3
"""Generate a CAD-like mechanical assembly as a triangle mesh.

The mesh is a sample and benchmark input for signed-distance-field
generation. It is about 2 units across, centred near the origin, Z up, and
deliberately contains the features an SDF generator finds hard:

* a base plate with cylindrical through-holes (a watertight solid whose holes
  are real tunnels with inner walls),
* cylindrical bosses, a shaft and two rings (tori),
* a thin fin: a closed box only 0.004 units thick, far thinner than one voxel
  of a 128^3 grid over 2 units (about 0.016),
* a one-sided sheet: a single open rectangle with no thickness,
* rivets and bolts whose triangles are much smaller than a voxel,
* long, thin fan triangles such as CAD exporters produce for cylinder caps.

Every closed part is watertight with counter-clockwise (outward-facing)
winding. Parts overlap one another, as in an assembly, and share no vertices.
The output is deterministic: the same arguments give a byte-identical file.

Usage:
    python3 make_cad_part.py --triangles 110000 --out cad_part.ply
    python3 make_cad_part.py --triangles 20000 --out cad_part.obj
"""

import argparse
import math
import sys

import numpy as np


# ---------------------------------------------------------------------------
# Mesh accumulator and helpers
# ---------------------------------------------------------------------------

class Mesh:
    """Accumulates independent parts into one vertex and face list."""

    def __init__(self):
        self._vertices = []
        self._faces = []
        self._vertex_count = 0

    def add(self, vertices, faces):
        """Add one part; vertices its faces do not use are dropped."""
        vertices = np.asarray(vertices, dtype=np.float64)
        faces = np.asarray(faces, dtype=np.int64)
        used, remap = np.unique(faces, return_inverse=True)
        self._vertices.append(vertices[used])
        self._faces.append(remap.reshape(faces.shape) + self._vertex_count)
        self._vertex_count += len(used)

    @property
    def triangle_count(self):
        return sum(len(f) for f in self._faces)

    def arrays(self):
        """Return (vertices float32 (V,3), faces int32 (F,3))."""
        vertices = np.concatenate(self._vertices).astype(np.float32)
        faces = np.concatenate(self._faces).astype(np.int32)
        return vertices, faces


def grid_faces(idx):
    """Triangulate a 2D array of vertex indices as a grid of quads.

    The quad normal follows the right-hand rule from the first index axis to
    the second, i.e. it points along d(first) x d(second).
    """
    a = idx[:-1, :-1]
    b = idx[1:, :-1]
    c = idx[1:, 1:]
    d = idx[:-1, 1:]
    first = np.stack([a, b, c], axis=-1).reshape(-1, 3)
    second = np.stack([a, c, d], axis=-1).reshape(-1, 3)
    return np.concatenate([first, second])


def closed_loop(idx):
    """Repeat the first row so a grid wraps around its first axis."""
    return np.concatenate([idx, idx[:1]], axis=0)


def rotation(axis, degrees):
    """Rotation matrix about the x, y or z axis."""
    c, s = math.cos(math.radians(degrees)), math.sin(math.radians(degrees))
    if axis == "x":
        return np.array([[1, 0, 0], [0, c, -s], [0, s, c]])
    if axis == "y":
        return np.array([[c, 0, s], [0, 1, 0], [-s, 0, c]])
    return np.array([[c, -s, 0], [s, c, 0], [0, 0, 1]])


def place(part, offset=(0.0, 0.0, 0.0), rotate=None):
    """Rotate a (vertices, faces) part about the origin, then translate it."""
    vertices, faces = part
    if rotate is not None:
        vertices = vertices @ np.asarray(rotate).T
    return vertices + np.asarray(offset), faces


def circle(radius, segments, start_degrees=0.0):
    """Points on a circle in the XY plane, counter-clockwise seen from +Z."""
    t = math.radians(start_degrees) + 2.0 * math.pi * np.arange(segments) / segments
    return radius * np.cos(t), radius * np.sin(t)


# ---------------------------------------------------------------------------
# Primitives (local coordinates; combine with place())
# ---------------------------------------------------------------------------

def box(lo, hi, divisions=(1, 1, 1)):
    """Closed axis-aligned box whose faces are subdivided into a lattice."""
    nx, ny, nz = divisions
    i, j, k = np.meshgrid(np.arange(nx + 1), np.arange(ny + 1),
                          np.arange(nz + 1), indexing="ij")
    on_surface = ((i == 0) | (i == nx) | (j == 0) | (j == ny)
                  | (k == 0) | (k == nz))
    index = np.full(on_surface.shape, -1, dtype=np.int64)
    index[on_surface] = np.arange(np.count_nonzero(on_surface))
    t = np.stack([i[on_surface] / nx, j[on_surface] / ny,
                  k[on_surface] / nz], axis=1)
    lo, hi = np.asarray(lo, float), np.asarray(hi, float)
    vertices = lo + t * (hi - lo)
    faces = np.concatenate([
        grid_faces(index[nx, :, :]),      # +X: dy x dz
        grid_faces(index[0, :, :].T),     # -X: dz x dy
        grid_faces(index[:, ny, :].T),    # +Y: dz x dx
        grid_faces(index[:, 0, :]),       # -Y: dx x dz
        grid_faces(index[:, :, nz]),      # +Z: dx x dy
        grid_faces(index[:, :, 0].T),     # -Z: dy x dx
    ])
    return vertices, faces


def cylinder(radius, z0, z1, segments, cap="fan"):
    """Closed cylinder along Z, side walls as single tall quads.

    cap="fan" triangulates each cap as a fan from its centre; cap="polygon"
    triangulates it as a fan from one rim vertex, as many exporters do, which
    gives extremely thin slivers. Both are long and thin for many segments.
    """
    x, y = circle(radius, segments)
    n = segments
    vertices = np.concatenate([
        np.stack([x, y, np.full(n, z0)], axis=1),
        np.stack([x, y, np.full(n, z1)], axis=1),
    ])
    rings = np.stack([np.arange(n), np.arange(n) + n], axis=1)
    faces = [grid_faces(closed_loop(rings))]        # d(angle) x dz: outward

    ring = np.arange(n)
    nxt = np.roll(ring, -1)
    if cap == "fan":
        vertices = np.concatenate([vertices, [[0, 0, z0], [0, 0, z1]]])
        bottom_c, top_c = 2 * n, 2 * n + 1
        faces.append(np.stack([np.full(n, bottom_c), nxt, ring], axis=1))
        faces.append(np.stack([np.full(n, top_c), ring + n, nxt + n], axis=1))
    elif cap == "polygon":
        j = np.arange(1, n - 1)
        faces.append(np.stack([np.zeros_like(j), j + 1, j], axis=1))
        faces.append(np.stack([np.full_like(j, n), j + n, j + 1 + n], axis=1))
    else:
        raise ValueError(f"unknown cap style {cap!r}")
    return vertices, np.concatenate(faces)


def torus(major_radius, minor_radius, major_segments, minor_segments):
    """Closed torus around the Z axis."""
    phi = 2.0 * math.pi * np.arange(major_segments) / major_segments
    psi = 2.0 * math.pi * np.arange(minor_segments) / minor_segments
    phi, psi = np.meshgrid(phi, psi, indexing="ij")
    rho = major_radius + minor_radius * np.cos(psi)
    vertices = np.stack([rho * np.cos(phi), rho * np.sin(phi),
                         minor_radius * np.sin(psi)], axis=-1).reshape(-1, 3)
    index = np.arange(major_segments * minor_segments).reshape(
        major_segments, minor_segments)
    index = closed_loop(closed_loop(index).T).T     # wrap both directions
    return vertices, grid_faces(index)              # d(phi) x d(psi): outward


def uv_sphere(radius, segments, rings):
    """Closed UV sphere with single pole vertices (triangle fans at the poles)."""
    phi = 2.0 * math.pi * np.arange(segments) / segments
    theta = -0.5 * math.pi + math.pi * np.arange(1, rings) / rings
    phi, theta = np.meshgrid(phi, theta, indexing="ij")
    body = np.stack([np.cos(theta) * np.cos(phi), np.cos(theta) * np.sin(phi),
                     np.sin(theta)], axis=-1).reshape(-1, 3)
    vertices = radius * np.concatenate([body, [[0, 0, -1], [0, 0, 1]]])
    index = np.arange(segments * (rings - 1)).reshape(segments, rings - 1)
    south, north = len(body), len(body) + 1
    ring = np.arange(segments)
    nxt = np.roll(ring, -1)
    faces = [
        grid_faces(closed_loop(index)),             # d(phi) x d(theta): outward
        np.stack([np.full(segments, south), index[nxt, 0], index[ring, 0]], 1),
        np.stack([np.full(segments, north), index[ring, -1], index[nxt, -1]], 1),
    ]
    return vertices, np.concatenate(faces)


def sheet(width, height, u_divisions, v_divisions):
    """Open, one-sided rectangle in the XY plane, normal +Z, centred."""
    u = np.linspace(-0.5 * width, 0.5 * width, u_divisions + 1)
    v = np.linspace(-0.5 * height, 0.5 * height, v_divisions + 1)
    u, v = np.meshgrid(u, v, indexing="ij")
    vertices = np.stack([u, v, np.zeros_like(u)], axis=-1).reshape(-1, 3)
    index = np.arange(vertices.shape[0]).reshape(u.shape)
    return vertices, grid_faces(index)


def plate_with_holes(cell_size, cells, z0, z1, holes, cell_divisions):
    """Closed rectangular plate with cylindrical through-holes.

    The plate is a grid of square cells; each cell edge is split into
    `cell_divisions` segments. A hole sits in the centre of a cell and its
    rim has 4 * cell_divisions vertices, joined to the cell border by a ring
    of quads, so top, bottom, outer walls and hole walls share every edge.
    `holes` maps (cell_i, cell_j) to a hole radius (< cell_size / 2).
    The plate spans [0, cells_x * cell_size] x [0, cells_y * cell_size].
    """
    cells_x, cells_y = cells
    k = cell_divisions
    nx, ny = cells_x * k, cells_y * k
    step = cell_size / k

    gx, gy = np.meshgrid(np.arange(nx + 1) * step, np.arange(ny + 1) * step,
                         indexing="ij")
    lattice = np.stack([gx, gy], axis=-1).reshape(-1, 2)
    lattice_count = len(lattice)
    top = np.arange(lattice_count).reshape(nx + 1, ny + 1)
    bottom = top + lattice_count
    vertices = [np.column_stack([lattice, np.full(lattice_count, z1)]),
                np.column_stack([lattice, np.full(lattice_count, z0)])]
    faces = []
    next_index = 2 * lattice_count

    # Outer side walls: perimeter loop counter-clockwise seen from +Z.
    perimeter = ([(i, 0) for i in range(nx)] + [(nx, j) for j in range(ny)]
                 + [(nx - i, ny) for i in range(nx)] + [(0, ny - j) for j in range(ny)])
    pi, pj = np.array(perimeter).T
    walls = np.stack([bottom[pi, pj], top[pi, pj]], axis=1)
    faces.append(grid_faces(closed_loop(walls)))    # d(loop) x dz: outward

    for ci in range(cells_x):
        for cj in range(cells_y):
            i0, j0 = ci * k, cj * k
            if (ci, cj) not in holes:
                cell_top = top[i0:i0 + k + 1, j0:j0 + k + 1]
                cell_bottom = bottom[i0:i0 + k + 1, j0:j0 + k + 1]
                faces.append(grid_faces(cell_top))
                faces.append(grid_faces(cell_bottom.T))
                continue

            # Cell border, counter-clockwise from the lower-left corner.
            t = np.arange(k)
            bi = np.concatenate([i0 + t, np.full(k, i0 + k), i0 + k - t, np.full(k, i0)])
            bj = np.concatenate([np.full(k, j0), j0 + t, np.full(k, j0 + k), j0 + k - t])
            # Hole rim, same count, starting at the same (225 degree) angle.
            cx, cy = (ci + 0.5) * cell_size, (cj + 0.5) * cell_size
            rx, ry = circle(holes[(ci, cj)], 4 * k, start_degrees=225.0)
            rim = np.column_stack([cx + rx, cy + ry])
            rim_top = next_index + np.arange(4 * k)
            rim_bottom = rim_top + 4 * k
            next_index += 8 * k
            vertices.append(np.column_stack([rim, np.full(4 * k, z1)]))
            vertices.append(np.column_stack([rim, np.full(4 * k, z0)]))

            ring_top = np.stack([top[bi, bj], rim_top], axis=1)
            ring_bottom = np.stack([bottom[bi, bj], rim_bottom], axis=1)
            faces.append(grid_faces(closed_loop(ring_top)))
            faces.append(grid_faces(closed_loop(ring_bottom).T))
            tunnel = np.stack([rim_top, rim_bottom], axis=1)
            faces.append(grid_faces(closed_loop(tunnel)))   # faces the axis

    return np.concatenate(vertices), np.concatenate(faces)


# ---------------------------------------------------------------------------
# The assembly
# ---------------------------------------------------------------------------

PLATE_TOP = -0.18
PLATE_BOTTOM = -0.30


def resolution(base, detail, minimum):
    """Segment count that grows with the detail level, never below minimum."""
    return max(minimum, int(round(base * detail)))


def build_assembly(detail):
    """Build the whole assembly at a given tessellation detail level."""
    mesh = Mesh()

    # Base plate, 1.8 x 1.2 x 0.12, with six through-holes.
    holes = {(0, 0): 0.09, (5, 0): 0.09, (0, 3): 0.09, (5, 3): 0.09,
             (3, 2): 0.07, (2, 0): 0.05}
    plate = plate_with_holes(0.3, (6, 4), PLATE_BOTTOM, PLATE_TOP, holes,
                             resolution(5, detail, 2))
    mesh.add(*place(plate, offset=(-0.9, -0.6, 0.0)))

    # Bosses standing on the plate (sunk slightly into it), with fan caps.
    segments = resolution(64, detail, 12)
    mesh.add(*place(cylinder(0.10, -0.20, 0.12, segments), (-0.45, 0.15, 0.0)))
    mesh.add(*place(cylinder(0.12, -0.20, 0.00, segments), (0.45, -0.15, 0.0)))
    # A tall pin on the second boss, caps triangulated from a rim vertex.
    mesh.add(*place(cylinder(0.04, -0.05, 0.50, segments, cap="polygon"),
                    (0.45, -0.15, 0.0)))
    # A horizontal shaft along X, polygon caps.
    mesh.add(*place(cylinder(0.05, -0.35, 0.35, segments, cap="polygon"),
                    (0.15, 0.42, 0.05), rotate=rotation("y", 90)))

    # Rings: one lying around the first boss, one standing around the shaft.
    major, minor = resolution(96, detail, 16), resolution(24, detail, 6)
    mesh.add(*place(torus(0.17, 0.025, major, minor), (-0.45, 0.15, 0.02)))
    mesh.add(*place(torus(0.09, 0.02, major, minor), (0.35, 0.42, 0.05),
                    rotate=rotation("y", 90)))

    # Thin fin: 0.7 long, 0.004 thick, 0.35 tall, standing at an angle.
    fin = box((-0.35, -0.002, -0.20), (0.35, 0.002, 0.15),
              (resolution(48, detail, 4), 1, resolution(24, detail, 2)))
    mesh.add(*place(fin, (0.05, -0.15, 0.0), rotate=rotation("z", 25)))

    # One-sided sheet (no thickness), tilted and hovering over the plate.
    plane = sheet(0.45, 0.30, resolution(24, detail, 2), resolution(16, detail, 2))
    mesh.add(*place(plane, (-0.55, -0.30, 0.25), rotate=rotation("x", 35)))

    # Rivets: rows of tiny spheres half sunk into the plate's top face.
    rivet_segments, rivet_rings = resolution(16, detail, 12), resolution(8, detail, 6)
    for y in (-0.54, 0.54):
        for x in np.linspace(-0.55, 0.55, 12):
            mesh.add(*place(uv_sphere(0.012, rivet_segments, rivet_rings),
                            (x, y, PLATE_TOP)))

    # Bolts on the first boss: hexagonal heads with round shanks.
    shank_segments = resolution(12, detail, 8)
    boss_top = 0.12
    for angle in np.arange(6) * 60.0 + 30.0:
        x = -0.45 + 0.065 * math.cos(math.radians(angle))
        y = 0.15 + 0.065 * math.sin(math.radians(angle))
        mesh.add(*place(cylinder(0.011, boss_top - 0.002, boss_top + 0.007, 6),
                        (x, y, 0.0)))
        mesh.add(*place(cylinder(0.005, boss_top - 0.05, boss_top + 0.001,
                                 shank_segments), (x, y, 0.0)))
    return mesh


def build_for_target(target):
    """Find the detail level whose triangle count is closest to target."""
    cache = {}

    def count(detail):
        if detail not in cache:
            cache[detail] = build_assembly(detail).triangle_count
        return cache[detail]

    lo, hi = 0.1, 1.0
    while count(hi) < target and hi < 64.0:
        lo, hi = hi, hi * 2.0
    for _ in range(24):
        mid = 0.5 * (lo + hi)
        if count(mid) < target:
            lo = mid
        else:
            hi = mid
    best = min(cache, key=lambda d: (abs(cache[d] - target), d))
    return build_assembly(best)


# ---------------------------------------------------------------------------
# Output
# ---------------------------------------------------------------------------

def write_ply(path, vertices, faces):
    """Binary little-endian PLY with float x,y,z and uchar/int face lists."""
    header = (
        "ply\n"
        "format binary_little_endian 1.0\n"
        "comment CAD-like assembly, sample mesh for SDF generation\n"
        f"element vertex {len(vertices)}\n"
        "property float x\n"
        "property float y\n"
        "property float z\n"
        f"element face {len(faces)}\n"
        "property list uchar int vertex_indices\n"
        "end_header\n"
    )
    face_records = np.empty(len(faces), dtype=[("n", "u1"), ("v", "<i4", (3,))])
    face_records["n"] = 3
    face_records["v"] = faces
    with open(path, "wb") as f:
        f.write(header.encode("ascii"))
        f.write(vertices.astype("<f4").tobytes())
        f.write(face_records.tobytes())


def write_obj(path, vertices, faces):
    """Plain OBJ with v and f lines (1-based indices)."""
    lines = ["# CAD-like assembly, sample mesh for SDF generation\n"]
    lines += ["v %.9g %.9g %.9g\n" % tuple(v) for v in vertices.astype(np.float64)]
    lines += ["f %d %d %d\n" % tuple(f) for f in (faces + 1).tolist()]
    with open(path, "w", newline="\n") as f:
        f.write("".join(lines))


def main(argv=None):
    parser = argparse.ArgumentParser(
        description="Generate a CAD-like mechanical assembly (base plate with "
                    "through-holes, bosses, rings, a 0.004-thick fin, a "
                    "one-sided sheet, tiny rivets and bolts, fan-triangulated "
                    "caps) as a sample and benchmark mesh for signed-distance-"
                    "field generation. Output is deterministic.")
    parser.add_argument("--triangles", type=int, default=110000,
                        help="approximate total triangle count (default: 110000)")
    parser.add_argument("--out", required=True,
                        help="output file (.ply or .obj)")
    parser.add_argument("--format", choices=("ply", "obj"),
                        help="output format (default: from the --out extension)")
    args = parser.parse_args(argv)

    fmt = args.format
    if fmt is None:
        ext = args.out.rsplit(".", 1)[-1].lower() if "." in args.out else ""
        if ext not in ("ply", "obj"):
            parser.error("cannot tell the format from --out; use --format")
        fmt = ext
    if args.triangles <= 0:
        parser.error("--triangles must be positive")

    vertices, faces = build_for_target(args.triangles).arrays()
    if fmt == "ply":
        write_ply(args.out, vertices, faces)
    else:
        write_obj(args.out, vertices, faces)

    lo, hi = vertices.min(axis=0), vertices.max(axis=0)
    print("triangles %d vertices %d bounds min (%.4f, %.4f, %.4f) max (%.4f, %.4f, %.4f)"
          % (len(faces), len(vertices), *lo, *hi))
    if abs(len(faces) - args.triangles) > 0.1 * args.triangles:
        print("warning: could not reach the requested triangle count",
              file=sys.stderr)
    return 0


if __name__ == "__main__":
    sys.exit(main())
