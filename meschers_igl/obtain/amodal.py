"""Amodal completion: occluded pieces of one bar that line up across an occluder are bridged
behind it (a hidden gap: its depth offset becomes a period)."""

from __future__ import annotations

import igl
import numpy as np

from ..geometry2d import overlapping_pairs, polygon_triangles
from .clip import plane_depth
from .glue import he_depth, interior_edges
from .records import Glue, Junction


def _chains(xy, Fa, hs):
    """Connected chains of half-edges ``hs`` (each as its ordered vertex list, tail first)."""
    if hs.size == 0:
        return []
    f, k = hs // 3, hs % 3
    p, q = Fa[f, (k + 1) % 3], Fa[f, (k + 2) % 3]
    nxt = dict(zip(p.tolist(), q.tolist()))
    heads = set(q.tolist())
    out = []
    for start in p.tolist():  # a few occluded edges per junction
        if start in heads:
            continue
        ch = [start]
        while ch[-1] in nxt and len(ch) <= hs.size:
            ch.append(nxt[ch[-1]])
        out.append(ch)
    return out


def _on_visible_edges(poly, tri, A, B, Fa: np.ndarray) -> bool:
    """Does a triangle of the strip ``poly`` (triangulated as ``tri``) have an edge, other than
    one of the chains' own edges ``A`` and ``B``, that is already an edge of the visible map
    ``Fa``?  Such a strip runs along a visible edge, not behind the occluder (edges of a scene
    that coincide exactly, seen along an axis): bridging it would give that edge a third face."""
    own = {tuple(sorted(p)) for C in (A, B) for p in zip(C[:-1], C[1:])}
    t = np.asarray([[poly[i] for i in tr] for tr in tri], dtype=np.int64)
    e = np.sort(t[:, [0, 1, 1, 2, 2, 0]].reshape(-1, 2), axis=1)
    e = np.array([p for p in map(tuple, e.tolist()) if p not in own], dtype=np.int64)
    if e.size == 0:
        return False
    n = np.int64(max(int(Fa.max(initial=0)), int(e.max())) + 1)
    fe = np.sort(Fa[:, [0, 1, 1, 2, 2, 0]].reshape(-1, 2), axis=1)
    return bool(np.isin(e[:, 0] * n + e[:, 1], fe[:, 0] * n + fe[:, 1]).any())


def bridge_hidden_gaps(xy, Fa, src, Z, pl, N, glue, arcs, fe, tol, Tm, model=None):
    """Amodal completion: bridge occluded pieces that line up across an occluder.

    Occluded edges (far side of a true occlusion where the far surface continues) are grouped
    into chains per source plane orientation.  Chains ``A`` and ``B`` of equal normals are
    bridged when the strip between them is a quadrilateral whose sides are parallel to an edge
    of ``A``'s source face (the bar's own edge lines continue behind the occluder) and which is
    hidden behind visible faces nearer than both planes.  The strip is triangulated, takes
    ``A``'s plane (so it is continuous with ``A``) and is glued to ``B`` across the depth
    offset, which becomes a period.  Each bridge face gets arcs to the visible faces in front.
    """
    import shapely

    nf = Fa.shape[0]
    none = (Fa, src, Z, np.zeros(nf, dtype=bool), glue, arcs, [])
    occ = fe.occluded
    if occ.size < 2:
        return none
    n_unit = N / np.linalg.norm(N, axis=1, keepdims=True)
    # group occluded half-edges by the orientation of their source face
    nk = np.round(n_unit[src[occ // 3]] / 1e-6).astype(np.int64)
    _, grp = np.unique(nk, axis=0, return_inverse=True)
    grp = grp.reshape(-1)
    chains = []  # (group, vertex list, source face)
    for g in np.unique(grp).tolist():
        for ch in _chains(xy, Fa, occ[grp == g]):
            he = occ[grp == g]
            f0 = he[Fa[he // 3, (he % 3 + 1) % 3] == ch[0]][0] // 3
            chains.append((g, ch, int(src[f0])))
    T = xy[Fa]
    new_faces, new_src, bridges, used = [], [], [], set()
    for ia, (ga, A, sa) in enumerate(chains):  # few chains
        best = None
        for ib, (gb, B, sb) in enumerate(chains):
            if ib == ia or gb != ga or ia in used or ib in used:
                continue
            a0, a1, b0, b1 = xy[A[0]], xy[A[-1]], xy[B[0]], xy[B[-1]]
            s0, s1 = b1 - a0, b0 - a1  # the strip's sides
            L0, L1 = np.linalg.norm(s0), np.linalg.norm(s1)
            if L0 <= tol or L1 <= tol or abs(cross2(s0, s1)) > tol * (L0 + L1):
                continue
            da = a1 - a0
            if cross2(da, s0) >= 0:  # the strip must lie to the right of A (outside its face)
                continue
            if not (_parallel_to_edge(s0, Tm[sa], tol) or _parallel_to_edge(s0, Tm[sb], tol)):
                continue
            poly = [*A[::-1], *B[::-1]]
            ring = shapely.Polygon(xy[poly])
            if not ring.is_valid or ring.area <= tol * (L0 + L1):  # not a simple strip
                continue
            c = xy[poly].mean(axis=0)
            gap = float(plane_depth(c, pl[sb]) - plane_depth(c, pl[sa]))
            if not strip_hidden(xy[poly], pl[sa], pl[sb], T, Z, tol):
                continue
            plane = sa  # the strip continues A's plane (glued to B across the gap) ...
            if model is not None:
                # ... and must run through empty space, not through a block lying between the
                # pieces or through the occluder (libigl's generalized winding number, camera
                # coordinates); else it continues B's plane, if that one is free
                P = c[None]  # the strip's middle (its rim touches the pieces' surfaces)
                plane = None
                for s_ in (sa, sb):
                    P3 = np.c_[P, plane_depth(P, pl[s_])]
                    if np.all(np.abs(igl.winding_number(model[0], model[1], P3)) <= 0.5):
                        plane = s_
                        break
                if plane is None:
                    continue
            if best is None or L0 < best[0]:
                best = (L0, ib, poly, sb, gap, plane)
        if best is None:
            continue
        _, ib, poly, sb, gap, plane = best
        P = xy[poly]
        tri = polygon_triangles(P)
        tri = None if tri is None else tri.tolist()
        if tri is None or _on_visible_edges(poly, tri, chains[ia][1], chains[ib][1], Fa):
            continue
        used |= {ia, ib}
        new_faces += [[poly[i] for i in t] for t in tri]
        new_src += [plane] * len(tri)
        kind = "hidden gap" if abs(gap) > tol else "occluded continuation"
        bridges.append(Junction(kind, P.mean(axis=0), abs(gap), len(poly) // 2))
    if not new_faces:
        return none
    Fb = np.vstack([Fa, np.asarray(new_faces, dtype=np.int64)])
    sb_all = np.concatenate([src, np.asarray(new_src, dtype=np.int64)])
    is_bridge = np.r_[np.zeros(nf, dtype=bool), np.ones(len(new_faces), dtype=bool)]
    Zb = plane_depth(xy[Fb], pl[sb_all][:, None, :])
    # glue: bridge half-edges to the occluded half-edges they run against, and to each other
    bh = np.arange(3 * nf, 3 * Fb.shape[0])
    bp, bq = Fb[bh // 3, (bh % 3 + 1) % 3], Fb[bh // 3, (bh % 3 + 2) % 3]
    op, oq = Fa[occ // 3, (occ % 3 + 1) % 3], Fa[occ // 3, (occ % 3 + 2) % 3]
    key_o = dict(zip(zip(oq.tolist(), op.tolist()), occ.tolist()))
    g1, g2 = [], []
    for h, u, v in zip(bh.tolist(), bp.tolist(), bq.tolist()):
        if (u, v) in key_o:
            g1.append(h)
            g2.append(key_o[(u, v)])
    h1b, h2b, _ = interior_edges(Fb[nf:], xy.shape[0])
    h1b, h2b = h1b + 3 * nf, h2b + 3 * nf
    zc = np.abs(he_depth(Zb, h1b) - he_depth(Zb, h2b)[:, ::-1]).max(axis=1) <= tol
    g1 += h1b[zc].tolist()
    g2 += h2b[zc].tolist()
    glue = Glue(
        np.concatenate([glue.h1, g1]).astype(np.int64),
        np.concatenate([glue.h2, g2]).astype(np.int64),
        np.concatenate([glue.glued, np.ones(len(g1), dtype=bool)]),
        np.concatenate([glue.continuous, np.zeros(len(g1), dtype=bool)]),
    )
    # bridge faces lie behind the visible faces they overlap on screen
    Tb = xy[Fb]
    pairs, _ = overlapping_pairs(Tb, tol)
    mixed = is_bridge[pairs[:, 0]] != is_bridge[pairs[:, 1]]
    pr = pairs[mixed]
    behind = np.where(is_bridge[pr[:, 0]], pr[:, 0], pr[:, 1])
    front = np.where(is_bridge[pr[:, 0]], pr[:, 1], pr[:, 0])
    arcs = np.vstack([arcs, np.stack([behind, front], axis=1)]).astype(np.int64)
    return Fb, sb_all, Zb, is_bridge, glue, arcs, bridges


def cross2(a, b) -> float:
    return float(a[0] * b[1] - a[1] * b[0])


def _parallel_to_edge(s, tri, tol) -> bool:
    """Is screen direction ``s`` parallel to an edge of the screen triangle ``tri`` (3, 2)?
    (A bar's model face has its long edges along the bar: the strip continues them.)"""
    E = tri[[1, 2, 0]] - tri
    L = np.linalg.norm(E, axis=1)
    c = np.abs(E[:, 0] * s[1] - E[:, 1] * s[0]) / np.maximum(L, 1e-300) / np.linalg.norm(s)
    return bool(np.any((c <= 1e-6) & (L > tol)))


def strip_hidden(P, pla, plb, T, Z, tol) -> bool:
    """Is the polygon ``P`` covered by visible faces nearer than both planes (sample points)?"""
    from ..geometry2d import barycentric

    c = P.mean(axis=0)
    pts = np.vstack([c, 0.5 * (P + c)])
    for x in pts:  # a handful of sample points
        B = barycentric(np.repeat(x[None], T.shape[0], 0), T)
        inside = np.all(B >= -1e-9, axis=1)
        if not inside.any():
            return False
        z = (B[inside] * Z[inside]).sum(axis=1).max()
        if z <= max(plane_depth(x, pla), plane_depth(x, plb)) + tol:
            return False
    return True
