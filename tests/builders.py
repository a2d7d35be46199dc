"""Mesh builders shared by test modules (tori, impossible tubes, slivers, obtuse sheets) and
the exact-distance oracle on ordinary meshes (``igl.exact_geodesic``)."""

from __future__ import annotations

import igl
import numpy as np

from meschers_igl import Mescher


def grid_faces(nu: int, nv: int) -> np.ndarray:
    """Faces of an nu x nv grid periodic in both directions (a torus)."""
    i, j = np.meshgrid(np.arange(nu), np.arange(nv), indexing="ij")
    jn = (j + 1) % nv
    a = i * nv + j
    b = ((i + 1) % nu) * nv + j
    c = ((i + 1) % nu) * nv + jn
    d = i * nv + jn
    return np.r_[np.c_[a.ravel(), b.ravel(), c.ravel()], np.c_[a.ravel(), c.ravel(), d.ravel()]]


def _tube(nu, nv, R, profile):
    """A tube around the z axis: (radial offset, height) of the cross-section from ``profile``."""
    u = 2 * np.pi * np.arange(nu) / nu
    rho, h = profile(np.arange(nv) / nv)
    U = np.repeat(u, nv)
    rr, hh = np.tile(rho, nu), np.tile(h, nu)
    xy = np.c_[(R + rr) * np.cos(U), (R + rr) * np.sin(U)]
    return grid_faces(nu, nv), xy, hh, np.repeat(np.arange(nu), nv)


def circle_profile(r):
    return lambda s: (r * np.cos(2 * np.pi * s), r * np.sin(2 * np.pi * s))


def square_profile(a):
    """A square of half-size ``a`` traversed at unit speed in s in [0, 1)."""

    def prof(s):
        t = (4 * s) % 4
        side, f = np.floor(t).astype(int), t - np.floor(t)
        x = np.choose(side, [a - 2 * a * f, -a + 0 * f, -a + 2 * a * f, a + 0 * f])
        y = np.choose(side, [a + 0 * f, a - 2 * a * f, -a + 0 * f, -a + 2 * a * f])
        return x, y

    return prof


def impossible_tube(nu=48, nv=16, R=2.0, profile=None, c=1.5):
    """A tube whose depth climbs by ``c`` per turn around the hole: impossible for ``c != 0``.

    Depth ``z = z0(v) + c u / 2 pi`` on the unrolled strip; the mescher is one turn, with the
    wrap-around edges taking the unrolled depth differences (the helix's ramp).
    """
    F, xy, z0, col = _tube(nu, nv, R, profile or circle_profile(0.7))
    Zv = z0 + c * col / nu
    Zc = Zv[F]
    cc = col[F]
    Zc = Zc + c * ((cc == 0) & (cc.max(axis=1, keepdims=True) == nu - 1))
    return Mescher.from_corner_depths(F, xy, Zc)


def ordinary_torus(nu=48, nv=16, R=2.0, r=0.7):
    F, xy, z0, _ = _tube(nu, nv, R, circle_profile(r))
    return np.c_[xy, z0], F.astype(np.int64)


def obtuse_sheet(nx=40, ny=40):
    """A height field on a sheared grid: most triangles have an angle near 150 degrees."""
    i, j = np.meshgrid(np.arange(nx), np.arange(ny), indexing="ij")
    x = (i + 0.9 * (j % 2)) / nx * 2.0
    y = 2.1 * j / ny
    V = np.c_[x.ravel(), y.ravel(), (0.3 * np.sin(2 * x) * np.cos(1.5 * y)).ravel()]
    a = (i[:-1, :-1] * ny + j[:-1, :-1]).ravel()
    b, c, d = a + ny, a + ny + 1, a + 1
    return V, np.r_[np.c_[a, b, c], np.c_[a, c, d]].astype(np.int64)


def sliver_box(size=(2.0, 1.0, 0.5), k=24, cluster=40, spacing=7e-5):
    """A CAD-like box tessellated with fans of slivers (a closed mesh).

    The three sides at corner 7 are fans from their opposite corner over points on the box
    edges at 7 (``k - 1`` per edge); edge 6-7 also carries a tight cluster whose fan angles are
    about ``spacing / 2`` rad (0.003 degrees).  The other three sides are two triangles each.
    """
    sx, sy, sz = size
    C = np.array([[x, y, z] for z in (0, sz) for y in (0, sy) for x in (0, sx)], float)
    ts = np.linspace(0, 1, k + 1)[1:-1]
    tc = 0.5 + spacing * (np.arange(cluster) - cluster / 2)
    pts, ids, nxt = [C], {}, 8
    for i, j in ((5, 7), (6, 7), (3, 7)):
        t = np.unique(np.r_[ts, tc]) if (i, j) == (6, 7) else ts
        pts.append(C[i] + t[:, None] * (C[j] - C[i]))
        ids[(i, j)] = np.arange(nxt, nxt + t.size)
        ids[(j, i)] = ids[(i, j)][::-1]
        nxt += t.size
    V = np.concatenate(pts)
    sides = [(0, 2, 3, 1), (4, 5, 7, 6), (0, 1, 5, 4), (2, 6, 7, 3), (0, 4, 6, 2), (1, 3, 7, 5)]
    F = []
    for cyc in sides:  # six sides
        s = (cyc.index(7) + 2) % 4 if 7 in cyc else 0
        cyc = cyc[s:] + cyc[:s]
        ring = []
        for a, b in zip(cyc, cyc[1:] + cyc[:1]):
            ring += [a, *ids.get((a, b), [])]
        F += [(ring[0], p, q) for p, q in zip(ring[1:-1], ring[2:])]
    return V, np.array(F, dtype=np.int64)


def exact(V, F, s):
    return igl.exact_geodesic(V, F, VS=np.atleast_1d(s).astype(np.int64), VT=np.arange(len(V)))


def mean_rel(d, de):
    mk = de > 0
    return float(np.mean(np.abs(d[mk] - de[mk]) / de[mk]))


def cad_prism(outline, height, fan_from=0, rings=1):
    """A CAD-style extrusion of a closed counter-clockwise outline ``(k, 2)``: side quads split
    in two (thin where the outline's edges are short), caps triangulated as fans from outline
    vertex ``fan_from`` (as STL exporters do: slivers and very obtuse triangles)."""
    k = len(outline)
    zs = np.linspace(0.0, height, rings + 1)
    V = np.concatenate([np.c_[outline, np.full(k, z)] for z in zs])
    i = np.arange(k)
    side = []
    for r in range(rings):
        a, b = r * k + i, r * k + (i + 1) % k
        side += [np.c_[a, b, b + k], np.c_[a, b + k, a + k]]
    j = np.arange(1, k - 1)
    p, q, s = np.full(k - 2, fan_from), (fan_from + j) % k, (fan_from + j + 1) % k
    caps = [np.c_[p, s, q], rings * k + np.c_[p, q, s]]
    return V, np.concatenate(side + caps).astype(np.int64)


def rounded_rectangle(a, b, r, segments):
    """Outline of the rectangle ``[-a, a] x [-b, b]`` with corners rounded at radius ``r``."""
    pts = []
    for cx, cy, t0 in (
        (a - r, b - r, 0),
        (-a + r, b - r, 90),
        (-a + r, -b + r, 180),
        (a - r, -b + r, 270),
    ):
        t = np.radians(np.linspace(t0, t0 + 90, segments + 1))
        pts.append(np.c_[cx + r * np.cos(t), cy + r * np.sin(t)])
    return np.concatenate(pts)


def chamfered_rectangle(a, b, w):
    """Outline of the rectangle ``[-a, a] x [-b, b]`` with its corners cut at width ``w``."""
    return np.array(
        [
            (a, -b + w),
            (a, b - w),
            (a - w, b),
            (-a + w, b),
            (-a, b - w),
            (-a, -b + w),
            (-a + w, -b),
            (a - w, -b),
        ]
    )


def box_mesh(lo, hi):
    """The closed box ``[lo, hi]`` (12 outward triangles)."""
    lo, hi = np.asarray(lo, float), np.asarray(hi, float)
    V = np.array(
        [[x, y, z] for x in (lo[0], hi[0]) for y in (lo[1], hi[1]) for z in (lo[2], hi[2])]
    )
    F = np.array(
        "0 1 3 0 3 2 4 6 7 4 7 5 0 4 5 0 5 1 2 3 7 2 7 6 0 2 6 0 6 4 1 5 7 1 7 3".split(), int
    ).reshape(-1, 3)
    T = V[F]
    if np.einsum("ij,ij->", T[:, 0], np.cross(T[:, 1], T[:, 2])) < 0:
        F = F[:, [0, 2, 1]]
    return V, F


def merge_meshes(parts):
    """One mesh of several ``(V, F)`` parts (not welded)."""
    Vs, Fs, n = [], [], 0
    for V, F in parts:
        Vs.append(V)
        Fs.append(F + n)
        n += V.shape[0]
    return np.vstack(Vs), np.vstack(Fs)


def ordinary_stairs(n=6, seed=0):
    """An ordinary straight staircase as one closed solid: its side profile extruded."""
    import triangle as tr

    prof = [(0.0, 0.0)]
    for k in range(n):
        prof += [(k, k + 1.0), (k + 1.0, k + 1.0)]
    prof += [(float(n), 0.0)]
    P = np.asarray(prof)
    m = P.shape[0]
    V = np.vstack([np.c_[P[:, 0], np.zeros(m), P[:, 1]], np.c_[P[:, 0], np.full(m, 3.0), P[:, 1]]])
    seg = np.c_[np.arange(m), (np.arange(m) + 1) % m]
    T = np.asarray(tr.triangulate({"vertices": P, "segments": seg}, "pQ")["triangles"])
    sides = []
    for i in range(m):
        j = (i + 1) % m
        sides += [[i, j, j + m], [i, j + m, i + m]]
    F = np.vstack([T, T[:, ::-1] + m, np.asarray(sides)])
    Tv = V[F]
    if np.einsum("ij,ij->", Tv[:, 0], np.cross(Tv[:, 1], Tv[:, 2])) < 0:
        F = F[:, [0, 2, 1]]
    return V, F


def tilted_view(view, degrees, seed):
    """``view`` turned by ``degrees`` about a random axis perpendicular to it (Rodrigues)."""
    a = np.random.default_rng(seed).normal(size=3)
    a -= (a @ view) * view
    a /= np.linalg.norm(a)
    t = np.radians(degrees)
    return np.cos(t) * view + np.sin(t) * np.cross(a, view)
