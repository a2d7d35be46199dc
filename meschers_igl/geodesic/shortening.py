"""Geodesics shortened from candidate paths: a path traced down a distance field (or along
edges) is pulled taut and swung around the vertices it bends at until it is locally shortest
(FlipOut's wedge condition), then tried past nearby cone vertices.

These give *a* geodesic, not always the shortest one (another homotopy class can be shorter);
:func:`~meschers_igl.geodesic.shortest_path` uses them only when tracing back through the exact
field fails, and :func:`~meschers_igl.geodesic.shortest_loops` to tighten loops.
"""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp
import scipy.sparse.csgraph as csgraph

from .. import intrinsic
from ..errors import MescherError
from .unfold import _MeshData, _taut


def _trace(md: _MeshData, d: np.ndarray, target: int, is_src: np.ndarray) -> list[tuple]:
    """Trace from ``target`` down ``-grad d``; return strips ``(v_start, faces, v_end)``.

    A strip is a sequence of faces that consecutive ones share an edge, entered at a vertex
    and left at a vertex; strips break where the trace meets a vertex (valleys of ``d``, where
    the field on both sides of an edge points at the edge, and boundaries are followed along
    the edge).  Hand-written: a sequential walk of O(path length) steps; no library traces
    barycentric rays across faces.
    """
    F, K, opp = md.F, md.K, md.opp
    eps = 1e-12
    strips: list[tuple] = []
    v = int(target)
    max_steps = 4 * F.shape[0] + 16
    steps = 0
    visited_vertices = {v}
    while not is_src[v]:
        fan = md.faces_of(v)
        # a face of the fan that holds a source: go straight to it
        hit = fan[is_src[F[fan]].any(axis=1)]
        if hit.size:
            f = int(hit[0])
            s = int(F[f][is_src[F[f]]][0])
            strips.append((v, [f], s))
            return strips
        # descent wedge: moving from corner c along -grad d enters the face
        corner = np.argmax(F[fan] == v, axis=1)
        W = -np.einsum("fij,fj->fi", K[fan], d[F[fan]])
        wc = W[np.arange(fan.size), corner]
        others = W.copy()
        others[np.arange(fan.size), corner] = np.inf
        ok = (wc < 0) & (others.min(axis=1) >= -eps * np.abs(W).max(axis=1))
        if ok.any():
            f = int(fan[np.flatnonzero(ok)[np.argmin(wc[ok])]])
            b = np.zeros(3)
            b[F[f] == v] = 1.0
            faces = [f]
            v_end = None
            while v_end is None:
                steps += 1
                if steps > max_steps:
                    raise MescherError(
                        "target: the trace down the distance gradient did not reach the source"
                    )
                w = -K[f] @ d[F[f]]
                neg = w < 0
                s_exit = np.where(neg, -b / np.where(neg, w, -1.0), np.inf)
                s_exit[b <= eps] = np.where(neg[b <= eps], 0.0, np.inf)
                i = int(np.argmin(s_exit))
                if s_exit[i] == 0.0 or not np.isfinite(s_exit[i]):
                    # valley or stationary: follow the edge we are on to its lower end
                    v_end = _lower_end(F[f], b, d)
                    break
                b = np.maximum(b + s_exit[i] * w, 0.0)
                b[i] = 0.0
                b /= b.sum()
                if (b > 1.0 - 1e-9).any():  # reached a corner
                    v_end = int(F[f][np.argmax(b)])
                    break
                g = int(opp[f, i])
                if g < 0:  # boundary: slide along it to the lower end
                    v_end = _lower_end(F[f], b, d)
                    break
                # express b in g: the edge's two vertices keep their weights
                bg = np.zeros(3)
                for c in range(3):  # three corners
                    bg[c] = b[F[f] == F[g, c]].sum() if (F[f] == F[g, c]).any() else 0.0
                faces.append(g)
                src_g = is_src[F[g]]
                if src_g.any():
                    v_end = int(F[g][src_g][0])
                    break
                wg = -K[g] @ d[F[g]]
                ig = int(np.argmax(bg == 0.0))
                if wg[ig] < 0:  # the field on the far side points back: valley
                    faces.pop()
                    v_end = _lower_end(F[f], b, d)
                    break
                f, b = g, bg
            strips.append((v, faces, v_end))
            v = v_end
        else:
            # no descent wedge: steepest descending edge
            nb = np.unique(F[fan])
            nb = nb[nb != v]
            down = nb[d[nb] < d[v]]
            if down.size == 0:
                # a spurious local minimum of an inaccurate field: finish along edges
                strips.extend(_edge_path(md, v, is_src))
                return strips
            u = int(down[np.argmin(d[down] - d[v])])
            f = int(fan[(F[fan] == u).any(axis=1)][0])
            strips.append((v, [f], u))
            v = u
        if v in visited_vertices and not is_src[v]:  # the field loops: finish along edges
            strips.extend(_edge_path(md, v, is_src))
            return strips
        visited_vertices.add(v)
    return strips


def _edge_path(md: _MeshData, v: int, is_src: np.ndarray) -> list[tuple]:
    """Fallback: Dijkstra along edges (intrinsic lengths) from ``v`` to the nearest source,
    as one-face strips.  Used only where the traced field is unusable (a spurious minimum)."""
    F, l = md.F, md.l
    n = is_src.size
    rows = F[:, [1, 2, 0]].reshape(-1)
    cols = F[:, [2, 0, 1]].reshape(-1)
    W = sp.csr_matrix((l.reshape(-1), (rows, cols)), shape=(n, n))
    W = W.maximum(W.T)
    _, pred = csgraph.dijkstra(W, directed=False, indices=v, return_predecessors=True)
    srcs = np.flatnonzero(is_src)
    dist = csgraph.dijkstra(W, directed=False, indices=v)
    s = int(srcs[np.argmin(dist[srcs])])
    if not np.isfinite(dist[s]):
        raise MescherError(f"target: no path from vertex {v} to a source")
    chain = [s]
    while chain[-1] != v:
        chain.append(int(pred[chain[-1]]))
    chain.reverse()
    out = []
    for a, b in zip(chain[:-1], chain[1:]):
        fan = md.faces_of(a)
        f = int(fan[(F[fan] == b).any(axis=1)][0])
        out.append((a, [f], b))
    return out


def _lower_end(Ff: np.ndarray, b: np.ndarray, d: np.ndarray) -> int:
    """Of the (one or two) corners with weight, the one with the lower distance."""
    cand = Ff[b > 0]
    return int(cand[np.argmin(d[cand])])


def _fan_arcs(md: _MeshData, v: int, f_in: int, f_out: int) -> list[list[int]]:
    """The faces from ``f_in`` to ``f_out`` (both included) around vertex ``v``, both ways.

    An arc that runs into the boundary is left out.  Walking crosses, in each face, the edge
    at ``v`` opposite the corner after (or before) ``v``: consistent orientation makes that one
    direction of rotation throughout.
    """
    if f_in == f_out:
        return [[f_in]]
    F, opp = md.F, md.opp
    arcs = []
    for step in (1, 2):
        arc, f, ok = [f_in], f_in, False
        for _ in range(md.vf.indptr[v + 1] - md.vf.indptr[v] + 1):  # at most the fan's size
            c = int(np.argmax(F[f] == v))
            g = int(opp[f, (c + step) % 3])
            if g < 0 or g == f_in:
                break
            arc.append(g)
            if g == f_out:
                ok = True
                break
            f = g
        if ok:
            arcs.append(arc)
    return arcs


def _dedupe(faces: list[int]) -> list[int]:
    out = [faces[0]]
    for f in faces[1:]:
        if f != out[-1]:
            out.append(f)
    return out


def _shorten(md: _MeshData, pieces: list[tuple], max_steps: int = 100000) -> list[tuple]:
    """Shorten a piecewise-taut path around its corner vertices until it is a geodesic.

    At each corner vertex ``v`` the path may swing to either side of ``v``: the two pieces
    meeting at ``v`` are joined with the faces of ``v``'s fan on that side and pulled taut
    again.  A swing is kept when it is shorter.  When no swing shortens, every corner has an
    angle >= pi on both sides, which is the condition for a locally shortest path through
    vertices (Sharp & Crane 2020, "You can find geodesic paths in triangle meshes by just
    flipping edges", Sec. 3: FlipOut's wedge condition).  FlipOut straightens such a wedge by
    intrinsic edge flips; here the wedge is unfolded on the mescher's own faces instead, which
    needs only edge lengths too and keeps the result on the input faces (no intrinsic-edge
    tracing back).  Each swing strictly shortens the path, so the loop ends.  Sequential by
    nature (each swing changes the next corner's neighbourhood): a Python loop over corners.
    """
    pieces = list(pieces)
    j, steps = 0, 0
    while j < len(pieces) - 1 and steps < max_steps:
        steps += 1
        A, B = pieces[j], pieces[j + 1]
        v, cur = A[2], A[3] + B[3]
        # the path enters v's star at A's trailing run of faces around v and leaves it at
        # B's leading run: cut both runs and go around v one way or the other
        inc_a = (md.F[A[1]] == v).any(axis=1)
        inc_b = (md.F[B[1]] == v).any(axis=1)
        i0 = len(A[1]) - int(np.argmin(inc_a[::-1])) if not inc_a.all() else 0
        j0 = int(np.argmin(inc_b)) - 1 if not inc_b.all() else len(B[1]) - 1
        best = None
        for arc in _fan_arcs(md, v, A[1][i0], B[1][j0]):
            new = _taut(md, A[0], _dedupe(A[1][:i0] + arc + B[1][j0 + 1 :]), B[2])
            length = sum(p[3] for p in new)
            if length < cur * (1.0 - 1e-12) and (best is None or length < best[0]):
                best = (length, new)
        if best is None:
            j += 1
        else:
            pieces[j : j + 2] = best[1]
            j = max(j - 1, 0)  # the previous corner's neighbourhood changed
    return pieces


def _cone_detours(md: _MeshData, pieces: list[tuple], tries: int = 8) -> list[tuple]:
    """Try the other side of the cone vertices next to a geodesic; keep what is shorter.

    Geodesics between two points differ by the side on which they pass cone vertices (angle sum
    below 2 pi: a box corner); swings at the path's own corners cannot cross a cone the path
    does not touch.  For the ``tries`` sharpest cones on the faces a geodesic crosses, the path
    is forced through the cone and shortened again, which lets it swing past on the other side
    (on a CAD box the trace and Dijkstra may both come down the wrong face next to a corner:
    +2.8% without this).
    """
    if md.cone is None:
        ang = intrinsic.corner_angles(md.l)
        total = np.bincount(md.F.reshape(-1), weights=ang.reshape(-1), minlength=md.vf.shape[0])
        bnd = np.zeros(md.vf.shape[0], dtype=bool)
        bf, bc = np.nonzero(md.opp < 0)
        bnd[md.F[bf, (bc + 1) % 3]] = bnd[md.F[bf, (bc + 2) % 3]] = True
        md.cone = np.where(bnd, 0.0, np.maximum(2.0 * np.pi - total, 0.0))  # angle defect
    length = sum(p[3] for p in pieces)
    for _ in range(3):  # a few rounds: each kept detour is strictly shorter
        on_path = {p[0] for p in pieces} | {p[2] for p in pieces}
        cand = []
        for j, piece in enumerate(pieces):  # pieces of one path: few
            for c in np.unique(md.F[piece[1]]).tolist():
                if c not in on_path and md.cone[c] > 1e-6:
                    cand.append((md.cone[c], j, c))
        best = None
        for _, j, c in sorted(cand, reverse=True)[:tries]:
            va, faces, vb, _ = pieces[j]
            inc = np.flatnonzero((md.F[faces] == c).any(axis=1))
            forced = (
                pieces[:j]
                + _taut(md, va, faces[: inc[0] + 1], c)
                + _taut(md, c, faces[inc[-1] :], vb)
                + pieces[j + 1 :]
            )
            new = _shorten(md, forced)
            new_len = sum(p[3] for p in new)
            if new_len < length * (1.0 - 1e-12) and (best is None or new_len < best[0]):
                best = (new_len, new)
        if best is None:
            break
        length, pieces = best
    return pieces
