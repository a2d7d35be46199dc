"""A SoftRas-style soft rasterizer for flattened meschers (Liu et al. 2019), in PyTorch.

A mescher is rendered flat (paper Section 4.1): every triangle lies in the screen plane at its
``xy``, is shaded with the normal of its *local* corners ``(x, y, local depth)``, and overlapping
triangles are ordered by one scalar depth offset per face (paper Section 4.5). The soft version
below is differentiable with respect to ``xy`` (through coverage and normals), ``zeta`` (through
the normals) and the offsets (through the soft z-ordering).

For a pixel centre ``p`` and a face ``j`` (Liu et al. 2019, Eqs. 1-4):

- coverage ``D_j(p) = sigmoid(delta_j(p) d_j(p)^2 / sigma)``, ``d_j`` the distance from ``p`` to
  the triangle's boundary, ``delta_j = +1`` inside and ``-1`` outside;
- silhouette ``alpha(p) = 1 - prod_j (1 - S_j(p))``, ``S_j`` as ``D_j`` but with the distance
  to the face's *silhouette* edges only (see below);
- colour ``c(p) = sum_j w_j C_j`` with ``w_j proportional to D_j exp(o_j / gamma)``, ``o_j`` the
  face's depth offset (larger is nearer the viewer);
- image ``I(p) = alpha(p) c(p) + (1 - alpha(p)) C_background``.

Two departures from SoftRas, both for pictures of meshes rather than of single triangles:

- SoftRas mixes the background into the softmax with a fixed logit ``eps / gamma``; with the
  small ``gamma`` needed for crisp z-ordering every face then wins over the background out to
  the culling radius, so silhouettes become hard steps at the wrong place.  Compositing with the
  soft silhouette keeps them soft and centred.
- SoftRas's silhouette ``1 - prod_j (1 - D_j)`` is 3/4 on every edge shared by two faces (each
  has ``D = 1/2`` there), which draws a faint wireframe over the whole object, and it grows
  outward where thin faces pile up along a fold.  ``S_j`` measures the distance to the edges
  where the covered region really ends (mesh boundary and folds, :func:`silhouette_edges`):
  inside a triangulated region it is 1, at the outline it is SoftRas's ``D_j``.  Colours keep
  SoftRas's ``D_j``, which anti-aliases and differentiates creases between faces.

Speed: each face is evaluated only on its pixel window (bounding
box widened by the radius where ``D`` falls below ``1e-4``), faces batched by window size, and
face-pixel pairs outside the face with ``D < 1e-4`` are dropped, as the official SoftRas code
does (otherwise far faces swamp the background).
"""

from __future__ import annotations

import math

import numpy as np

from ._torch import require_torch

torch = require_torch()

from ..errors import MescherError  # noqa: E402

Tensor = torch.Tensor

#: face-pixel pairs with coverage below this (and outside the face) are dropped (SoftRas)
COVERAGE_CUTOFF = 1e-4
#: logit of COVERAGE_CUTOFF: a pair is kept when ``delta d^2 / sigma`` is above it
_LOGIT_CUTOFF = math.log(COVERAGE_CUTOFF / (1.0 - COVERAGE_CUTOFF))
#: |d_sil^2 / sigma| is clamped here: coverage is then 1 - 2e-22 or 2e-22
_SIL_CLAMP = 50.0


def pixel_centers(resolution: int | tuple[int, int], dtype=None, device=None) -> Tensor:
    """Screen positions of the pixel centres of an image spanning ``[-1, 1]^2``.

    Parameters
    ----------
    resolution : int or (H, W)
        Image size in pixels.
    dtype : torch.dtype, optional
        Default ``torch.get_default_dtype()``.
    device : torch.device, optional
        Default CPU.

    Returns
    -------
    (H*W, 2) tensor
        Row-major (row 0 at the top, y up): pixel ``(i, j)`` is at
        ``x = -1 + (2 j + 1) / W``, ``y = 1 - (2 i + 1) / H``.
    """
    H, W = _resolution(resolution)
    dtype = dtype or torch.get_default_dtype()
    x = -1.0 + (2.0 * torch.arange(W, dtype=dtype, device=device) + 1.0) / W
    y = 1.0 - (2.0 * torch.arange(H, dtype=dtype, device=device) + 1.0) / H
    return torch.stack(torch.meshgrid(x, y, indexing="xy"), dim=-1).reshape(-1, 2)


def _resolution(resolution) -> tuple[int, int]:
    if isinstance(resolution, (int, np.integer)):
        resolution = (int(resolution), int(resolution))
    try:
        H, W = (int(r) for r in resolution)
    except (TypeError, ValueError) as exc:
        raise MescherError(
            f"resolution: expected an int or (H, W) of positive ints, found {resolution!r}"
        ) from exc
    if H < 1 or W < 1:
        raise MescherError(f"resolution: expected positive sizes, found {(H, W)}")
    return H, W


def corner_depths_from_zeta(zeta: Tensor, face_edges: Tensor, face_edge_signs: Tensor) -> Tensor:
    """Per-face local corner depths (corner 0 at depth 0) from a locally integrable ``zeta``.

    Parameters
    ----------
    zeta : (#E,) tensor
        Relative depth per edge, ``zeta[e] = depth(head) - depth(tail)``.
    face_edges : (#F, 3) int64 tensor
        Edge opposite each corner (core convention, libigl's column order).
    face_edge_signs : (#F, 3) tensor
        ``+1`` where the stored edge runs ``F[f, i+1] -> F[f, i+2]``, else ``-1``.

    Returns
    -------
    (#F, 3) tensor
        ``Z[f] = (0, zeta_{01}, -zeta_{20})``; the edge opposite corner 2 runs 0 -> 1 and the one
        opposite corner 1 runs 2 -> 0.  Equals ``(0, zeta_01, zeta_01 + zeta_12)`` when
        ``d12 zeta = 0``.
    """
    s = face_edge_signs.to(zeta.dtype)
    z1 = s[:, 2] * zeta[face_edges[:, 2]]
    z2 = -s[:, 1] * zeta[face_edges[:, 1]]
    return torch.stack([torch.zeros_like(z1), z1, z2], dim=1)


def local_face_normals(F: Tensor, xy: Tensor, Z: Tensor, eps: float = 1e-30) -> Tensor:
    """Unit normals of the local corners ``(x, y, Z)`` of each face, camera frame.

    Parameters
    ----------
    F : (#F, 3) int64 tensor
    xy : (#V, 2) tensor
        Screen positions.
    Z : (#F, 3) tensor
        Local corner depths (any per-face offset).

    Returns
    -------
    (#F, 3) tensor
        ``n = (p1 - p0) x (p2 - p0) / |...|`` with ``p_i = (x_i, y_i, Z_i)``; ``n_z > 0`` for a
        face whose screen orientation is counter-clockwise.
    """
    P = xy[F]  # (#F, 3, 2)
    e1 = torch.cat([P[:, 1] - P[:, 0], (Z[:, 1] - Z[:, 0])[:, None]], dim=1)
    e2 = torch.cat([P[:, 2] - P[:, 0], (Z[:, 2] - Z[:, 0])[:, None]], dim=1)
    n = torch.linalg.cross(e1, e2, dim=1)
    return n / torch.sqrt((n * n).sum(dim=1, keepdim=True) + eps)


def face_normals_from_zeta(
    F: Tensor, xy: Tensor, zeta: Tensor, face_edges: Tensor, face_edge_signs: Tensor
) -> Tensor:
    """Unit face normals of a mescher from ``xy`` and ``zeta`` (paper Section 3.1).

    See :func:`corner_depths_from_zeta` and :func:`local_face_normals`; (#F, 3).
    """
    return local_face_normals(F, xy, corner_depths_from_zeta(zeta, face_edges, face_edge_signs))


def lambertian(
    normals: Tensor,
    lights,
    light_colors=None,
    ambient=0.2,
    albedo=1.0,
) -> Tensor:
    """Flat Lambertian shading under directional lights plus ambient light.

    Parameters
    ----------
    normals : (#F, 3) tensor
        Unit normals, camera frame (z toward the viewer).
    lights : (L, 3) array_like
        Directions *toward* each light (normalized here), camera frame.
    light_colors : (L, 3) array_like, optional
        RGB intensity of each light; default white, ``(1 - ambient) / L`` each.
    ambient : float or (3,) array_like, default: 0.2
    albedo : float or (3,) array_like, default: 1.0

    Returns
    -------
    (#F, 3) tensor
        ``C_f = albedo * (ambient + sum_l color_l max(0, n_f . l))``.
    """
    dt, dev = normals.dtype, normals.device
    L = _as_lights(lights, dt).to(dev)
    amb = torch.as_tensor(ambient, dtype=dt, device=dev).reshape(-1)
    if light_colors is None:
        colors = torch.full(
            (L.shape[0], 3), float(1.0 - amb.mean()) / L.shape[0], dtype=dt, device=dev
        )
    else:
        colors = torch.as_tensor(np.asarray(light_colors, dtype=np.float64), dtype=dt, device=dev)
        if colors.shape != (L.shape[0], 3):
            raise MescherError(
                f"light_colors: expected shape ({L.shape[0]}, 3), found {tuple(colors.shape)}"
            )
    lit = torch.relu(normals @ L.T) @ colors  # (#F, 3)
    return torch.as_tensor(albedo, dtype=dt, device=dev) * (amb + lit)


def _as_lights(lights, dtype) -> Tensor:
    L = np.asarray(lights, dtype=np.float64)
    if L.ndim == 1:
        L = L[None]
    if L.ndim != 2 or L.shape[1] != 3 or L.shape[0] == 0 or not np.all(np.isfinite(L)):
        raise MescherError(f"lights: expected (L, 3) finite directions, found {L.shape}")
    norms = np.linalg.norm(L, axis=1)
    if np.any(norms == 0):
        raise MescherError("lights: expected nonzero directions, found a zero vector")
    return torch.as_tensor(L / norms[:, None], dtype=dtype)


def silhouette_edges(F, xy) -> np.ndarray:
    """Which face edges bound the covered screen region (boundary and fold edges).

    Edge ``k`` of face ``f`` runs from corner ``k`` to corner ``k + 1``.  It is *interior* when
    another face traverses it the opposite way (a consistently oriented neighbour) with the same
    screen orientation: the two faces then lie on opposite sides of it on screen.  Otherwise it
    is a mesh boundary or a fold (the neighbour is folded under or over the face), where the
    covered region ends.

    Parameters
    ----------
    F : (#F, 3) int array_like
    xy : (#V, 2) float array_like

    Returns
    -------
    (#F, 3) bool ndarray
        True on silhouette edges.
    """
    F = np.asarray(F, dtype=np.int64)
    P = np.asarray(xy, dtype=np.float64)[F]
    area2 = (P[:, 1, 0] - P[:, 0, 0]) * (P[:, 2, 1] - P[:, 0, 1]) - (P[:, 1, 1] - P[:, 0, 1]) * (
        P[:, 2, 0] - P[:, 0, 0]
    )
    up = np.repeat((area2 >= 0)[:, None], 3, axis=1).astype(np.int64)
    n = int(F.max(initial=0)) + 1
    tail, head = F, F[:, [1, 2, 0]]
    # half-edge key with the face's screen orientation; the twin has head and tail swapped
    keys = (tail * n + head) * 2 + up
    twins = (head * n + tail) * 2 + up
    return ~np.isin(twins, keys)


def _windows(P: Tensor, radius: float, H: int, W: int):
    """Pixel windows of faces: first row/column and size, each face's box widened by radius."""
    lo = P.min(dim=1).values - radius
    hi = P.max(dim=1).values + radius
    # column j has x = -1 + (2j+1)/W, row i has y = 1 - (2i+1)/H
    j0 = torch.ceil((lo[:, 0] + 1.0) * (W / 2.0) - 0.5).clamp(0, W - 1).long()
    j1 = torch.floor((hi[:, 0] + 1.0) * (W / 2.0) - 0.5).clamp(-1, W - 1).long()
    i0 = torch.ceil((1.0 - hi[:, 1]) * (H / 2.0) - 0.5).clamp(0, H - 1).long()
    i1 = torch.floor((1.0 - lo[:, 1]) * (H / 2.0) - 0.5).clamp(-1, H - 1).long()
    return i0, j0, (i1 - i0 + 1).clamp(min=0), (j1 - j0 + 1).clamp(min=0)


def _candidate_pairs(P: Tensor, radius: float, H: int, W: int) -> tuple[Tensor, Tensor]:
    """All (face, pixel) pairs in the faces' windows; faces batched by window size.

    Windows are rounded up to powers of two per axis so that a handful of batches (each a dense
    (faces, rows, cols) grid, masked to the true window) covers all faces without Python loops
    over faces.
    """
    i0, j0, hh, ww = _windows(P, radius, H, W)
    nonempty = (hh > 0) & (ww > 0)
    bh = torch.where(nonempty, 2 ** torch.ceil(torch.log2(hh.clamp(min=1).double())).long(), 0)
    bw = torch.where(nonempty, 2 ** torch.ceil(torch.log2(ww.clamp(min=1).double())).long(), 0)
    key = bh * (4 * max(H, W) + 1) + bw
    faces_out, pix_out = [], []
    for k in torch.unique(key[nonempty]).tolist():
        f = torch.nonzero(key == k).squeeze(1)
        sh, sw = int(bh[f[0]]), int(bw[f[0]])
        di = torch.arange(sh, device=P.device)[None, :, None]
        dj = torch.arange(sw, device=P.device)[None, None, :]
        ok = (di < hh[f, None, None]) & (dj < ww[f, None, None])
        pix = (i0[f, None, None] + di) * W + (j0[f, None, None] + dj)
        ff = f[:, None, None].expand_as(pix)
        faces_out.append(ff[ok])
        pix_out.append(pix[ok])
    if not faces_out:
        empty = torch.zeros(0, dtype=torch.long, device=P.device)
        return empty, empty
    return torch.cat(faces_out), torch.cat(pix_out)


def _signed_scaled_dist(
    tri: Tensor, p: Tensor, sigma: float, eps: float, sil: Tensor | None = None
) -> tuple[Tensor, Tensor | None]:
    """``delta d^2 / sigma`` for (face, pixel) pairs: tri (P, 3, 2), p (P, 2) -> (P,).

    With ``sil`` (P, 3) bool, also ``delta d_sil^2 / sigma`` where ``d_sil`` is the distance to
    the face's silhouette edges only, clamped to ``+-_SIL_CLAMP`` (no silhouette edge: the
    clamp).  Works on x and y columns separately: reductions over a trailing axis of length 2
    are several times slower in PyTorch on the CPU than the explicit sums.
    """
    ax, ay = tri[:, 0, 0], tri[:, 0, 1]
    bx, by = tri[:, 1, 0], tri[:, 1, 1]
    cx, cy = tri[:, 2, 0], tri[:, 2, 1]
    px, py = p[:, 0], p[:, 1]
    area2 = (bx - ax) * (cy - ay) - (by - ay) * (cx - ax)
    d2 = d2s = inside = None
    big = _SIL_CLAMP * sigma
    for k, (sx, sy, tx, ty) in enumerate(((ax, ay, bx, by), (bx, by, cx, cy), (cx, cy, ax, ay))):
        ex, ey = tx - sx, ty - sy
        wx, wy = px - sx, py - sy
        # inside iff p is on the interior side of every edge, whatever the orientation; closed
        # triangles, so that a pixel centre on an interior edge is covered by both faces
        side = ((ex * wy - ey * wx) * area2) >= 0
        inside = side if inside is None else inside & side
        u = ((wx * ex + wy * ey) / (ex * ex + ey * ey + eps)).clamp(0.0, 1.0)
        rx, ry = wx - u * ex, wy - u * ey
        dk = rx * rx + ry * ry
        d2 = dk if d2 is None else torch.minimum(d2, dk)
        if sil is not None:
            dks = torch.where(sil[:, k], dk.clamp(max=big), big)
            d2s = dks if d2s is None else torch.minimum(d2s, dks)
    inside = inside & (area2 != 0)  # a degenerate face covers nothing
    x = torch.where(inside, d2, -d2) / sigma
    xs = None if sil is None else torch.where(inside, d2s, -d2s) / sigma
    return x, xs


def soft_rasterize(
    F: Tensor,
    xy: Tensor,
    colors: Tensor,
    offsets: Tensor,
    resolution: int | tuple[int, int] = 128,
    sigma: float = 1e-4,
    gamma: float = 1e-2,
    background=(1.0, 1.0, 1.0),
    return_alpha: bool = False,
    silhouette="auto",
):
    """Soft-rasterize flat-shaded triangles over the screen square ``[-1, 1]^2``.

    Parameters
    ----------
    F : (#F, 3) int64 tensor
        Triangles (either screen orientation).
    xy : (#V, 2) tensor
        Screen positions (differentiable).
    colors : (#F, C) tensor
        Flat colour of each face, e.g. from :func:`lambertian` (differentiable).
    offsets : (#F,) tensor
        Depth offset per face, larger is nearer the viewer (differentiable); only differences
        matter, in units of ``gamma``.
    resolution : int or (H, W), default: 128
    sigma : float, default: 1e-4
        Edge sharpness in squared screen units (a pixel is ``2 / W`` wide).
    gamma : float, default: 1e-2
        Softness of the z-ordering.
    background : (C,) array_like, default: white
    return_alpha : bool, default: False
        Also return the soft silhouette.
    silhouette : "auto", (#F, 3) bool array_like or None, default: "auto"
        Edges (corner k -> k+1) where the covered region ends, see :func:`silhouette_edges`
        ("auto" computes them from ``F`` and ``xy``); None treats every edge as one (SoftRas).

    Returns
    -------
    image : (H, W, C) tensor
        Row 0 at the top (y up), see :func:`pixel_centers`.
    alpha : (H, W) tensor
        Only with ``return_alpha``: ``1 - prod_j (1 - S_j)``.
    """
    H, W = _resolution(resolution)
    if not (sigma > 0 and gamma > 0):
        raise MescherError(f"sigma, gamma: expected positive values, found {sigma}, {gamma}")
    if F.ndim != 2 or F.shape[1] != 3:
        raise MescherError(f"F: expected shape (#F, 3), found {tuple(F.shape)}")
    if colors.ndim != 2 or colors.shape[0] != F.shape[0]:
        raise MescherError(f"colors: expected shape ({F.shape[0]}, C), found {tuple(colors.shape)}")
    if offsets.shape != (F.shape[0],):
        raise MescherError(f"offsets: expected shape ({F.shape[0]},), found {tuple(offsets.shape)}")
    dt = xy.dtype
    eps = torch.finfo(dt).tiny * 1e3
    # radius beyond which an outside pixel has coverage below COVERAGE_CUTOFF
    radius = math.sqrt(sigma * -_LOGIT_CUTOFF)
    dev = xy.device
    centres = pixel_centers((H, W), dtype=dt, device=dev)

    with torch.no_grad():
        P = xy.detach()[F]
        cand_f, cand_p = _candidate_pairs(P, radius, H, W)
        x0, _ = _signed_scaled_dist(P[cand_f], centres[cand_p], sigma, eps)
        keep = x0 > _LOGIT_CUTOFF  # inside faces always pass (x0 > 0)
        pf, pp = cand_f[keep], cand_p[keep]

    if isinstance(silhouette, str) and silhouette == "auto":
        silhouette = silhouette_edges(F.cpu().numpy(), xy.detach().cpu().numpy())
    if silhouette is not None:
        silhouette = torch.as_tensor(np.asarray(silhouette, dtype=bool), device=dev)
        if silhouette.shape != F.shape:
            raise MescherError(
                f"silhouette: expected a ({F.shape[0]}, 3) bool array, found "
                f"{tuple(silhouette.shape)}"
            )
        silhouette = silhouette[pf]

    # differentiable pass on the kept pairs only
    x, xs = _signed_scaled_dist(xy[F[pf]], centres[pp], sigma, eps, silhouette)
    n_pix = H * W
    log_T = torch.zeros(n_pix, dtype=dt, device=dev).index_add(
        0, pp, torch.nn.functional.logsigmoid(-(x if xs is None else xs))
    )
    alpha = 1.0 - torch.exp(log_T)

    logit = torch.nn.functional.logsigmoid(x) + offsets[pf] / gamma
    with torch.no_grad():
        m = torch.full((n_pix,), -torch.inf, dtype=dt, device=dev).scatter_reduce(
            0, pp, logit.detach(), reduce="amax", include_self=True
        )
        m = torch.where(torch.isfinite(m), m, torch.zeros_like(m))
    w = torch.exp(logit - m[pp])
    S = torch.zeros(n_pix, dtype=dt, device=dev).index_add(0, pp, w)
    C = torch.zeros(n_pix, colors.shape[1], dtype=dt, device=dev).index_add(
        0, pp, w[:, None] * colors[pf]
    )
    color = C / torch.where(S > 0, S, torch.ones_like(S))[:, None]
    bg = torch.as_tensor(np.asarray(background, dtype=np.float64), dtype=dt, device=dev)
    bg = bg.reshape(1, -1)
    image = (alpha[:, None] * color + (1.0 - alpha[:, None]) * bg).reshape(H, W, -1)
    if return_alpha:
        return image, alpha.reshape(H, W)
    return image


def render_mescher(
    m,
    offsets=None,
    lights=((0.0, 0.0, 1.0),),
    light_colors=None,
    ambient=0.2,
    albedo=1.0,
    resolution: int | tuple[int, int] = 128,
    sigma: float = 1e-5,
    gamma: float = 1e-3,
    background=(1.0, 1.0, 1.0),
    return_alpha: bool = False,
):
    """Render a :class:`~meschers_igl.Mescher` with :func:`soft_rasterize` (numpy in and out).

    Parameters
    ----------
    m : Mescher
    offsets : (#F,) array_like, optional
        Per-face depth offsets (larger nearer); default all equal.
    lights, light_colors, ambient, albedo
        See :func:`lambertian`.
    resolution, sigma, gamma, background, return_alpha
        See :func:`soft_rasterize`; the small default ``sigma`` gives a nearly hard image.

    Returns
    -------
    (H, W, 3) float64 ndarray in [0, 1], and (H, W) alpha with ``return_alpha``.
    """
    dt = torch.float64
    F = torch.tensor(np.asarray(m.F), dtype=torch.long)
    xy = torch.tensor(np.asarray(m.xy), dtype=dt)
    zeta = torch.tensor(np.asarray(m.zeta), dtype=dt)
    fe = torch.tensor(np.asarray(m.face_edges), dtype=torch.long)
    fs = torch.tensor(np.asarray(m.face_edge_signs), dtype=dt)
    o = (
        torch.zeros(F.shape[0], dtype=dt)
        if offsets is None
        else torch.tensor(np.asarray(offsets), dtype=dt)
    )
    with torch.no_grad():
        n = face_normals_from_zeta(F, xy, zeta, fe, fs)
        colors = lambertian(n, lights, light_colors, ambient, albedo)
        out = soft_rasterize(F, xy, colors, o, resolution, sigma, gamma, background, return_alpha)
    if return_alpha:
        return out[0].numpy(), out[1].numpy()
    return out.numpy()
