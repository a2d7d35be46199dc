"""Conversions to the two 3D representations earlier work used (paper Sec. 4.6).

* **bent**: drop the harmonic part and integrate: ``V = (x, y, z)`` with ``z`` from the Hodge
  decomposition.  Local depth differences equal the exact part ``d01 z``.
* **cut**: cut the surface open along edges that meet every impossible loop, integrate ``zeta``
  across the remaining edges (breadth-first over faces), and duplicate vertices whose corners
  disagree.  Depth differences equal ``zeta`` on every edge; across the cut the jump equals the
  period of the loop it cuts.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np
import scipy.sparse as sp
import scipy.sparse.csgraph as csgraph

from . import topology as topo
from .errors import MescherError
from .validate import as_count, as_index_array


def bent_embedding(m) -> tuple[np.ndarray, np.ndarray]:
    """``(V, F)``: the mescher with its harmonic part removed, embedded in 3D."""
    z = np.asarray(m.hodge().z)
    return np.column_stack([m.xy, z]), np.array(m.F)


def cut_embedding(m, cut_edges=None, tol: float | None = None):
    """Integrate ``zeta`` on the mescher cut open.

    Faces are integrated breadth-first across a spanning forest of the dual graph; every other
    interior edge is glued back when both sides agree on the depths of its endpoints.  With the
    default ``cut_edges=None`` the cut is exactly the set of edges where they disagree -- a
    seam across every loop with a non-zero period, on closed surfaces and on surfaces with
    boundary alike (a ring is cut across, from boundary to boundary).

    Parameters
    ----------
    m : Mescher
    cut_edges : (k,) int, optional
        Edge indices to cut along instead; it is an error if they leave an impossible loop
        uncut (depths would disagree across an uncut edge).
    tol : float, optional
        Depth agreement tolerance (default ``1e-9 * m.scale()``).

    Returns
    -------
    V : (#Vc, 3) float64
        Cut-model vertices (x, y, depth).
    F : (#F, 3) int64
        Faces (face i is the mescher's face i).
    vmap : (#Vc,) int64
        Mescher vertex of each cut-model vertex.
    """
    ne, nf = m.n_edges, m.n_faces
    user_cut = np.zeros(ne, dtype=bool)
    if cut_edges is not None and np.size(cut_edges):
        user_cut[as_index_array(cut_edges, "cut_edges", ne)] = True
    tol = 1e-9 * m.scale() if tol is None else float(tol)
    ef = topo.edge_faces(np.asarray(m.face_edges), ne)
    F = np.asarray(m.F)
    Z = np.asarray(m.corner_depths())
    inner = np.flatnonzero((ef[:, 1] >= 0) & ~user_cut)
    a, b = ef[inner, 0], ef[inner, 1]
    tail, head = m.edges[inner, 0], m.edges[inner, 1]
    ia = np.argmax(F[a] == tail[:, None], axis=1)
    ib = np.argmax(F[b] == tail[:, None], axis=1)
    ja = np.argmax(F[a] == head[:, None], axis=1)
    jb = np.argmax(F[b] == head[:, None], axis=1)
    # Spanning forest over faces through the uncut edges; offsets o (one per face) summed
    # down the tree: o[child] - o[parent] = depth jump across the shared edge.
    A = sp.csr_matrix((np.arange(1, a.size + 1, dtype=float), (a, b)), shape=(nf, nf))
    A = (A + A.T).tocsr()
    pred = topo.spanning_forest(A)
    child = np.flatnonzero(pred >= 0)
    par = pred[child]
    eid = np.asarray(A[child, par]).ravel().astype(np.int64) - 1  # index into (a, b)
    za, zb = Z[a, ia], Z[b, ib]
    delta = np.zeros(nf)
    delta[child] = np.where(a[eid] == par, za[eid] - zb[eid], zb[eid] - za[eid])
    o = topo.integrate_on_tree(pred, delta)
    Zg = Z + o[:, None]
    # Glue back every uncut edge whose two sides agree at both endpoints.
    mismatch = np.maximum(np.abs(Zg[a, ia] - Zg[b, ib]), np.abs(Zg[a, ja] - Zg[b, jb]))
    agree = mismatch <= tol
    if cut_edges is not None and not agree.all():
        raise MescherError(
            "cut_edges: expected a cut that opens every impossible loop, found "
            f"{int((~agree).sum())} uncut edge(s) whose sides disagree in depth by up to "
            f"{mismatch.max():.3g} (first: edge {int(inner[np.argmax(~agree)])}); "
            "pass cut_edges=None for an automatic cut"
        )
    g = agree
    ca = np.concatenate([3 * a[g] + ia[g], 3 * a[g] + ja[g]])
    cb = np.concatenate([3 * b[g] + ib[g], 3 * b[g] + jb[g]])
    C = sp.csr_matrix((np.ones(ca.size), (ca, cb)), shape=(3 * nf, 3 * nf))
    nv, lab = csgraph.connected_components(C, directed=False)
    vmap = np.zeros(nv, dtype=np.int64)
    vmap[lab] = F.reshape(-1)
    depth = np.zeros(nv)
    depth[lab] = Zg.reshape(-1)
    spread = np.abs(Zg.reshape(-1) - depth[lab])
    if spread.max(initial=0.0) > tol:  # tolerance drift along a chain of glued corners
        raise MescherError(
            f"cut_embedding: corners of one vertex disagree in depth by {spread.max():.3g} "
            f"after gluing (tol {tol:.3g}); pass a larger tol"
        )
    V = np.column_stack([np.asarray(m.xy)[vmap], depth])
    return V, lab.reshape(-1, 3).astype(np.int64), vmap


@dataclass(frozen=True)
class StraightCut:
    """A cut along one straight screen line, as an artist cuts a bar (see :func:`straight_cut`).

    Attributes
    ----------
    mescher : Mescher
        The mescher with the faces the cut crosses split along it (exact: new vertices on the
        crossed edges, depths interpolated linearly in each face, so the periods are unchanged).
        Its first ``m.n_vertices`` vertices are ``m``'s, at the same screen positions.
    cut_edges : (k,) int64
        Edges of ``mescher`` along the cut: ``cut_embedding(mescher, cut_edges)``.
    face_parent : (#F',) int64
        Face of ``m`` each face of ``mescher`` lies in (for :meth:`DepthOrder.follow`).
    point, normal : (2,) float64
        The cut line ``{p : normal . (p - point) = 0}`` on screen (``normal`` a unit vector).
    segment : (2, 2) float64
        Screen end points of the cut: the part of the line that crosses the cut bar.
    jump : float
        Depth jump across the cut: the period it opens.
    """

    mescher: Any
    cut_edges: np.ndarray
    face_parent: np.ndarray
    point: np.ndarray
    normal: np.ndarray
    segment: np.ndarray
    jump: float


def _level_set(m, s: np.ndarray, ef: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray, int]:
    """Connected pieces of the level set ``s == 0`` of a vertex function (no vertex on it).

    Returns
    -------
    crossed : (#E,) bool
        Edges whose end points lie on both sides.
    t : (#E,) float64
        Where a crossed edge meets the level set (0 at its tail, 1 at its head; NaN elsewhere).
    comp_face : (#F,) int64
        Piece of each crossed face (two faces are in one piece when they share a crossed
        edge); -1 for faces not crossed.
    n : int
        Number of pieces.

    ``ef`` is ``topology.edge_faces`` of ``m`` (computed once by the caller).
    """
    E, nf = m.edges, m.n_faces
    s0, s1 = s[E[:, 0]], s[E[:, 1]]
    crossed = (s0 > 0) != (s1 > 0)
    t = np.full(len(E), np.nan)
    t[crossed] = s0[crossed] / (s0[crossed] - s1[crossed])
    # components over the crossed faces only (a few hundred of them), not the whole mesh
    ab = ef[crossed]
    faces, idx = np.unique(ab, return_inverse=True)
    idx = idx.reshape(ab.shape)
    if faces.size and faces[0] < 0:  # boundary edges: drop the missing face
        faces, idx = faces[1:], idx - 1
    k = faces.size
    both = (idx >= 0).all(axis=1)
    A = sp.csr_matrix((np.ones(int(both.sum())), (idx[both, 0], idx[both, 1])), shape=(k, k))
    n, lab = csgraph.connected_components(A, directed=False)
    comp_face = np.full(nf, -1, dtype=np.int64)
    comp_face[faces] = lab
    return crossed, t, comp_face, int(n)


def _free_pieces(
    m, normal: np.ndarray, c: float, loops: tuple, P: np.ndarray, tol: float, ef, tiny: float
) -> list:
    """Pieces of the screen line ``normal . xy == c`` where one cut opens every period and
    nothing else of the figure is on screen.

    A piece (a closed curve around a bar, or an arc from boundary to boundary) is *alone* when
    no face crossed by another piece meets its screen segment: then, cut there, the two sides
    never share a pixel with anything but themselves, and front and back layers of the bar are
    cut on the same screen line (no sliver).  It opens every period when the generator loops'
    periods are one multiple ``jump`` of their signed intersection numbers with it (the period
    class is dual to the piece), so the surface cut along it integrates.  ``loops`` is
    ``(edges (k,), G (#generators, k))``: the generator loops' edges and their signed incidence.

    Returns
    -------
    list of ``(lo, hi, jump, piece, s, t, comp_face)``, ``lo``/``hi`` the piece's
    segment in the coordinate along the line, ``s`` the level function.  Vertices within
    ``tiny`` of the line count as on its positive side (the level set is then taken just beside
    them, so it still crosses edges only; :func:`_split_along` snaps those crossings back onto
    the vertices).
    """
    xy = np.asarray(m.xy)
    s = xy @ normal - c
    s[np.abs(s) <= tiny] = tiny
    crossed, t, comp_face, nc = _level_set(m, s, ef)
    if nc == 0:
        return []
    E, fe = m.edges, np.asarray(m.face_edges)
    along = xy @ np.array([-normal[1], normal[0]])
    ce = np.flatnonzero(crossed)
    u = np.full(len(E), np.nan)
    u[ce] = along[E[ce, 0]] * (1.0 - t[ce]) + along[E[ce, 1]] * t[ce]
    hit = np.flatnonzero(comp_face >= 0)
    uf = u[fe[hit]]  # (#crossed faces, 3): two crossed edges each
    flo, fhi = np.nanmin(uf, axis=1), np.nanmax(uf, axis=1)
    fcomp = comp_face[hit]
    lo, hi = np.full(nc, np.inf), np.full(nc, -np.inf)
    np.minimum.at(lo, fcomp, flo)
    np.maximum.at(hi, fcomp, fhi)
    pieces = np.arange(nc)[:, None]
    overlap = (flo[None, :] <= hi[:, None]) & (fhi[None, :] >= lo[:, None]) & (fcomp != pieces)
    alone = ~overlap.any(axis=1)
    # signed crossings of each generator loop with each piece: In[i, k]
    le, G = loops
    sign = np.where(crossed[le], np.sign(s[E[le, 1]] - s[E[le, 0]]), 0.0)
    C = np.zeros((le.size, nc))
    C[np.arange(le.size), np.maximum(comp_face[ef[le, 0]], 0)] = sign
    In = G @ C
    norm2 = (In * In).sum(axis=0)
    jump = (In * P[:, None]).sum(axis=0) / np.maximum(norm2, 1.0)
    resid = np.abs(P[:, None] - jump[None, :] * In).max(axis=0, initial=0.0)
    good = alone & (norm2 > 0) & (resid <= tol) & (np.abs(jump) > tol)
    return [(lo[k], hi[k], jump[k], k, s, t, comp_face) for k in np.flatnonzero(good)]


def _split_along(m, s: np.ndarray, t: np.ndarray, on_line: np.ndarray, faces: np.ndarray):
    """Split ``faces`` along the level set ``s == 0`` (exact edge splits).

    Each face has one corner ``a`` alone on its side; with ``b, c`` the next corners, it
    becomes ``(a, p_ab, p_ac)`` and the quad ``(p_ab, b, c, p_ac)`` cut along its shorter
    diagonal.  Depths are interpolated linearly in the face, which is exact (a face is flat in
    its own corner depths).  A crossing at a vertex on the line (``on_line``) is that vertex:
    the triangles that collapse are dropped, so a line through vertices splits fewer faces and
    puts no new vertex on an edge where the surface folds (a bar's corner), whose area-weighted
    normal would then differ from its neighbours'.  New vertices are numbered after ``m``'s.

    Returns ``(mescher, cut_edges, face_parent)``.
    """
    F, xy = np.asarray(m.F), np.asarray(m.xy)
    fe = np.asarray(m.face_edges)
    Z = np.asarray(m.corner_depths())
    E, nv = m.edges, m.n_vertices
    pos = s[F[faces]] > 0  # (k, 3)
    lone = np.argmax((pos != np.roll(pos, -1, axis=1)) & (pos != np.roll(pos, 1, axis=1)), axis=1)
    r = (lone[:, None] + np.arange(3)) % 3  # corners a, b, c of each face
    rows = np.arange(faces.size)[:, None]
    a, b, c = (F[faces][rows, r]).T
    za, zb, zc = (Z[faces][rows, r]).T
    e_ab, e_ac = fe[faces, r[:, 2]], fe[faces, r[:, 1]]  # the edge opposite c is (a, b)
    cut_e = np.unique(np.concatenate([e_ab, e_ac]))
    # a crossing at a vertex on the line is that vertex; the others are new vertices
    vid = np.full(m.n_edges, -1, dtype=np.int64)
    snap_tail, snap_head = on_line[E[cut_e, 0]], on_line[E[cut_e, 1]]
    fresh = cut_e[~snap_tail & ~snap_head]
    vid[cut_e] = np.where(snap_tail, E[cut_e, 0], E[cut_e, 1])
    vid[fresh] = nv + np.arange(fresh.size)
    tf = t[fresh][:, None]
    xy2 = np.concatenate([xy, xy[E[fresh, 0]] * (1.0 - tf) + xy[E[fresh, 1]] * tf])

    def at(e, tail, z_tail, z_head):  # the crossing on edge e, its depth from the face
        w = np.where(E[e, 0] == tail, t[e], 1.0 - t[e])
        w = np.where(on_line[tail], 0.0, np.where(on_line[E[e].sum(1) - tail], 1.0, w))
        return vid[e], z_tail + w * (z_head - z_tail)

    p_ab, z_ab = at(e_ab, a, za, zb)
    p_ac, z_ac = at(e_ac, a, za, zc)
    # the quad's shorter diagonal gives the better-shaped pair of triangles
    short = (
        np.linalg.norm(xy2[p_ab] - xy2[c], axis=1) <= np.linalg.norm(xy2[b] - xy2[p_ac], axis=1)
    )[:, None]
    tris = [
        (np.stack([a, p_ab, p_ac], 1), np.stack([za, z_ab, z_ac], 1)),
        (
            np.where(short, np.stack([p_ab, b, c], 1), np.stack([p_ab, b, p_ac], 1)),
            np.where(short, np.stack([z_ab, zb, zc], 1), np.stack([z_ab, zb, z_ac], 1)),
        ),
        (
            np.where(short, np.stack([p_ab, c, p_ac], 1), np.stack([b, c, p_ac], 1)),
            np.where(short, np.stack([z_ab, zc, z_ac], 1), np.stack([zb, zc, z_ac], 1)),
        ),
    ]
    keep = np.ones(len(F), dtype=bool)
    keep[faces] = False
    Fn = np.concatenate([T for T, _ in tris])
    Zn = np.concatenate([z for _, z in tris])
    pn = np.tile(faces, 3)
    ok = (Fn[:, 0] != Fn[:, 1]) & (Fn[:, 1] != Fn[:, 2]) & (Fn[:, 2] != Fn[:, 0])
    F2 = np.concatenate([F[keep], Fn[ok]])
    Z2 = np.concatenate([Z[keep], Zn[ok]])
    parent = np.concatenate([np.flatnonzero(keep), pn[ok]])
    m2 = type(m).from_corner_depths(F2, xy2, Z2)
    seam = p_ab != p_ac
    cut, _ = topo.edge_lookup(m2.edges, len(xy2), p_ab[seam], p_ac[seam])
    return m2, np.unique(cut), parent


def straight_cut(
    m,
    order=None,
    *,
    directions: int = 8,
    offsets: int = 40,
    tries: int = 6,
    tol: float | None = None,
) -> StraightCut:
    """Where an artist would cut the mescher: one straight screen line across one bar.

    A cut model made by hand (ParadoxToolkit's, the gallery's) cuts the impossible loop across a
    bar in a plane that contains the view direction: seen from the view the cut is a straight
    line, front and back of the bar are cut on the same line, and the two open ends meet on
    screen without a sliver (the gallery's :func:`~meschers_igl.gallery.polycube.slant_cut`
    tilts a box model's cut onto such a plane).  A mescher's screen positions are fixed, so
    here the plane is a screen line ``normal . xy == c``: its level set on the surface is a set
    of closed curves; one of them, alone on screen, that opens every period is the cut.

    Lines across the figure's main screen edge directions and in ``directions`` evenly spaced
    directions, at ``offsets`` positions each, are searched.  In each direction the candidate
    pieces at consecutive positions that cross the same bar form a run (a stretch of bar free
    of anything else); a cut goes through a run's middle, moved onto the nearest vertex of the
    bar (a bar's grid then puts the cut through vertices on its corners, so no face on a fold
    is split).  Without ``order`` the longest run wins, lines across the figure's main edge
    directions first (a bar cut square, in its longest free stretch).  With ``order``, the ``tries`` longest runs at different places are cut and the one whose cut
    model, z-buffered, shows what the mescher shows in that order (:func:`cut_mismatch`) wins:
    the jump must fall where the figure's impossibility hides it (the impossible cube's back
    bar is cut between its crossing and the top, not below the crossing); among equals, the
    one whose split turns the vertex normals least.  Candidates are
    found with integer intersection numbers (no mesh is cut to try one).

    Parameters
    ----------
    m : Mescher
        An impossible mescher (a non-zero period).
    order : DepthOrder, optional
        ``m``'s depth order, to choose the cut whose cut model shows the same picture.
    directions, offsets : int
        Search grid: evenly spaced directions over 180 degrees, positions across the screen box.
    tries : int
        Places cut and compared when ``order`` is given.
    tol : float, optional
        Period agreement tolerance (default ``1e-6 * m.scale()``).

    Returns
    -------
    StraightCut
        ``cut_embedding(cut.mescher, cut.cut_edges)`` is the cut model.

    Raises
    ------
    MescherError
        When ``m`` has no period, or no single straight cut alone on screen opens all of them
        (several period classes that no one bar carries, a bar crossed everywhere by others):
        :func:`cut_embedding`'s cut along mesh edges still works there.
    """
    from .hodge import loop_matrix

    directions = as_count(directions, "directions", minimum=1)
    offsets = as_count(offsets, "offsets", minimum=1)
    tries = as_count(tries, "tries", minimum=1)
    tol = 1e-6 * m.scale() if tol is None else float(tol)
    Gamma = loop_matrix(m.homology_generators(), m.n_edges).tocsr()
    P = np.asarray(Gamma @ np.asarray(m.zeta))
    le = np.unique(Gamma.tocoo().col)  # the loops' edges: intersection numbers need only these
    loops = (le, Gamma[:, le].toarray())
    if not (P.size and np.abs(P).max() > tol):
        raise MescherError(
            "m: expected an impossible mescher (a non-zero period) to cut, found "
            "every period 0; cut_embedding(m) needs no seam"
        )
    xy = np.asarray(m.xy)
    ef = topo.edge_faces(np.asarray(m.face_edges), m.n_edges)
    tiny = 1e-9 * m.scale()
    # line normals along the figure's main screen edge directions (a bar is cut square to
    # its edges), then evenly spaced ones
    thetas = _main_directions(xy, np.asarray(m.edges))
    n_main = len(thetas)
    thetas += list(np.pi * np.arange(directions) / directions)
    runs_all = []  # see _run
    for i_th, th in enumerate(thetas):  # a few hundred lines, each vectorized over the mesh
        square = i_th < n_main  # across the bar's edges: preferred
        normal = np.array([np.cos(th), np.sin(th)])
        proj = xy @ normal
        step = (proj.max() - proj.min()) / (offsets + 1)
        runs: list[list] = []  # open runs: [lo, hi, members [(c, lo, hi)], summed cut length]
        for j in range(1, offsets + 1):
            c = proj.min() + j * step
            nxt, going_on = [], set()
            for lo, hi, *_ in _free_pieces(m, normal, c, loops, P, tol, ef, tiny):
                k = next((k for k, r in enumerate(runs) if r[0] <= hi and r[1] >= lo), None)
                if k is None:
                    nxt.append([lo, hi, [(c, lo, hi)], hi - lo])
                else:
                    r = runs[k]
                    going_on.add(k)
                    nxt.append([lo, hi, [*r[2], (c, lo, hi)], r[3] + hi - lo])
            runs_all += [_run(r, normal, square) for k, r in enumerate(runs) if k not in going_on]
            runs = nxt
        runs_all += [_run(r, normal, square) for r in runs]
    if not runs_all:
        raise MescherError(
            "m: expected a bar that one straight cut can open alone on screen, "
            "found none; use cut_embedding(m) (a cut along mesh edges)"
        )
    runs_all.sort(key=lambda r: r[:3], reverse=True)
    if order is None:
        return _cut_at(m, *runs_all[0][3:5], loops, P, tol, ef, tiny)
    cuts = [_cut_at(m, *r[3:5], loops, P, tol, ef, tiny) for r in _distinct(runs_all, tries)]
    # the cut model that looks like the mescher; among equals, the split that moves the
    # (area-weighted) vertex normals least, then the longer run
    miss = np.round([cut_mismatch(cut, order) for cut in cuts], 4)
    n0 = np.asarray(m.vertex_normals())
    turn = [
        np.round(1.0 - (np.asarray(c.mescher.vertex_normals())[: len(n0)] * n0).sum(1).min(), 3)
        for c in cuts
    ]
    return cuts[int(np.lexsort((np.arange(len(cuts)), turn, miss))[0])]


def _main_directions(xy: np.ndarray, edges: np.ndarray) -> list[float]:
    """The figure's main screen edge directions (angles in ``[0, pi)``): the 1-degree bins
    holding at least 5% of the total edge length, at most six, longest first."""
    ev = xy[edges[:, 1]] - xy[edges[:, 0]]
    ang = np.mod(np.arctan2(ev[:, 1], ev[:, 0]), np.pi)
    length = np.linalg.norm(ev, axis=1)
    bins = np.round(np.degrees(ang)).astype(np.int64) % 180
    hist = np.bincount(bins, weights=length, minlength=180)
    main = np.argsort(hist)[::-1][:6]
    main = main[hist[main] >= 0.05 * hist.sum()]
    return [float(np.average(ang[bins == b], weights=length[bins == b])) for b in main]


def _run(r: list, normal: np.ndarray, square: bool) -> tuple:
    """A finished run as ``(square, free length, -mean cut length, normal, (c, lo, hi),
    centre)``: ``square`` when the line is across the figure's main edge directions,
    ``(c, lo, hi, free)`` its middle line, that line's piece and the run's length, ``centre``
    where on screen it cuts; tuples sort best last."""
    members, length_sum = r[2], r[3]
    c, lo, hi = members[(len(members) - 1) // 2]
    centre = normal * c + np.array([-normal[1], normal[0]]) * 0.5 * (lo + hi)
    free = members[-1][0] - members[0][0]
    return (square, free, -length_sum / len(members), normal, (c, lo, hi, free), centre)


def _distinct(runs: list, k: int) -> list:
    """The first ``k`` runs that cut at different places (centres farther apart than their
    cuts are long): one stretch of bar is found in many directions."""
    out: list = []
    for r in runs:
        if all(np.linalg.norm(r[5] - q[5]) > max(-r[2], -q[2]) for q in out):
            out.append(r)
            if len(out) == k:
                break
    return out


def _cut_at(m, normal, middle, loops, P, tol, ef, tiny) -> StraightCut:
    """The straight cut through a run's middle piece ``middle = (c, lo, hi, free)`` (found on
    the line ``normal . xy == c`` by the search, so it is there), moved onto vertices within
    the middle third of the run."""
    xy = np.asarray(m.xy)
    c_mid, lo, hi, free = middle
    pieces = [
        q
        for q in _free_pieces(m, normal, c_mid, loops, P, tol, ef, tiny)
        if q[0] <= hi and q[1] >= lo
    ]
    lo, hi, *_, piece, s, t, comp_face = min(pieces, key=lambda q: q[1] - q[0])
    # through vertices of the cut faces near the run's middle, the line that splits the fewest
    # edges where the surface folds (a bar's corners; every edge of a curved surface): a new
    # vertex there gets an area-weighted normal unlike its neighbours' (a shading tick)
    c = _through_vertices(
        m, normal, c_mid, free / 6, np.flatnonzero(comp_face == piece), lo, hi, tiny
    )
    again = [
        q for q in _free_pieces(m, normal, c, loops, P, tol, ef, tiny) if q[0] <= hi and q[1] >= lo
    ]
    if not again:  # that vertex's line meets something else: the run's middle
        c, again = c_mid, pieces
    lo, hi, jump, piece, s, t, comp_face = min(again, key=lambda q: q[1] - q[0])
    on_line = np.abs(xy @ normal - c) <= tiny
    m2, cut, parent = _split_along(m, s, t, on_line, np.flatnonzero(comp_face == piece))
    d = np.array([-normal[1], normal[0]])
    point = normal * c
    u = np.asarray(m2.xy)[m2.edges[cut].ravel()] @ d  # the seam's extent along the line
    segment = np.stack([point + u.min() * d, point + u.max() * d])
    return StraightCut(m2, cut, parent, point, normal, segment, float(jump))


def _through_vertices(m, normal, c_mid, reach, faces, lo, hi, tiny, k: int = 256) -> float:
    """Offset of the line through a vertex of ``faces`` within ``reach`` of ``c_mid`` (the
    ``k`` nearest) that splits the fewest fold edges (then the fewest edges, then the
    nearest); ``c_mid`` when no vertex is that near."""
    xy = np.asarray(m.xy)
    F, E = np.asarray(m.F), m.edges
    proj = np.unique(xy[np.unique(F[faces])] @ normal)
    proj = proj[np.abs(proj - c_mid) <= reach]
    cand = np.append(proj[np.argsort(np.abs(proj - c_mid))[:k]], c_mid)
    fe = np.asarray(m.face_edges)
    ef = topo.edge_faces(fe, m.n_edges)
    N = np.asarray(m.face_normals())
    fold = (ef[:, 1] < 0) | ((N[ef[:, 0]] * N[np.maximum(ef[:, 1], 0)]).sum(1) < 1 - 1e-9)
    along = xy @ np.array([-normal[1], normal[0]])
    # edges near the piece's segment (both ends within its span, padded by the longest edge)
    pad = float(np.abs(along[E[:, 0]] - along[E[:, 1]]).max())
    near = np.flatnonzero(
        (np.minimum(along[E[:, 0]], along[E[:, 1]]) <= hi + pad)
        & (np.maximum(along[E[:, 0]], along[E[:, 1]]) >= lo - pad)
    )
    s = (xy[E[near]] @ normal)[None, :, :] - cand[:, None, None]  # (k, #near, 2)
    strict = (np.abs(s) > tiny).all(axis=2) & ((s[..., 0] > 0) != (s[..., 1] > 0))
    key = np.stack([(strict & fold[near]).sum(1), strict.sum(1), np.abs(cand - c_mid)], axis=1)
    return float(cand[np.lexsort(key.T[::-1])[0]])


def cut_mismatch(cut: StraightCut, order, size: int = 128) -> float:
    """Share of the figure's pixels where the cut model shows another face than the mescher.

    The cut model (:func:`cut_embedding` along ``cut.cut_edges``) is a real 3D model: its
    picture is the painter's picture in the order of its own depths
    (:meth:`DepthOrder.from_embedding`).  The mescher's picture is painted in ``order`` carried
    to the split mescher (:meth:`DepthOrder.follow`).  Both are sampled with
    :func:`meschers_igl.painter.visible_faces` (no GPU).

    Parameters
    ----------
    cut : StraightCut
    order : DepthOrder
        The depth order of the mescher that was cut (before the split).
    size : int
        Pixels along the longer side.

    Returns
    -------
    float
        ``#{pixels whose visible faces differ} / #{pixels covered by either}``; 0 when the cut
        model looks exactly like the mescher.
    """
    from .order import DepthOrder
    from .painter import visible_faces

    m2 = cut.mescher
    V, F, _ = cut_embedding(m2, cut.cut_edges)
    own = DepthOrder.from_embedding(m2, V[F][:, :, 2])
    seen = visible_faces(m2, order.follow(m2, cut.face_parent), size=size)
    shown = visible_faces(m2, own, size=size)
    hit = (seen >= 0) | (shown >= 0)
    return float(np.mean(seen[hit] != shown[hit])) if hit.any() else 0.0
