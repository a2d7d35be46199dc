"""The compiled kernel of exact geodesics: window propagation on an intrinsic triangle mesh.

:class:`~meschers_igl.geodesic.exact.ExactGeodesicSolver` sets up the mesh's arrays
(:class:`MeshArrays`) and a query's (:class:`QueryArrays`), and calls :func:`propagate` until
it returns :data:`DONE`; the algorithm (windows, pseudo-sources and their shadows, pruning,
trimming, merging) is described in that module's docstring.  Hand-written in numba: no library
propagates windows on a mesh given by its edge lengths.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from ..heap import heap_pop, heap_push
from ..jit import kernel

TWO_PI = 2.0 * np.pi
SADDLE_TOL = 1e-9  # angle excess (rad) above which a vertex is a saddle (pseudo-source)
_REL = 1e-12  # relative slack in the pruning rules
_MERGE = 1e-12  # relative: two windows whose unfolded sources differ by less are one window
_TOUCH = 1e-12  # relative: window ends closer than this touch
_SHADOW_SLACK = 1e-9  # rad: pseudo-sources' shadows are widened by this on each side
_VIS = 1e-10  # relative slack of "the apex (or an end) is on a ray of the window": a ray through
# a vertex along a straight chain of edges (flat vertices) is the border of two windows and its
# crossing is rounded by ~eps / sin(sliver angle); a distance taken this way is off by <= 2 _VIS L


#: the kernels only compiled code calls (all but :func:`walk_rings` and :func:`propagate`): no
#: CPython wrapper to compile on the first run.  Calling one from Python crashes the interpreter.
_inner = kernel(nogil=True, no_cpython_wrapper=True)


@_inner
def _useless(dist, a, b, c, L, cx, cy, b0, b1, sx, sy, sig):  # pragma: no cover - compiled
    """Xin-Wang pruning: True when every point of the window is strictly beaten via a vertex."""
    d0 = sig + np.sqrt((b0 - sx) ** 2 + sy * sy)
    d1 = sig + np.sqrt((b1 - sx) ** 2 + sy * sy)
    tol = _REL * (d1 + d0 + L)
    if dist[a] + b1 < d1 - tol:
        return True
    if dist[b] + (L - b0) < d0 - tol:
        return True
    dc = dist[c]
    if dc >= sig:
        if (
            dc + np.sqrt((cx - b0) ** 2 + cy * cy) < d0 - tol
            and dc + np.sqrt((cx - b1) ** 2 + cy * cy) < d1 - tol
        ):
            return True
    return False


@_inner
def _cut(lo, hi, a, b, r1, r2, r3, nr, w0, w1, w2):  # pragma: no cover - compiled
    """Cut from the ends of ``[lo, hi]`` the pieces of the overlap ``[a, b]`` (pieces
    ``[a, r1], [r1, r2], [r2, r3]``, ``nr`` of them, the last ending at ``b``) that the other
    window wins (``w0, w1, w2``); an interior piece is not cut (it would split the window)."""
    i = 0
    if a <= lo and w0:
        lo = r1
        i = 1
        if nr > 1 and w1:
            lo = r2
            i = 2
            if nr > 2 and w2:
                lo = r3
                i = 3
    if i == nr:
        return (hi, hi) if b >= hi else (lo, hi)
    if b >= hi:
        if nr == 3 and w2:
            hi = r2
            if w1 and i < 2:
                hi = r1
                if w0 and i < 1:
                    hi = a
        elif nr == 2 and w1:
            hi = r1
            if w0 and i < 1:
                hi = a
        elif nr == 1 and w0:
            hi = a
    return lo, hi


@_inner
def _gap(x, wx, wy2, ws, ox, oy2, osg):  # pragma: no cover - compiled
    """``d_o(x) - d_w(x)`` for two windows' distance functions on one edge."""
    return osg + np.sqrt((x - ox) ** 2 + oy2) - ws - np.sqrt((x - wx) ** 2 + wy2)


@_inner
def _resolve(lo, hi, wx, wy2, ws, olo, ohi, ox, oy2, osg, L):  # pragma: no cover - compiled
    """Trim two overlapping windows ``w`` and ``o`` of one edge (same frame) against each other.

    Both distance functions are ``sigma + sqrt((x - sx)^2 + sy^2)``; their difference
    ``g = d_o - d_w`` has at most two roots in the overlap ``[a, b]`` (MMP's quadratic, from
    squaring twice; it may add roots where ``g`` keeps its sign, which only splits a piece),
    so the overlap splits into at most three pieces of constant sign.  A piece is won by one
    window when it is nearer by more than the round-off slack at the piece's midpoint and at
    its ends that are not roots (``g = 0`` there).  Each window loses the won pieces touching
    its ends (:func:`_cut`).  The roots and the signs are computed once for the pair.

    Returns
    -------
    (lo, hi, olo, ohi) : the two trimmed intervals (``hi <= lo``: the window is gone).
    """
    a = max(lo, olo)
    b = min(hi, ohi)
    if b <= a:
        return lo, hi, olo, ohi
    D = ws - osg
    al = 2.0 * (wx - ox)
    be = ox * ox - wx * wx + oy2 - wy2 - D * D
    qa = al * al - 4.0 * D * D
    qb = 2.0 * al * be + 8.0 * D * D * wx
    qc = be * be - 4.0 * D * D * (wx * wx + wy2)
    # the piece ends a < r1 (< r2 (< r3)), the last one b; scalars, not an array (an array
    # here was allocated on every call: 1.5x the whole propagation)
    r1 = b
    r2 = b
    r3 = b
    nr = 1
    scale = abs(qb) + abs(qc) + 1e-300
    if abs(qa) * (L * L + 1.0) > 1e-14 * scale:
        disc = qb * qb - 4.0 * qa * qc
        if disc >= 0.0:
            sq = np.sqrt(disc)
            qq = -0.5 * (qb + sq) if qb >= 0.0 else -0.5 * (qb - sq)
            x1 = qq / qa
            x2 = qc / qq if qq != 0.0 else x1
            if x1 > x2:
                x1, x2 = x2, x1
            if a < x1 < b:
                r1 = x1
                nr = 2
                if a < x2 < b and x2 != x1:
                    r2 = x2
                    nr = 3
            elif a < x2 < b:
                r1 = x2
                nr = 2
    elif qb != 0.0:
        x1 = -qc / qb
        if a < x1 < b:
            r1 = x1
            nr = 2
    tol = _REL * (ws + osg + L)
    ga = _gap(a, wx, wy2, ws, ox, oy2, osg)
    gb = _gap(b, wx, wy2, ws, ox, oy2, osg)
    g0 = _gap(0.5 * (a + r1), wx, wy2, ws, ox, oy2, osg)
    # piece 0: its midpoint, a, and b when it is the only piece
    o0 = g0 < -tol and ga < -tol and (nr > 1 or gb < -tol)
    w0 = g0 > tol and ga > tol and (nr > 1 or gb > tol)
    o1 = w1 = o2 = w2 = False
    if nr > 1:
        g1 = _gap(0.5 * (r1 + r2), wx, wy2, ws, ox, oy2, osg)
        o1 = g1 < -tol and (nr > 2 or gb < -tol)
        w1 = g1 > tol and (nr > 2 or gb > tol)
    if nr > 2:
        g2 = _gap(0.5 * (r2 + r3), wx, wy2, ws, ox, oy2, osg)
        o2 = g2 < -tol and gb < -tol
        w2 = g2 > tol and gb > tol
    lo, hi = _cut(lo, hi, a, b, r1, r2, r3, nr, o0, o1, o2)
    if hi > lo:  # o loses only to what is left of w
        olo, ohi = _cut(olo, ohi, a, b, r1, r2, r3, nr, w0, w1, w2)
    return lo, hi, olo, ohi


@_inner
def _block_remove(e, i, bstart, bn, aw, alo, ahi, pos):  # pragma: no cover - compiled
    """Remove entry ``i`` of edge ``e``'s block: its last entry moves into the hole."""
    base = bstart[e]
    last = bn[e] - 1
    if i != last:
        aw[base + i] = aw[base + last]
        alo[base + i] = alo[base + last]
        ahi[base + i] = ahi[base + last]
        pos[aw[base + i]] = i
    bn[e] = last


@_inner
def _trim_by_ends(da, db, L, b0, b1, sx, sy, sig):  # pragma: no cover - compiled
    """Cut the parts of ``[b0, b1]`` where the route along the edge from ``A`` (a prefix: rule
    1's difference decreases in ``q``) or from ``B`` (a suffix) is strictly shorter."""
    y2 = sy * sy
    tol = _REL * (sig + L + np.sqrt(sx * sx + y2))
    if np.isfinite(da) and sig + np.sqrt((b0 - sx) ** 2 + y2) - da - b0 > tol:
        k = da - sig
        den = 2.0 * (sx + k)
        if den > 0.0:
            q = (sx * sx + y2 - k * k) / den - tol
            b0 = max(b0, min(q, b1))
    if np.isfinite(db) and sig + np.sqrt((b1 - sx) ** 2 + y2) - db - (L - b1) > tol:
        k = db - sig
        ax = L - sx
        den = 2.0 * (ax + k)
        if den > 0.0:
            q = L - ((ax * ax + y2 - k * k) / den - tol)
            b1 = min(b1, max(q, b0))
    return b0, b1


@_inner
def _ring_pos(cpos, csgn, k, psi):  # pragma: no cover - compiled
    """Ring position of the direction at angle ``psi`` from corner ``k``'s first edge (towards
    its second); NaN for a vertex without a ring (no shadow is then used)."""
    if csgn[k] == 0:
        return np.nan
    return cpos[k] + csgn[k] * psi


@_inner
def _shadow(b, p, sg, al, th, bnd, piece):  # pragma: no cover - compiled
    """Part ``piece`` (0 or 1) of a corner's angles ``[0, al]`` into which a pseudo-source with
    back direction ``b`` (a ring position) may send a shortest path on.

    A shortest path through a vertex turns by at least ``pi`` on both sides (else a shortcut
    past the vertex is shorter; Mitchell, Mount, Papadimitriou 1987), so from a vertex of total
    angle ``th`` it goes on only at ring positions ``[b + pi, b + th - pi]`` (modulo ``th``: the
    shadow, of width ``th - 2 pi``), and from a boundary vertex (ring ``[0, th]``) at
    ``[0, b - pi]`` and ``[b + pi, th]``.  Any shortest path to the vertex gives the same shadow
    (up to a round-off tie), so the one that set its distance is used, widened by
    ``_SHADOW_SLACK``.  Returns the part as corner angles ``(psi0, psi1)``; empty if
    ``psi1 <= psi0``.  ``p, sg``: the corner's first edge's ring position and turn.
    """
    lo = p if sg > 0 else p - al  # the corner as ring positions [lo, lo + al]
    hi = lo + al
    if bnd:
        if piece == 0:
            w0 = b + np.pi - _SHADOW_SLACK
            w1 = th + _SHADOW_SLACK
        else:
            w0 = -_SHADOW_SLACK
            w1 = b - np.pi + _SHADOW_SLACK
    else:
        w0 = b + np.pi - _SHADOW_SLACK
        w1 = b + th - np.pi + _SHADOW_SLACK
        k = np.floor(w0 / th)  # the wedge starting in [0, th), and shifted by -th
        w0 -= k * th
        w1 -= k * th
        if piece == 1:
            w0 -= th
            w1 -= th
    q0 = max(lo, w0)
    q1 = min(hi, w1)
    if q1 <= q0:
        return 0.0, -1.0
    if sg > 0:
        return q0 - p, q1 - p
    return p - q1, p - q0


@_inner
def _ray_hit(cx, cy, psi):  # pragma: no cover - compiled
    """Where the ray from the apex ``C = (cx, cy)`` at angle ``psi`` from ``C->A`` (towards
    ``C->B``) meets the edge ``AB`` (``A = (0, 0)``, ``B = (L, 0)``, ``cy > 0``)."""
    cs = np.cos(psi)
    sn = np.sin(psi)
    dx = -cx * cs + cy * sn
    dy = -cx * sn - cy * cs
    if dy >= 0.0:
        return np.inf
    return cx - dx * cy / dy


@kernel(nogil=True)
def walk_rings(F, twin, cang, vptr, vcorner, nv):  # pragma: no cover - compiled
    """Walk each vertex's one-ring: ``cpos, csgn, theta, vbnd`` of :func:`propagate`."""
    n = twin.size
    # np.empty and fills, not np.zeros: np.zeros is a compilation of its own per dtype
    cpos, csgn = np.empty(n, dtype=np.float64), np.empty(n, dtype=np.float64)
    theta, vbnd = np.empty(nv, dtype=np.float64), np.empty(nv, dtype=np.bool_)
    cpos[:], csgn[:], theta[:], vbnd[:] = 0.0, 0.0, 0.0, False
    for v in range(nv):
        k0 = vptr[v]
        deg = vptr[v + 1] - k0
        if deg == 0:
            continue
        # start at a corner with a boundary edge at v, entering through it, if there is one
        h0 = vcorner[k0]
        win = F[h0 // 3, (h0 % 3 + 1) % 3]
        for k in range(k0, k0 + deg):
            h = vcorner[k]
            f = h // 3
            c = h - 3 * f
            if twin[3 * f + (c + 1) % 3] < 0:  # the edge from v to F[f, c+2]
                h0 = h
                win = F[f, (c + 2) % 3]
                vbnd[v] = True
                break
            if twin[3 * f + (c + 2) % 3] < 0:  # the edge from v to F[f, c+1]
                h0 = h
                win = F[f, (c + 1) % 3]
                vbnd[v] = True
                break
        h = h0
        pos = 0.0
        ok = True
        for step in range(deg):
            f = h // 3
            c = h - 3 * f
            a = cang[h]
            if win == F[f, (c + 1) % 3]:
                csgn[h] = 1.0
                cpos[h] = pos
                wout = F[f, (c + 2) % 3]
                hout = 3 * f + (c + 1) % 3  # opposite F[f, c+1]: the edge v - F[f, c+2]
            elif win == F[f, (c + 2) % 3]:
                csgn[h] = -1.0
                cpos[h] = pos + a
                wout = F[f, (c + 1) % 3]
                hout = 3 * f + (c + 2) % 3
            else:
                ok = False
                break
            pos += a
            t = twin[hout]
            if step == deg - 1:
                # a closed ring comes back to its first corner, an open one ends at the boundary
                ok = (t < 0) if vbnd[v] else (t >= 0 and (t // 3) == (h0 // 3))
                break
            if t < 0:
                ok = False
                break
            g = t // 3
            cg = -1
            for j in range(3):
                if F[g, j] == v:
                    cg = j
            if cg < 0:
                ok = False
                break
            h = 3 * g + cg
            win = wout
        theta[v] = pos
        if not ok:
            for k in range(k0, k0 + deg):
                csgn[vcorner[k]] = 0.0
    return cpos, csgn, theta, vbnd


class MeshArrays(NamedTuple):
    """The intrinsic mesh as the kernel reads it (built once per solver; see :func:`propagate`)."""

    F: np.ndarray
    fl: np.ndarray
    fx: np.ndarray
    fy: np.ndarray
    twin: np.ndarray
    rev: np.ndarray
    hedge: np.ndarray
    pseudo: np.ndarray
    vptr: np.ndarray
    vcorner: np.ndarray
    cflip: np.ndarray
    cang: np.ndarray
    cpos: np.ndarray
    csgn: np.ndarray
    theta: np.ndarray
    vbnd: np.ndarray
    mdeg: np.int64


class QueryArrays(NamedTuple):
    """One query's arrays, written in place by the kernel (the solver's query state; ``kids_h,
    kids_b``: scratch, the children of one step)."""

    dist: np.ndarray
    emitted: np.ndarray
    bpos: np.ndarray
    via: np.ndarray
    vimg: np.ndarray
    wh: np.ndarray
    wb: np.ndarray
    state: np.ndarray
    pos: np.ndarray
    free: np.ndarray
    bstart: np.ndarray
    bcls: np.ndarray
    bn: np.ndarray
    fhead: np.ndarray
    aw: np.ndarray
    alo: np.ndarray
    ahi: np.ndarray
    hk: np.ndarray
    hv: np.ndarray
    kids_h: np.ndarray
    kids_b: np.ndarray


# what the kernel returns: why it stopped
DONE = 0  # the queue is empty, or every target is final
REPORT = 1  # max_pops items taken out: time for a progress report
GROW_HEAP = 2  # the heap might not hold one more step
GROW_WINDOWS = 3  # the window table might not hold one more step
GROW_ARENA = 4  # the edge blocks' arena might not hold one more step
_GO = -1  # (internal) room for one more step
# the counters carried across calls, by index into ``ctr``
C_HEAP, C_FREE, C_USED, C_ARENA_TOP, C_CREATED, C_EMITTED, C_MAX_BLOCK = range(7)
# ``via[v]`` of a vertex whose distance is not set by a window or an edge (sources, unreached)
NO_PARENT = -(1 << 62)
# a window's state: queued (and in its edge's block), or dead (trimmed away or merged)
QUEUED = 0
DEAD = 2
# columns of a window's row in ``wb`` (and of a child's in the children's buffer)
B0, B1, SX, SY, SIG = range(5)

#: the decorators of the steps of :func:`propagate`: without reference counting (``_nrt=False``),
#: like :func:`propagate`, which allocates nothing: the steps borrow the caller's arrays and
#: return scalars.  ``_helper``: compiled into :func:`propagate` (``inline="always"``, steps
#: called once); ``_small``: compiled once, inlined by LLVM (steps called at several places, and
#: rare branches with loops such as :func:`_new_block`: numba's IR inlining copies blocks with
#: their scopes, costing compile time faster than length).  On a 20k-face torus against one long
#: function: steps called, not inlined, 5x slower (36 arrays passed and counted; uncounted
#: 1.5x); inlined but counted 2.5x; inlined and uncounted, as fast.  A ``_small`` step takes only
#: the arrays it uses (compiled with the groups' types, each cost ~0.5 s of first compile).
_helper = kernel(nogil=True, _nrt=False, inline="always")
_small = kernel(nogil=True, _nrt=False, no_cpython_wrapper=True)


@_helper
def _room(mesh, arr, ctr, pops, max_pops, targets):  # pragma: no cover - compiled
    """Why to stop before the next step (:data:`DONE` ... :data:`GROW_ARENA`), or ``_GO``.

    One step queues at most ``2 mdeg`` children and ``2 mdeg + 3`` pseudo-source events, each
    child in at most one new edge block of twice the largest capacity so far.
    """
    mdeg = mesh.mdeg
    hk = arr.hk
    if ctr[C_HEAP] == 0:
        return DONE
    if pops >= max_pops:
        return REPORT
    if targets.size and (pops & 1023) == 0:
        far = 0.0  # the farthest target's distance so far (inf: one not reached yet)
        for v in targets:
            far = max(far, arr.dist[v])
        if hk[0] >= far:
            return DONE
    if ctr[C_HEAP] + 4 * mdeg + 8 > hk.size:
        return GROW_HEAP
    if ctr[C_FREE] + arr.wh.size - ctr[C_USED] < 2 * mdeg + 2:
        return GROW_WINDOWS
    if ctr[C_ARENA_TOP] + 2 * mdeg * (2 * ctr[C_MAX_BLOCK] + 8) > arr.aw.size:
        return GROW_ARENA
    return _GO


@_small
def _queue_vertex(pseudo, dist, hk, hv, ctr, u):  # pragma: no cover - compiled
    """Queue a pseudo-source's emission at its (lowered) distance."""
    if pseudo[u]:
        ctr[C_HEAP] = heap_push(hk, hv, ctr[C_HEAP], dist[u], -(u + 1))


@_small
def _add_child(kids_h, kids_b, n, t, b0, b1, sx, sy, sig):  # pragma: no cover - compiled
    """Write a child window (half-edge ``t``, interval, source image, distance) at row ``n``."""
    kids_h[n] = t
    kids_b[n, B0] = b0
    kids_b[n, B1] = b1
    kids_b[n, SX] = sx
    kids_b[n, SY] = sy
    kids_b[n, SIG] = sig
    return n + 1


@_helper
def _emit_from_vertex(mesh, arr, ctr, v, key, kids_h, kids_b):  # pragma: no cover - compiled
    """Pseudo-source (or source) ``v``, final at ``key``, relaxes its neighbours along edges and
    sends windows across each opposite edge, into its shadow (:func:`_shadow`) only.

    Returns the number of children written to ``kids_h, kids_b``.
    """
    F, fl, fx, fy = mesh.F, mesh.fl, mesh.fx, mesh.fy
    cang, cpos, csgn = mesh.cang, mesh.cpos, mesh.csgn
    dist, bpos = arr.dist, arr.bpos
    b = bpos[v]
    nch = np.int64(0)  # typed (see _trim_on_edge)
    for k in range(mesh.vptr[v], mesh.vptr[v + 1]):
        h = mesh.vcorner[k]  # half-edge opposite v in its face
        f = h // 3
        c = h - 3 * f
        # neighbours along the two edges at v (lengths: opposite b, opposite a)
        for j in range(2):
            u = F[f, (c + 1 + j) % 3]
            du = key + fl[3 * f + (c + 2 - j) % 3]
            if du < dist[u]:
                dist[u] = du
                arr.via[u] = -(v + 1)
                # u's path arrives along the edge from v: u's corner's second edge (j = 0) or
                # first edge (j = 1)
                cu = 3 * f + (c + 1 + j) % 3
                bpos[u] = _ring_pos(cpos, csgn, cu, cang[cu] if j == 0 else 0.0)
                _queue_vertex(mesh.pseudo, dist, arr.hk, arr.hv, ctr, u)
        t = mesh.twin[h]
        if t < 0:
            continue
        # the rays from v across the opposite edge: all of them from a source or a vertex
        # without a ring, else those in its shadow
        L = fl[h]
        al = cang[h]
        for piece in range(2):
            if b != b or csgn[h] == 0:
                if piece == 1:
                    break
                p0, p1 = 0.0, al
            else:
                p0, p1 = _shadow(b, cpos[h], csgn[h], al, mesh.theta[v], mesh.vbnd[v], piece)
                if p1 <= p0:
                    continue
            x0 = 0.0 if p0 <= 0.0 else _ray_hit(fx[h], fy[h], p0)
            x1 = L if p1 >= al else _ray_hit(fx[h], fy[h], p1)
            x0 = min(max(x0, 0.0), L)
            x1 = min(max(x1, 0.0), L)
            if x1 <= x0:
                continue
            ctr[C_EMITTED] += 1
            if mesh.rev[h]:
                nch = _add_child(kids_h, kids_b, nch, t, L - x1, L - x0, L - fx[h], -fy[h], key)
            else:
                nch = _add_child(kids_h, kids_b, nch, t, x0, x1, fx[h], -fy[h], key)
    return nch


@_small
def _reach(pseudo, dist, via, vimg, hk, hv, ctr, u, dv, h, sx, sy):  # pragma: no cover - compiled
    """A window on half-edge ``h`` (source image ``(sx, sy)``) reaches vertex ``u`` at ``dv``:
    True when that lowers ``u``'s distance (recorded, and ``u`` queued if a pseudo-source; the
    caller sets its ring position)."""
    if dv >= dist[u]:
        return False
    dist[u] = dv
    via[u] = h
    vimg[u, 0] = sx
    vimg[u, 1] = sy
    _queue_vertex(pseudo, dist, hk, hv, ctr, u)
    return True


@_helper
def _unfold_child(x0, x1, ox, oy, ex, ey, Lk, sx, sy):  # pragma: no cover - compiled
    """The child a window's rays through ``[x0, x1]`` (of the entry edge) make on a far edge.

    The far edge starts at ``(ox, oy)`` with unit direction ``(ex, ey)`` and length ``Lk`` (in
    the entry edge's frame).  Returns ``(lo, hi, ssx, ssy)``: the interval the rays from
    ``(sx, sy)`` cross, and the source, in the far edge's frame (seen from the entered face).
    """
    qx = sx - ox
    qy = sy - oy
    ssx = qx * ex + qy * ey
    ssy = ex * qy - ey * qx
    lo = Lk
    hi = 0.0
    for j in range(2):
        px = (x0 if j == 0 else x1) - ox
        py = -oy
        ppx = px * ex + py * ey
        ppy = ex * py - ey * px
        den = ssy - ppy
        if den > 0.0:
            uu = ssx + (ppx - ssx) * ssy / den
        else:
            uu = ppx
        uu = min(max(uu, 0.0), Lk)
        lo = min(lo, uu)
        hi = max(hi, uu)
    return lo, hi, ssx, ssy


@_helper
def _leave_block(arr, e, w):  # pragma: no cover - compiled
    """Take window ``w`` out of edge ``e``'s block (an emptied block goes to its free list)."""
    bstart, bn = arr.bstart, arr.bn
    _block_remove(e, arr.pos[w], bstart, bn, arr.aw, arr.alo, arr.ahi, arr.pos)
    if bn[e] == 0:
        arr.aw[bstart[e]] = arr.fhead[arr.bcls[e]]
        arr.fhead[arr.bcls[e]] = bstart[e]
        bstart[e] = -1


@_helper
def _enter_face(mesh, arr, ctr, w, kids_h, kids_b):  # pragma: no cover - compiled
    """Window ``w`` enters its face: it leaves its edge's block, sets the distances of the
    vertices it reaches, and splits into children on the two far edges.

    Returns the number of children written to ``kids_h, kids_b``.
    """
    F, fl, cang, cpos, csgn = mesh.F, mesh.fl, mesh.cang, mesh.cpos, mesh.csgn
    wb, bpos = arr.wb, arr.bpos
    # out of its edge's block: only queued windows trim newcomers (measured: the popped ones
    # removed no more windows, and the blocks stay short)
    h = arr.wh[w]
    _leave_block(arr, mesh.hedge[h], w)
    b0 = wb[w, B0]
    b1 = wb[w, B1]
    sx = wb[w, SX]
    sy = wb[w, SY]
    sig = wb[w, SIG]
    f = h // 3
    c = h - 3 * f
    ia = F[f, (c + 1) % 3]
    ib = F[f, (c + 2) % 3]
    ic = F[f, c]
    L = fl[h]
    cx = mesh.fx[h]
    cy = mesh.fy[h]
    if _useless(arr.dist, ia, ib, ic, L, cx, cy, b0, b1, sx, sy, sig):
        return 0
    tol = _VIS * L
    pseudo, dist, via, vimg, hk, hv = mesh.pseudo, arr.dist, arr.via, arr.vimg, arr.hk, arr.hv
    # the window's ends may be the edge's vertices; the apex when visible
    if b0 <= tol and _reach(
        pseudo, dist, via, vimg, hk, hv, ctr, ia, sig + np.hypot(sx, sy), h, sx, sy
    ):
        # it arrives at A from below AB: past A's first edge (to B), away from C
        ca = 3 * f + (c + 1) % 3
        bpos[ia] = _ring_pos(cpos, csgn, ca, -np.arctan2(-sy, sx))
    if b1 >= L - tol and _reach(
        pseudo, dist, via, vimg, hk, hv, ctr, ib, sig + np.hypot(L - sx, sy), h, sx, sy
    ):
        # at B: past B's second edge (to A), away from C
        cb = 3 * f + (c + 2) % 3
        bpos[ib] = _ring_pos(cpos, csgn, cb, cang[cb] + np.arctan2(-sy, L - sx))
    # where the ray from s through the apex C crosses AB (a face without area, C on the line
    # AB, and s on that line too: the rays run along AB, C is at its place)
    tc = sx + (cx - sx) * (-sy) / (cy - sy) if cy > sy else cx
    if b0 - tol <= tc <= b1 + tol:
        if _reach(
            pseudo, dist, via, vimg, hk, hv, ctr, ic, sig + np.hypot(cx - sx, cy - sy), h, sx, sy
        ):
            # within C's corner: the angle from C->A to C->s (C->B is counterclockwise)
            qx = sx - cx
            qy = sy - cy
            psi = np.arctan2(-cx * qy + cy * qx, -cx * qx - cy * qy)
            bpos[ic] = _ring_pos(cpos, csgn, h, psi)
    nch = np.int64(0)  # typed (see _trim_on_edge)
    for side in range(2):
        if side == 0:
            # child on AC: rays through [b0, min(b1, tc)]; frame: C -> A
            x0, x1 = b0, min(b1, tc)
            hc = 3 * f + (c + 2) % 3
            ox, oy, ex, ey = cx, cy, -cx, -cy
        else:
            # child on CB: rays through [max(b0, tc), b1]; frame: B -> C
            x0, x1 = max(b0, tc), b1
            hc = 3 * f + (c + 1) % 3
            ox, oy, ex, ey = L, 0.0, cx - L, cy
        if x1 <= x0:
            continue
        t = mesh.twin[hc]
        if t < 0:
            continue  # a boundary edge: rays end there
        Lk = fl[hc]
        lo, hi, ssx, ssy = _unfold_child(x0, x1, ox, oy, ex / Lk, ey / Lk, Lk, sx, sy)
        if sy >= -tol and b0 - tol <= sx <= b1 + tol:
            # the source on the edge itself (sent across a face without area): it sees the
            # whole far edges, which the rays through the interval miss
            lo, hi = 0.0, Lk
        if hi <= lo:
            continue
        if mesh.rev[hc]:
            nch = _add_child(kids_h, kids_b, nch, t, Lk - hi, Lk - lo, Lk - ssx, -ssy, sig)
        else:
            nch = _add_child(kids_h, kids_b, nch, t, lo, hi, ssx, -ssy, sig)
    return nch


@_helper
def _trim_on_edge(mesh, arr, t, b0, b1, sx, sy, sig):  # pragma: no cover - compiled
    """Trim a new window (on half-edge ``t``) and the windows queued on its edge against each
    other (:func:`_resolve`), merging it with those of the same unfolded source.

    Returns what is left of the new window's interval (``b1 <= b0``: nothing).
    """
    wb, aw, alo, ahi = arr.wb, arr.aw, arr.alo, arr.ahi
    L = mesh.fl[t]
    e = mesh.hedge[t]
    flip = mesh.rev[t]
    cf = mesh.cflip[t]
    sy2 = sy * sy
    base = arr.bstart[e]
    i = np.int64(0)  # typed: a literal 0 compiles the steps it is passed to again
    while i < arr.bn[e]:
        o = aw[base + i]
        # overlap test in the common frame, from the block (no access to o's row)
        c0 = L - b1 if cf else b0
        c1 = L - b0 if cf else b1
        # (touching windows go on: they may be two pieces of one window, see below)
        if ahi[base + i] < c0 - _TOUCH * L or alo[base + i] > c1 + _TOUCH * L:
            i += 1
            continue
        olo = wb[o, B0]
        ohi = wb[o, B1]
        ox = wb[o, SX]
        same = arr.wh[o] == t
        if same:
            # the same unfolded source (across flat vertices: the two children of a window
            # split at a vertex meet again behind it): one window for both
            mtol = _MERGE * (abs(sx) + abs(sy) + sig + L)
            if (
                abs(ox - sx) <= mtol
                and abs(wb[o, SY] - sy) <= mtol
                and abs(wb[o, SIG] - sig) <= mtol
            ):
                if olo <= b0 and ohi >= b1:
                    return b0, b0  # nothing new: the queued one covers it
                b0 = min(b0, olo)
                b1 = max(b1, ohi)
                arr.state[o] = DEAD
                _block_remove(e, i, arr.bstart, arr.bn, aw, alo, ahi, arr.pos)
                i = np.int64(0)  # the wider window may overlap windows already passed
                continue
        if not same and flip:
            olo, ohi = L - ohi, L - olo
            ox = L - ox
        oy2 = wb[o, SY] * wb[o, SY]
        osg = wb[o, SIG]
        b0, b1, nlo, nhi = _resolve(b0, b1, sx, sy2, sig, olo, ohi, ox, oy2, osg, L)
        if b1 <= b0:
            return b0, b1
        if nhi <= nlo:
            arr.state[o] = DEAD  # out of the block; its slot is freed when popped
            _block_remove(e, i, arr.bstart, arr.bn, aw, alo, ahi, arr.pos)
            continue  # the block's last window moved to i
        if nlo != olo or nhi != ohi:
            if not same and flip:
                nlo, nhi = L - nhi, L - nlo
            wb[o, B0] = nlo
            wb[o, B1] = nhi
            if mesh.cflip[arr.wh[o]]:
                alo[base + i] = L - nhi
                ahi[base + i] = L - nlo
            else:
                alo[base + i] = nlo
                ahi[base + i] = nhi
        i += 1
    return b0, b1


@_small
def _new_block(aw, alo, ahi, bstart, bcls, fhead, ctr, e, k):  # pragma: no cover - compiled
    """Give edge ``e`` (``k`` windows; its block full, or none yet) a block of twice the
    capacity (the first: 4), its windows moved there and the old block put on its free list."""
    cls = 0 if bstart[e] < 0 else bcls[e] + 1
    size = 4 << cls
    if fhead[cls] >= 0:
        nb = fhead[cls]
        fhead[cls] = aw[nb]
    else:
        nb = ctr[C_ARENA_TOP]
        ctr[C_ARENA_TOP] += size
        ctr[C_MAX_BLOCK] = max(ctr[C_MAX_BLOCK], size)
    if bstart[e] >= 0:
        ob = bstart[e]
        for j in range(k):
            aw[nb + j] = aw[ob + j]
            alo[nb + j] = alo[ob + j]
            ahi[nb + j] = ahi[ob + j]
        aw[ob] = fhead[bcls[e]]
        fhead[bcls[e]] = ob
    bstart[e] = nb
    bcls[e] = cls


@_helper
def _block_add(arr, ctr, e, w, lo, hi):  # pragma: no cover - compiled
    """Append window ``w`` (extent ``[lo, hi]`` in the edge's common frame) to edge ``e``'s
    block, moved into a new block of twice the capacity when it is full (:func:`_new_block`)."""
    aw, alo, ahi, bstart = arr.aw, arr.alo, arr.ahi, arr.bstart
    k = arr.bn[e]
    if bstart[e] < 0 or k == 4 << arr.bcls[e]:
        _new_block(aw, alo, ahi, bstart, arr.bcls, arr.fhead, ctr, e, k)
    base = bstart[e]
    aw[base + k] = w
    alo[base + k] = lo
    ahi[base + k] = hi
    arr.pos[w] = k
    arr.bn[e] = k + 1


@_helper
def _queue_child(mesh, arr, ctr, kids_h, kids_b, j):  # pragma: no cover - compiled
    """Child ``j`` of a step (a window on half-edge ``kids_h[j]``): pruned, trimmed against
    its edge's windows, and queued (a window slot, its edge's block, the heap) if anything is
    left."""
    t = kids_h[j]
    b0, b1, sx, sy, sig = kids_b[j, B0], kids_b[j, B1], kids_b[j, SX], kids_b[j, SY], kids_b[j, SIG]
    F, fl, dist = mesh.F, mesh.fl, arr.dist
    f = t // 3
    c = t - 3 * f
    L = fl[t]
    ia, ib, ic = F[f, (c + 1) % 3], F[f, (c + 2) % 3], F[f, c]
    if _useless(dist, ia, ib, ic, L, mesh.fx[t], mesh.fy[t], b0, b1, sx, sy, sig):
        return
    b0, b1 = _trim_by_ends(dist[ia], dist[ib], L, b0, b1, sx, sy, sig)
    if b1 <= b0:
        return
    b0, b1 = _trim_on_edge(mesh, arr, t, b0, b1, sx, sy, sig)
    if b1 <= b0:
        return
    # its key: the least distance it gives
    if b0 <= sx <= b1:
        kk = sig + abs(sy)
    else:
        kk = sig + min(np.sqrt((b0 - sx) ** 2 + sy * sy), np.sqrt((b1 - sx) ** 2 + sy * sy))
    if ctr[C_FREE] > 0:
        ctr[C_FREE] -= 1
        w = arr.free[ctr[C_FREE]]
    else:
        w = ctr[C_USED]
        ctr[C_USED] += 1
    ctr[C_CREATED] += 1
    wb = arr.wb
    arr.wh[w] = t
    wb[w, B0] = b0
    wb[w, B1] = b1
    wb[w, SX] = sx
    wb[w, SY] = sy
    wb[w, SIG] = sig
    arr.state[w] = QUEUED
    if mesh.cflip[t]:
        lo, hi = L - b1, L - b0
    else:
        lo, hi = b0, b1
    _block_add(arr, ctr, mesh.hedge[t], w, lo, hi)
    ctr[C_HEAP] = heap_push(arr.hk, arr.hv, ctr[C_HEAP], kk, w)


@kernel(nogil=True, _nrt=False)
def propagate(mesh, arr, ctr, max_pops, targets):  # pragma: no cover - compiled
    """Exact distances from the sources queued in ``arr.hk, arr.hv`` (see the module docstring).

    Each step takes the least item out of the queue: a pseudo-source emits
    (:func:`_emit_from_vertex`) or a window enters its face (:func:`_enter_face`), and the
    children that step makes are each pruned, trimmed against their edge's windows and queued
    (:func:`_queue_child`).  The steps are compiled into this function, which counts no
    references and allocates nothing (``_helper``, ``_small``).

    ``mesh`` (:class:`MeshArrays`): ``fl, fx, fy`` (#F*3,): for half-edge ``h = 3 f + c`` (the
    edge opposite corner ``c``, from ``F[f, c+1]`` to ``F[f, c+2]``) its length and the apex
    ``F[f, c]`` in its frame.  ``twin`` (#F*3,): the same edge seen from the other face (-1 on
    the boundary); ``rev``: the twin runs the other way; ``hedge``: the edge id; ``cflip``: the
    half-edge's frame is the mirror image (``x -> L - x``) of its edge's common frame (that of
    the edge's first half-edge).  ``cang, cpos, csgn`` (#F*3,): for the corner opposite
    half-edge ``h``, its angle, the ring position of its first edge (to ``F[f, c+1]``; the
    angle from the first edge of the one-ring of the corner's vertex) and its turn (+1 or -1)
    in that ring (0: the vertex has no ring to walk, non-manifold); ``theta`` (#V,): total
    angles; ``vbnd``: boundary vertices (their ring starts at a boundary edge); ``mdeg``: the
    largest vertex degree.

    ``arr`` (:class:`QueryArrays`) and the counters ``ctr`` (indexed by the ``C_*`` names) are
    the propagation's state, carried from call to call
    (:class:`~meschers_igl.geodesic.exact._State`).  ``via, vimg`` record where each vertex's
    distance came from: ``via[v] = h >= 0`` a window on half-edge ``h`` whose source image is
    ``vimg[v]`` in ``h``'s frame, ``via[v] = -(u + 1)`` the edge from vertex ``u``.  The kernel
    runs until the queue is empty (:data:`DONE`), ``max_pops`` items were taken out
    (:data:`REPORT`), or the heap, the window table or the edge blocks' arena might not hold
    one more step (:data:`GROW_HEAP`, :data:`GROW_WINDOWS`, :data:`GROW_ARENA`); the caller then
    grows that array and calls again.  Room is checked before each step, not at each write, so
    that a step is never left half done.  With ``targets`` (non-empty) it also ends
    (:data:`DONE`) once the least key left is at least every target's distance: no later item
    can lower a distance below its key, so those are final.

    The windows queued on an edge are kept in one contiguous block per edge (ids and their
    extent in the edge's common frame), so that finding the ones a new window overlaps is a
    scan of a few cache lines; a linked list through the window table cost one cache miss per
    queued window, and there are ``O(sqrt n)`` of them per edge (measured: 35 per new window at
    100k faces, 3/4 of the time).
    """
    kids_h, kids_b = arr.kids_h, arr.kids_b  # the children of one step
    pops = 0
    while True:
        status = _room(mesh, arr, ctr, pops, max_pops, targets)
        if status != _GO:
            return status
        pops += 1
        key, item, ctr[C_HEAP] = heap_pop(arr.hk, arr.hv, ctr[C_HEAP])
        if item < 0:
            v = -item - 1
            if key > arr.dist[v] or arr.emitted[v] <= key:
                continue  # stale event
            arr.emitted[v] = key
            nch = _emit_from_vertex(mesh, arr, ctr, v, key, kids_h, kids_b)
        else:
            arr.free[ctr[C_FREE]] = item
            ctr[C_FREE] += 1
            if arr.state[item] != QUEUED:
                continue
            nch = _enter_face(mesh, arr, ctr, item, kids_h, kids_b)
        for j in range(nch):
            _queue_child(mesh, arr, ctr, kids_h, kids_b, j)
