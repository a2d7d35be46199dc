"""Ordinary scenes (real objects) for the "possible from every view" tests.

Built independently of the code under test: separate axis-aligned blocks (8 corners, 12
triangles each), and solids that are unions of unit voxels (the boundary squares between a
filled and an empty cell, two triangles each, corners welded by their integer coordinates).
Seen along views with zero or equal components, their edges line up on screen exactly with
edges at other depths: a box's top edge on the foot of the wall behind it, a tread's front edge
on the next riser's foot.  Each builder returns ``(V, F)`` with +z up.
"""

from __future__ import annotations

import itertools

import numpy as np
from builders import merge_meshes


def blocks(lo, hi):
    """Separate boxes ``[lo_k, hi_k]`` as one soup of closed, outward triangle meshes."""
    lo, hi = np.atleast_2d(np.asarray(lo, float)), np.atleast_2d(np.asarray(hi, float))
    V, F = [], []
    # the 6 faces of the unit cube as corner bit-triples, CCW seen from outside
    quads = [
        [(0, 0, 0), (0, 1, 0), (1, 1, 0), (1, 0, 0)],  # z = 0, normal -z
        [(0, 0, 1), (1, 0, 1), (1, 1, 1), (0, 1, 1)],  # z = 1, normal +z
        [(0, 0, 0), (1, 0, 0), (1, 0, 1), (0, 0, 1)],  # y = 0, normal -y
        [(0, 1, 0), (0, 1, 1), (1, 1, 1), (1, 1, 0)],  # y = 1, normal +y
        [(0, 0, 0), (0, 0, 1), (0, 1, 1), (0, 1, 0)],  # x = 0, normal -x
        [(1, 0, 0), (1, 1, 0), (1, 1, 1), (1, 0, 1)],  # x = 1, normal +x
    ]
    corners = list(itertools.product((0, 1), repeat=3))
    index = {c: i for i, c in enumerate(corners)}
    tri = []
    for q in quads:
        a, b, c, d = (index[x] for x in q)
        tri += [(a, b, c), (a, c, d)]
    tri = np.array(tri)
    bits = np.array(corners, float)
    for k in range(lo.shape[0]):
        F.append(tri + 8 * k)
        V.append(lo[k] + bits * (hi[k] - lo[k]))
    return np.vstack(V), np.vstack(F).astype(np.int64)


def voxel_solid(filled, scale=(1.0, 1.0, 1.0), origin=(0.0, 0.0, 0.0)):
    """The boundary of a union of unit cells ``filled[i, j, k]`` (x, y, z) as one closed,
    outward triangle mesh (cells meeting only along an edge are not allowed)."""
    filled = np.pad(np.asarray(filled, bool), 1)
    V, F, key = [], [], {}

    def vid(p):
        if p not in key:
            key[p] = len(V)
            V.append(p)
        return key[p]

    for axis in range(3):
        u, w = (axis + 1) % 3, (axis + 2) % 3
        a = filled
        b = np.roll(filled, -1, axis=axis)  # the next cell along the axis
        for sign, cells in ((1, a & ~b), (-1, ~a & b)):  # outward +axis, -axis
            for c in np.argwhere(cells):
                base = np.array(c) - 1
                base[axis] += 1  # the face between cell c and c + e_axis
                eu, ew = np.eye(3, dtype=int)[u], np.eye(3, dtype=int)[w]
                q = [base, base + eu, base + eu + ew, base + ew]  # CCW about +axis
                q = [vid(tuple(int(x) for x in p)) for p in q]
                if sign < 0:
                    q = q[::-1]
                F += [(q[0], q[1], q[2]), (q[0], q[2], q[3])]
    V = np.array(V, float) * np.asarray(scale, float) + np.asarray(origin, float)
    return V, np.array(F, np.int64)


def floor_box_wall():
    """A floor plate, a unit box on it and a wall behind it: three separate blocks."""
    return blocks(
        [[-1.0, -1.0, -0.2], [0.0, 0.0, 0.0], [-0.5, 2.0, 0.0]],
        [[3.0, 4.0, 0.0], [1.0, 1.0, 1.0], [2.5, 2.5, 2.0]],
    )


def two_boxes():
    """Two boxes side by side on nothing, the second deeper, taller and set back: seen along
    views with zero components their edges line up on screen."""
    return blocks([[0.0, 0.0, 0.0], [1.5, 1.0, 0.0]], [[1.0, 1.0, 1.0], [2.5, 2.0, 2.0]])


def table():
    """A table: a top slab on four legs (five separate blocks) standing on a floor plate."""
    t = 0.2
    legs_lo = [[0.0, 0.0, 0.0], [2.0 - t, 0.0, 0.0], [0.0, 1.0 - t, 0.0], [2.0 - t, 1.0 - t, 0.0]]
    lo = [[-1.0, -1.0, -0.2], *legs_lo, [0.0, 0.0, 1.0]]
    hi = [[3.0, 2.0, 0.0], *[[x + t, y + t, 1.0] for x, y, _ in legs_lo], [2.0, 1.0, 1.2]]
    return blocks(lo, hi)


def l_block():
    """An L-shaped block (one closed solid of 3 x 2 x 2 cells, one corner column removed)
    before a wall."""
    cells = np.ones((3, 2, 2), bool)
    cells[1:, :, 1] = False  # the L: full height at x = 0, one cell high beyond
    return merge_meshes([voxel_solid(cells), blocks([[-1.0, 3.0, 0.0]], [[4.0, 3.5, 3.0]])])


def stairs(n=4):
    """Ordinary straight stairs of ``n`` steps (one closed solid: riser 1, tread 1, width 2)
    climbing along +y, before a wall."""
    cells = np.zeros((2, n, n), bool)
    for j in range(n):
        cells[:, j, : j + 1] = True
    return merge_meshes(
        [voxel_solid(cells), blocks([[-1.0, n + 1.0, 0.0]], [[3.0, n + 1.5, n + 1.0]])]
    )


def stair_blocks(n=4):
    """Ordinary stairs as separate blocks (each step a box from the ground), on a floor."""
    lo = [[-1.0, -1.0, -0.2]] + [[0.0, float(j), 0.0] for j in range(n)]
    hi = [[3.0, n + 1.0, 0.0]] + [[2.0, j + 1.0, j + 1.0] for j in range(n)]
    return blocks(lo, hi)


SCENES = {
    "floor_box_wall": floor_box_wall,
    "two_boxes": two_boxes,
    "table": table,
    "l_block": l_block,
    "stairs": stairs,
    "stair_blocks": stair_blocks,
}


def axis_views():
    """90 views ``(a, b, c)`` toward the camera from in front (-y) and above (+z): zero and
    equal components, many of them exact alignments of the scenes' edges."""
    return [
        (a, b, c)
        for a in (-1.0, -0.5, 0.0, 0.5, 1.0)
        for b in (-2.0, -1.0, -0.5)
        for c in (0.25, 0.5, 1.0, 1.5, 2.0, 3.0)
    ]
