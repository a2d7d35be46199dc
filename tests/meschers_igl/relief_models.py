"""A Reutersvärd relief built the way an artist builds one (for tests/meschers_igl/test_relief.py).

Independent of the code under test: cubes as convex blocks (``visible_models.convex_block``),
moved along the view by affine shears solved here, compressed in depth, welded by coordinates.

The figure: Reutersvärd's triangle of ``3 k`` touching cubes (each shares a face with the next;
twelve by default, ``k = 4``) seen along (1, 1, 1) -- ``k`` steps of one cube along x, then y,
then z, so the path returns to its start on screen, ``T = k a (1, 1, 1)`` nearer the viewer.
(Reutersvärd drew nine separate cubes; touching ones are what a person reads as one surface,
and nine touching cubes cannot be carved: see :func:`reutersvard_relief`.)  A person assuming
right angles reads cubes that climb ``|T| = sqrt(3) k a`` per turn; a carver cannot cut that,
so the relief:

1. **shears** each cube ``i`` along the view by ``-s_i(p) T`` with ``s_i`` affine and
   continuous across every face two cubes share (``s_{i+1} - s_i = c_i ((p - q_i) . n_i)``
   vanishes on the shared face's plane), rising by one per turn (``s_last(p) = s_0(p - T) + 1``):
   the last cube lands on the first one and the chain closes into a real torus.  The climb is
   spread evenly over the cubes inside the bars (corners stay rigid, :func:`seam_shears`), so
   no cube folds and no two cubes overlap in 3D.  Screen positions do not change
   (orthographic), every face stays planar.
2. **compresses** depth by ``lam`` (bas-relief): ``p -> p - (1 - lam) (p . v) v``.  The face
   normals lean toward the viewer; their screen directions, which a person reads the frame
   from, do not change.

Why the shears cannot be avoided (a fact, not a choice): on a connected visible surface whose
glued edges all run along the three screen axis directions ``d_k``, face gradients ``g_k`` that
are the same for all faces of a family must satisfy ``(g_i - g_j) . d_k^perp = 0`` on every
family pair, which leaves only ``g_k = t G_k + g`` (``G_k`` the right-angled gradients, ``g`` a
tilt); the loop integral is then ``t`` times the perceived climb, zero only for a flat relief.
So a relief that reads as this triangle has faces *near* three families, not on them.
"""

from __future__ import annotations

import numpy as np
from visible_models import AXES, ISO_VIEW, convex_block, weld_blocks


def cube_path(k: int = 4, a: float = 1.0):
    """Centres of the ``3 k`` cubes on the perceived (unrolled) path, and the interfaces.

    The path starts in the middle of the x side so that the closing seam is an ordinary face
    between two cubes of a bar (not a corner): centres ``c_0 = (k - 1) a x``, then steps of
    ``a`` along x (1 step to the corner), y (k), z (k), x (k - 1).  Returns ``(centres (3k, 3),
    normals (3k, 3), points (3k, 3), T)``: the interface ``i`` separates cube ``i`` from cube
    ``i + 1`` (the last one from cube ``0 + T``)."""
    steps = [AXES[0]] + [AXES[1]] * k + [AXES[2]] * k + [AXES[0]] * (k - 1)
    c = [(k - 1) * a * AXES[0]]
    for d in steps:
        c.append(c[-1] + a * d)
    c = np.asarray(c)
    T = c[-1] - c[0]  # k a (1, 1, 1)
    n = np.asarray(steps)
    q = 0.5 * (c[:-1] + c[1:])
    return c[:-1], n, q, T


def seam_shears(n: np.ndarray, a: float = 1.0) -> tuple[np.ndarray, float]:
    """Kinks ``c_i`` at the seams and the slope ``g`` of the shear ``s`` along the path.

    The corner cubes stay rigid (``s`` constant: a corner's two seams have different normals,
    and an affine ``s`` continuous across both with no gradient across the bars must be
    constant); each of the ``3 (k - 1)`` cubes inside a bar rises by ``g`` along the bar, so
    ``g = 1 / (3 (k - 1))`` closes the turn.  Entering a bar from a corner the kink is ``+g /
    a``, leaving it into a corner ``-g / a``, 0 between two cubes of a bar.  ``g (T . d) / a = k
    g < 1`` keeps every sheared cube the right way round (no fold)."""
    m = n.shape[0]
    corner = np.zeros(m + 1, dtype=bool)  # cube i turns the path (cube m is cube 0 again)
    corner[1:m] = np.any(n[1:] != n[:-1], axis=1)
    g = 1.0 / np.count_nonzero(~corner[:m])
    return (g / a) * (corner[:m].astype(float) - corner[1:].astype(float)), g


def relief_blocks(k: int = 4, a: float = 1.0, lam: float = 0.3):
    """The relief's cubes, each sheared and compressed (a convex block), before welding.

    Returns
    -------
    blocks : list of (V (8, 3), polygons)
        Polygons in the order ``+x, -x, +y, -y, +z, -z`` (outward, CCW).
    T : (3,) the perceived climb per turn ``k a (1, 1, 1)``
    n : (3k, 3) the seam normals (seam ``i`` between cube ``i`` and ``i + 1``, cyclic)
    """
    centres, n, q, T = cube_path(k, a)
    coef, g = seam_shears(n, a)
    v = ISO_VIEW
    blocks = []
    # s_0 rises by g across cube 0 (inside the x bar): s_0(p) = g (x - x_0 + a / 2) / a
    s0_lin, s0_off = (g / a) * AXES[0], -(g / a) * (centres[0, 0] - a / 2)
    s_lin, s_off = s0_lin, s0_off  # s_i(p) = s_lin . p + s_off
    for i, ctr in enumerate(centres):
        hs = np.array([np.r_[e * sg, -(ctr @ (e * sg)) - a / 2] for e in AXES for sg in (1, -1)])
        Vb, Pb = convex_block(hs, ctr)
        if len(Pb) != 6:
            raise AssertionError("a cube with other than 6 faces")  # a builder bug, not input
        Vb = Vb - (Vb @ s_lin + s_off)[:, None] * T[None, :]
        Vb = Vb - (1.0 - lam) * (Vb @ v)[:, None] * v[None, :]  # bas-relief: depth times lam
        blocks.append((Vb, Pb))
        # across seam i: s_{i+1} = s_i + c_i (p - q_i) . n_i
        s_lin = s_lin + coef[i] * n[i]
        s_off = s_off - coef[i] * (q[i] @ n[i])
    # one turn later the shear is the first cube's plus one: the last cube lands on the first
    if not (np.allclose(s_lin, s0_lin) and np.isclose(s_off, s0_off - s0_lin @ T + 1.0)):
        raise AssertionError("the shears do not close the turn")  # a builder bug, not input
    return blocks, T, n


def reutersvard_relief(k: int = 4, a: float = 1.0, lam: float = 0.3, with_axes: bool = False):
    """Reutersvärd's triangle of ``3 k`` touching cubes as a shallow closed relief (a torus).

    ``k = 3`` (Reutersvärd's nine cubes) cannot be carved: the cubes just before and after an
    inner corner overlap on screen ``sqrt(3) a`` apart in depth, and the shear between them is
    2 of the ``3 (k - 1)`` bar cubes' rises, ``2 k / (3 (k - 1))`` of that distance -- all of it
    for ``k = 3`` (they touch at a vertex, a pinch), 8/9 for ``k = 4``.

    Returns
    -------
    V : (#V, 3), polygons : list of quads, perceived_period : float[, axes]
        The welded model (world frame, seen along ``ISO_VIEW``), its faces (each cube face a
        quad; faces two cubes share are removed), and the climb per turn a person assuming
        right angles perceives, ``sqrt(3) k a`` -- computed from the path, not from the model.
        ``with_axes``: also the cube axis (0, 1, 2 for x, y, z) each quad is a face of.
    """
    blocks, T, n = relief_blocks(k, a, lam)
    V, polys = weld_blocks(blocks)
    if not with_axes:
        return V, polys, float(np.linalg.norm(T))
    # faces kept by weld_blocks, in order: all but the two each seam glues (cube i's face
    # toward seam i, cube i + 1's face away from it); face j of a cube is axis j // 2
    m = len(blocks)
    glued = np.zeros((m, 6), dtype=bool)
    for i in range(m):
        ax = int(np.argmax(np.abs(n[i])))
        glued[i, 2 * ax + (n[i, ax] < 0)] = True
        glued[(i + 1) % m, 2 * ax + (n[i, ax] > 0)] = True
    axes = np.tile(np.arange(6) // 2, m)[~glued.reshape(-1)]
    if axes.size != len(polys):
        raise AssertionError("face axes do not match the welded faces")  # a builder bug
    return V, polys, float(np.linalg.norm(T)), axes


def flat_backed_relief(k: int = 4, a: float = 1.0, lam: float = 0.3, back: float = 0.5):
    """The same relief as a modelling tool makes it: each cube extruded along the view to one
    flat back plane (a prism: the cube's front faces, walls parallel to the view, the back) and
    the twelve prisms joined by Boolean union (PyMeshLab's, as exported: triangles, duplicate
    vertices, zero-area slivers where the union conforms).  A thick annulus with a flat back,
    ``back`` behind the nearest-to-back cube corner; its front is the torus relief's front.

    Returns
    -------
    V : (#V, 3), F : (#F, 3) int64, perceived_period : float
    """
    import pymeshlab
    from scipy.spatial import ConvexHull

    blocks, T, _ = relief_blocks(k, a, lam)
    v = ISO_VIEW
    z_back = min(float((b[0] @ v).min()) for b in blocks) - back
    ms = pymeshlab.MeshSet()
    acc = None
    for Vb, _ in blocks:
        # a convex block over a flat back: the hull of its corners and their shadows on the back
        P = np.vstack([Vb, Vb - ((Vb @ v) - z_back)[:, None] * v[None, :]])
        Fh = ConvexHull(P).simplices.copy()
        Tr = P[Fh]
        out = np.einsum(
            "ij,ij->i",
            np.cross(Tr[:, 1] - Tr[:, 0], Tr[:, 2] - Tr[:, 0]),
            Tr.mean(axis=1) - P.mean(axis=0),
        )
        Fh[out < 0] = Fh[out < 0][:, ::-1]  # outward
        ms.add_mesh(pymeshlab.Mesh(P, Fh))
        if acc is not None:
            ms.generate_boolean_union(first_mesh=acc, second_mesh=ms.current_mesh_id())
        acc = ms.current_mesh_id()
    mesh = ms.current_mesh()
    return mesh.vertex_matrix(), mesh.face_matrix().astype(np.int64), float(np.linalg.norm(T))
