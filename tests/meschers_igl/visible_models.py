"""Models of impossible figures built the way artists build them (for tests/meschers_igl/test_visible*.py).

Everything here is independent of the code under test: convex blocks from half-spaces
(scipy.spatial.HalfspaceIntersection), welded by coordinates, written as quads / STL soups.
Each builder returns the model and the depth gap(s) it was built with.
"""

from __future__ import annotations

import numpy as np
from scipy.spatial import HalfspaceIntersection

ISO_VIEW = np.array([1.0, 1.0, 1.0]) / np.sqrt(3.0)
ISO_UP = np.array([-1.0, -1.0, 2.0]) / np.sqrt(6.0)
AXES = np.eye(3)


def convex_block(halfspaces: np.ndarray, inside: np.ndarray):
    """Convex polyhedron {x : A x + b <= 0} as (V, polygons): faces outward, CCW, as n-gons."""
    hs = HalfspaceIntersection(halfspaces, inside)
    V = hs.intersections
    # merge duplicate corners (several planes through one corner)
    key = np.round(V, 9)
    _, first, inv = np.unique(key, axis=0, return_index=True, return_inverse=True)
    V = V[first]
    polys = []
    for A_b in halfspaces:
        a, b = A_b[:3], A_b[3]
        on = np.flatnonzero(np.abs(V @ a + b) <= 1e-9 * max(1.0, np.abs(V).max()))
        if on.size < 3:
            continue
        c = V[on].mean(axis=0)
        n = a / np.linalg.norm(a)
        u = V[on[0]] - c
        u /= np.linalg.norm(u)
        w = np.cross(n, u)
        ang = np.arctan2((V[on] - c) @ w, (V[on] - c) @ u)
        polys.append(on[np.argsort(ang)].tolist())  # CCW about the outward normal
    return V, polys


def bar_block(R0, R1, d_prev, d, d_next, t, cut0=None, cut1=None, view=ISO_VIEW):
    """A straight square bar from R0 to R1 (direction d, an axis), ends mitred against the
    neighbouring bars' directions; ``cut0``/``cut1`` replace an end by a plane containing the
    view direction (the impossible junction) or, with "cap", by a plane perpendicular to d."""
    d = np.asarray(d, float)
    others = [e for e in AXES if abs(e @ d) < 0.5]
    hs = []
    for e in others:  # |(p - R0) . e| <= t/2
        hs.append(np.r_[e, -(R0 @ e) - t / 2])
        hs.append(np.r_[-e, (R0 @ e) - t / 2])

    def end(R, m, sign):  # sign * (p - R) . m <= 0
        m = np.asarray(m, float)
        hs.append(np.r_[sign * m, -sign * (R @ m)])

    def normal(kind, d_other, at_start):
        if kind == "cap":
            return d
        m = (np.asarray(d_other) + d) if kind is None else None
        if kind == "view":
            m = np.asarray(d_other) + d
            m = m - (m @ view) * view
        return m

    end(R0, normal(cut0, d_prev, True), -1.0)  # (p - R0) . m >= 0
    end(R1, normal(cut1, d_next, False), 1.0)  # (p - R1) . m <= 0
    hs = np.asarray(hs)
    inside = 0.5 * (R0 + R1)
    return convex_block(hs, inside)


def ring(steps, t=1.0, split=0.5, hidden=None, view=ISO_VIEW):
    """Blocks of a ring of axis-aligned bars ``steps = [(axis vector, length), ...]`` whose sum is
    parallel to ``view`` (so the ring closes on screen but not in depth).

    The first bar is cut at ``split`` of its length: its far part starts the ring, its near part
    ends it one turn later (displaced by the gap along the view).  With ``hidden=None`` both ends
    are cut by one plane containing the view, so their cross-sections coincide on screen (the
    impossible junction); with ``hidden=(a, b)`` the ending piece stops ``a`` before the split and
    the starting piece starts ``b`` after it, both capped square (a gap for an occluder to hide).

    Returns a list of (V, polygons) blocks and the depth gap ``|sum|``."""
    d0 = np.asarray(steps[0][0], float)
    L0 = steps[0][1]
    m = d0 - (d0 @ view) * view  # cut plane containing the view
    R = [np.zeros(3)]
    for a, L in steps:
        R.append(R[-1] + np.asarray(a, float) * L)
    gap_vec = R[-1] - R[0]
    assert np.allclose(np.cross(gap_vec, view), 0)
    dirs = [np.asarray(a, float) for a, _ in steps]
    K = len(steps)
    a, b = (0.0, 0.0) if hidden is None else hidden
    cut = None if hidden is None else "cap"
    S0 = R[0] + (split * L0 + b) * d0  # start of the ring
    E = R[-1] + (split * L0 - a) * d0  # end of the ring
    blocks = [_bar(S0, R[1], d0, dirs[1], t, ("plane", m) if cut is None else ("cap",), None)]
    for k in range(1, K):
        blocks.append(_bar(R[k], R[k + 1], dirs[k], dirs[(k + 1) % K], t, None, dirs[k - 1]))
    blocks.append(
        _bar(R[K], E, d0, None, t, None, dirs[K - 1], end=("plane", m) if cut is None else ("cap",))
    )
    return blocks, float(gap_vec @ view)


def _bar(R0, R1, d, d_next, t, start, d_prev, end=None):
    """Square bar R0 -> R1 along axis d; start/end: ("plane", m), ("cap",) or None (mitre)."""
    d = np.asarray(d, float)
    hs = []
    for e in AXES:
        if abs(e @ d) > 0.5:
            continue
        hs.append(np.r_[e, -(R0 @ e) - t / 2])
        hs.append(np.r_[-e, (R0 @ e) - t / 2])
    # start: (p - R0) . m >= 0
    if start is None:
        m0 = np.asarray(d_prev) + d
    elif start[0] == "cap":
        m0 = d
    else:
        m0 = start[1] if start[1] @ d > 0 else -start[1]
    hs.append(np.r_[-m0, m0 @ R0])
    if end is None:
        m1 = d + np.asarray(d_next)
    elif end[0] == "cap":
        m1 = d
    else:
        m1 = end[1] if end[1] @ d > 0 else -end[1]
    hs.append(np.r_[m1, -(m1 @ R1)])
    return convex_block(np.asarray(hs), 0.5 * (R0 + R1))


def weld_blocks(blocks, drop_internal=True):
    """One welded polygon mesh from touching blocks: coincident faces (the mitres between
    blocks) are removed, vertices merged by coordinates."""
    V = np.vstack([b[0] for b in blocks])
    offs = np.cumsum([0] + [b[0].shape[0] for b in blocks])
    polys = [[i + offs[k] for i in p] for k, b in enumerate(blocks) for p in b[1]]
    key = np.round(V, 9)
    _, first, inv = np.unique(key, axis=0, return_index=True, return_inverse=True)
    Vw = V[first]
    polys = [[int(inv[i]) for i in p] for p in polys]
    if drop_internal:
        sig = {}
        for i, p in enumerate(polys):
            sig.setdefault(tuple(sorted(p)), []).append(i)
        drop = {i for ids in sig.values() if len(ids) > 1 for i in ids}
        polys = [p for i, p in enumerate(polys) if i not in drop]
    return Vw, polys


def separate_blocks(blocks):
    """Blocks as separate closed parts of one mesh (no welding)."""
    V = np.vstack([b[0] for b in blocks])
    offs = np.cumsum([0] + [b[0].shape[0] for b in blocks])
    return V, [[i + offs[k] for i in p] for k, b in enumerate(blocks) for p in b[1]]


def triangulate(polys):
    """Fan triangulation of convex polygons."""
    return np.array([[p[0], p[i], p[i + 1]] for p in polys for i in range(1, len(p) - 1)], np.int64)


def soup(V, F):
    """An unwelded STL-like triangle soup (every face its own three vertices, float32)."""
    Vs = V[F].reshape(-1, 3).astype(np.float32).astype(np.float64)
    return Vs, np.arange(Vs.shape[0], dtype=np.int64).reshape(-1, 3)


def write_obj(path, V, polys):
    with open(path, "w") as fh:
        fh.writelines(f"v {x:.17g} {y:.17g} {z:.17g}\n" for x, y, z in V)
        fh.writelines("f " + " ".join(str(i + 1) for i in p) + "\n" for p in polys)
    return path


def write_stl(path, V, F):
    """ASCII STL soup (float32 as STL stores it)."""
    T = V[F]
    n = np.cross(T[:, 1] - T[:, 0], T[:, 2] - T[:, 0])
    n /= np.linalg.norm(n, axis=1, keepdims=True)
    with open(path, "w") as fh:
        fh.write("solid m\n")
        for k in range(F.shape[0]):
            fh.write(f" facet normal {n[k, 0]:e} {n[k, 1]:e} {n[k, 2]:e}\n  outer loop\n")
            for c in range(3):
                x, y, z = (float(np.float32(a)) for a in T[k, c])
                fh.write(f"   vertex {x:.9g} {y:.9g} {z:.9g}\n")
            fh.write("  endloop\n endfacet\n")
        fh.write("endsolid m\n")
    return path


# ------------------------------------------------------------------------------ the figures
def u_tribar(L=4.0, t=1.0):
    """Penrose tribar as one closed (capped) solid: bars +x, +y, +z of length L seen along
    (1,1,1), opened in the middle of the x bar by a plane containing the view and capped
    there (a U-shaped solid whose two ends line up on screen).  Gap L * sqrt(3)."""
    blocks, gap = ring([(AXES[0], L), (AXES[1], L), (AXES[2], L)], t)
    V, polys = weld_blocks(blocks)
    return V, polys, gap


def block_stairs(L=2.0, t=1.0):
    """A Penrose-stair ring of four separate closed blocks (+x 3L, +y 2L, -x L, +z 2L; the last
    block carries the near half of the first flight): each block touches the next along a
    mitre; the last lines up on screen with the first, one turn higher by 2 L sqrt(3) along the
    view."""
    blocks, gap = ring([(AXES[0], 3 * L), (AXES[1], 2 * L), (-AXES[0], L), (AXES[2], 2 * L)], t)
    blocks = blocks[:3] + [weld_blocks(blocks[3:])]
    V, polys = separate_blocks(blocks)
    return V, polys, gap


def hidden_gap_frame(L=6.0, t=1.0, hole=0.6):
    """A tribar frame whose x bar is broken (ends capped square, ``hole`` apart on screen), the
    gap hidden behind a crossing bar placed nearer the viewer; the pieces differ in depth by
    L sqrt(3).  Two closed parts: the frame and the crossing bar."""
    blocks, gap = ring([(AXES[0], L), (AXES[1], L), (AXES[2], L)], t, hidden=(hole / 2, hole / 2))
    frame = weld_blocks(blocks)
    # the crossing bar: along z (screen up-ish) through the gap's middle, moved 2L toward the
    # viewer so it is in front of both pieces; thick enough to hide the caps
    c = np.array([0.5 * L, 0.0, 0.0]) + 2.0 * L * ISO_VIEW
    w, dy, h = hole + 2.0 * t, 0.5 * t, 0.6 * L
    hs = np.array(
        [
            [1, 0, 0, -(c[0] + w / 2)],
            [-1, 0, 0, c[0] - w / 2],
            [0, 1, 0, -(c[1] + dy)],
            [0, -1, 0, c[1] - dy],
            [0, 0, 1, -(c[2] + h)],
            [0, 0, -1, c[2] - h],
        ],
        float,
    )
    occ = convex_block(hs, c)
    V, polys = separate_blocks([frame, occ])
    return V, polys, gap


def read_obj(path):
    """(V, F) of an OBJ file, polygons fanned into triangles (a test-side reader)."""
    V, F = [], []
    for line in open(path):
        t = line.split()
        if not t:
            continue
        if t[0] == "v":
            V.append([float(x) for x in t[1:4]])
        elif t[0] == "f":
            idx = [int(x.split("/")[0]) - 1 for x in t[1:]]
            F += [[idx[0], idx[i], idx[i + 1]] for i in range(1, len(idx) - 1)]
    return np.asarray(V), np.asarray(F, dtype=np.int64)


def sheared_tribar_torus(L=4.0, t=1.0):
    """A real closed torus that looks like a Penrose tribar (a sheared trick).

    The tribar ring (x, y, z bars seen along (1,1,1), opened in the x bar) is cut into blocks at
    its mitres and across the z bar's middle; each block is moved along the view by
    ``-gap * s(p)`` with ``s`` affine per block: 0 on the first x piece, 1 on the last one, and
    continuous across every interface plane (``s`` changes by multiples of the interface's own
    affine function).  Screen positions do not change, every face stays planar, and the last
    piece lands exactly on the first: the ring closes into a torus.  Returns (V, polygons,
    gap): a person assuming right angles perceives the tribar and its period ``gap``."""
    x, y, z = AXES
    v = ISO_VIEW
    m = x - (x @ v) * v
    R0 = np.zeros(3)
    R1, R2, R3 = R0 + L * x, R0 + L * x + L * y, R0 + L * (x + y + z)
    gap = float((R3 - R0) @ v)
    Rm = 0.5 * (R2 + R3)
    S0, E = R0 + 0.5 * L * x, R3 + 0.5 * L * x
    blocks = [
        _bar(S0, R1, x, y, t, ("plane", m), None),
        _bar(R1, R2, y, z, t, None, x),
        _bar(R2, Rm, z, None, t, None, y, end=("cap",)),
        _bar(Rm, R3, z, x, t, ("cap",), None),
        _bar(R3, E, x, None, t, None, z, end=("plane", m)),
    ]
    lam_a = lambda p: (p - R1) @ (x + y)  # noqa: E731  (the mitre at R1)
    lam_m = lambda p: (p - R2) @ (y + z)  # noqa: E731  (the mitre at R2)
    lam_c = lambda p: (p - Rm) @ z  # noqa: E731  (across the z bar)
    # alpha lam_a + beta lam_m + gamma lam_c == 1 on the mitre plane at R3 (normal z + x)
    P = np.array([R3, R3 + (x - z), R3 + y])
    A = np.stack([np.array([lam_a(p), lam_m(p), lam_c(p)]) for p in P])
    al, be, ga = np.linalg.solve(A, np.ones(3))
    s_of = [
        lambda p: 0.0 * p[:, 0],
        lambda p: al * lam_a(p),
        lambda p: al * lam_a(p) + be * lam_m(p),
        lambda p: al * lam_a(p) + be * lam_m(p) + ga * lam_c(p),
        lambda p: 1.0 + 0.0 * p[:, 0],
    ]
    moved = [(Vb - gap * s(Vb)[:, None] * v, Pb) for (Vb, Pb), s in zip(blocks, s_of)]
    V, polys = weld_blocks(moved)
    return V, polys, gap


def box_block(lo, hi):
    """An axis-aligned box [lo, hi] as (V, polygons) (outward quads)."""
    lo, hi = np.asarray(lo, float), np.asarray(hi, float)
    hs = np.array([np.r_[a, -(hi @ a)] for a in AXES] + [np.r_[-a, lo @ a] for a in AXES])
    return convex_block(hs, 0.5 * (lo + hi))


def hidden_gap_cube(L=6.0, t=1.0, hole=0.6, split=0.5):
    """The impossible cube as a real closed frame whose impossible bar is broken behind a
    crossing bar (a "closed genus-3 frame"), seen along (1, 1, 1).

    A box frame has 12 square bars over the corners {0, L}^3; seen along the diagonal its near
    corner N = (L, L, L) and far corner O = 0 coincide on screen.  The impossible cube replaces
    N's three bars by one: the y bar from (L, 0, L) runs on through N's place (the "extension"),
    and on screen it continues into the far y bar from (0, L, 0) toward O, which is one turn
    deeper by N - O = L (1, 1, 1), a depth of L sqrt(3) along the view.  Here the two pieces
    stop short (square caps, ``hole`` apart on screen, the far piece at y = L/2 + hole/2, the
    near one at y = 3L/2 - hole/2) and a crossing bar nearer the viewer hides the gap; a viewer
    completes one straight bar behind it (amodal completion).  (A box frame with all 12 bars
    and one of them broken cannot hide an offset: its other 11 axis-aligned bars keep the two
    pieces on one 3D line.  Which is why the impossible cube drops N.)

    Corners are t-cubes, bars are boxes between them, welded where they touch: the frame is
    one closed solid of genus 3 (7 corners, 9 bars); the crossing bar is a second closed part.
    Returns (V, polygons, gap) with gap = L sqrt(3).
    """
    h = t / 2
    corners = [
        np.array(c, float) * L
        for c in [(0, 0, 0), (1, 0, 0), (0, 1, 0), (0, 0, 1), (1, 1, 0), (1, 0, 1), (0, 1, 1)]
    ]
    blocks = [box_block(c - h, c + h) for c in corners]
    key = {tuple(np.round(c / L).astype(int)): c for c in corners}
    bars = [
        ((0, 0, 0), (1, 0, 0)),
        ((0, 0, 0), (0, 0, 1)),
        ((1, 0, 0), (1, 1, 0)),
        ((1, 0, 0), (1, 0, 1)),
        ((0, 1, 0), (1, 1, 0)),
        ((0, 1, 0), (0, 1, 1)),
        ((0, 0, 1), (1, 0, 1)),
        ((0, 0, 1), (0, 1, 1)),
    ]
    for a, b in bars:  # a box between the two corner cubes
        A, B = key[a], key[b]
        d = (B - A) / L
        lo, hi = np.minimum(A, B) - h, np.maximum(A, B) + h
        lo, hi = lo + t * np.abs(d), hi - t * np.abs(d)
        blocks.append(box_block(lo, hi))
    y = AXES[1]
    XZ, Y = key[(1, 0, 1)], key[(0, 1, 0)]
    # the near piece: from the (L, 0, L) corner along +y, through N's place, capped
    blocks.append(
        box_block(XZ + h * y - h * (1 - y), XZ + ((1 + split) * L - hole / 2) * y + h * (1 - y))
    )
    # the far piece: from the (0, L, 0) corner along -y, capped
    blocks.append(
        box_block(Y - ((1 - split) * L - hole / 2) * y - h * (1 - y), Y - h * y + h * (1 - y))
    )
    frame = weld_blocks(blocks)
    # the crossing bar: a square bar along z through the gap's screen middle, 2 L sqrt(3)
    # nearer than the far piece (in front of everything), wide enough to hide the gap and the
    # near piece's square cap
    c = np.array([0.0, split * L, 0.0]) + 2.0 * L * np.sqrt(3.0) * ISO_VIEW
    s, hz = hole + t, 0.6 * L
    occ = box_block(c - np.array([s / 2, s / 2, hz]), c + np.array([s / 2, s / 2, hz]))
    V, polys = separate_blocks([frame, occ])
    return V, polys, float(L * np.sqrt(3.0))


def convert_quietly(V, F, view, up=(0.0, 0.0, 1.0)):
    """``model_to_mescher`` from the unit ``view`` with its warnings silenced, and the periods
    above 1e-6 of the size: (m, order, report, |periods|)."""
    import warnings

    from meschers_igl.errors import MescherWarning
    from meschers_igl.obtain import model_to_mescher

    v = np.asarray(view, float)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", MescherWarning)
        m, order, report = model_to_mescher(V, F, view=v / np.linalg.norm(v), up=up)
    p = np.abs(np.asarray(m.periods()))
    return m, order, report, p[p > 1e-6 * m.scale()]
