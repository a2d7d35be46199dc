"""Inverse rendering (paper Section 4.5): the soft rasterizer and the mescher fit."""

from __future__ import annotations

import math
import subprocess
import sys

import numpy as np
import pytest

torch = pytest.importorskip("torch")
pytest.importorskip("largesteps")

from meschers_igl import Mescher, MescherError  # noqa: E402
from meschers_igl.inverse import metrics as met  # noqa: E402
from meschers_igl.inverse import optimize as opt  # noqa: E402
from meschers_igl.inverse import rasterizer as ras  # noqa: E402
from meschers_igl.inverse import sobolev as sob  # noqa: E402
from meschers_igl.inverse import targets as tg  # noqa: E402

D64 = torch.float64


@pytest.fixture(autouse=True)
def _one_thread():
    # the CI machine has two cores shared by xdist workers: keep torch to one thread
    old = torch.get_num_threads()
    torch.set_num_threads(1)
    yield
    torch.set_num_threads(old)


def _t(a, dtype=D64):
    return torch.tensor(np.array(a), dtype=dtype)


# --------------------------------------------------------------------------- packaging


def test_import_does_not_load_torch():
    code = "import sys, meschers_igl.inverse; print('torch' in sys.modules)"
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert out.stdout.strip() == "False"


def test_missing_torch_says_how_to_install():
    code = (
        "import sys; sys.modules['torch'] = None\n"
        "try:\n    from meschers_igl.inverse import soft_rasterize\n"
        "except ImportError as e:\n    print(e)\n"
    )
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert "pip install 'meschers[inverse]'" in out.stdout
    assert "torch==2.13.0" in out.stdout


# --------------------------------------------------------------------------- rasterizer


def test_pixel_centers_hand_values():
    c = ras.pixel_centers(2, dtype=D64).numpy()
    np.testing.assert_array_equal(c, [[-0.5, 0.5], [0.5, 0.5], [-0.5, -0.5], [0.5, -0.5]])
    c = ras.pixel_centers((1, 4), dtype=D64).numpy()
    np.testing.assert_array_equal(c[:, 0], [-0.75, -0.25, 0.25, 0.75])
    np.testing.assert_array_equal(c[:, 1], 0.0)


def _inside_oracle(P, pts):
    """Strictly inside a triangle, by barycentric coordinates (independent of the rasterizer)."""
    T = np.column_stack([P[1] - P[0], P[2] - P[0]])
    lam = np.linalg.solve(T, (pts - P[0]).T).T
    return (lam[:, 0] > 0) & (lam[:, 1] > 0) & (lam.sum(1) < 1)


@pytest.mark.parametrize("flip", [False, True])
def test_hard_coverage_is_the_triangle(flip):
    rng = np.random.default_rng(0)
    P = rng.uniform(-0.9, 0.9, (3, 2))
    F = np.array([[0, 2, 1]] if flip else [[0, 1, 2]])
    res = 48
    _, alpha = ras.soft_rasterize(
        _t(F, torch.long),
        _t(P),
        _t([[0.3, 0.3, 0.3]]),
        _t([0.5]),
        res,
        sigma=1e-9,
        return_alpha=True,
    )
    inside = _inside_oracle(P, ras.pixel_centers(res, dtype=D64).numpy()).reshape(res, res)
    assert inside.sum() > 50
    np.testing.assert_array_equal(alpha.numpy() > 0.5, inside)


def test_coverage_is_sigmoid_of_scaled_squared_distance():
    # a huge triangle whose bottom edge is the line y = 0: coverage depends on y alone
    P = np.array([[-50.0, 0.0], [50.0, 0.0], [0.0, 50.0]])
    res, sigma = 8, 0.05
    _, alpha = ras.soft_rasterize(
        _t([[0, 1, 2]], torch.long),
        _t(P),
        _t([[1.0, 1.0, 1.0]]),
        _t([0.5]),
        res,
        sigma=sigma,
        return_alpha=True,
    )
    y = 1.0 - (2.0 * np.arange(res) + 1.0) / res  # row centres
    expect = 1.0 / (1.0 + np.exp(-np.sign(y) * y**2 / sigma))
    expect[expect < ras.COVERAGE_CUTOFF] = 0.0  # culled pairs
    np.testing.assert_allclose(alpha.numpy(), np.repeat(expect[:, None], res, 1), atol=1e-12)


def test_shared_edges_leave_no_seam_and_plain_softras_does():
    # a square as two triangles: the diagonal is interior, the outline is the silhouette
    P = np.array([[-0.5, -0.5], [0.5, -0.5], [0.5, 0.5], [-0.5, 0.5]])
    F = _t([[0, 1, 2], [0, 2, 3]], torch.long)
    col = _t([[0.2, 0.4, 0.6], [0.2, 0.4, 0.6]])
    kw = dict(resolution=9, sigma=1e-4, return_alpha=True)  # pixel centres on the diagonal
    img, alpha = ras.soft_rasterize(F, _t(P), col, _t([0.5, 0.5]), **kw)
    np.testing.assert_array_equal(
        ras.silhouette_edges(F.numpy(), P), [[True, True, False], [False, True, True]]
    )
    inner = alpha.numpy()[2:7, 2:7]
    np.testing.assert_allclose(inner, 1.0, atol=1e-12)  # the diagonal too
    np.testing.assert_allclose(img.numpy()[2:7, 2:7], np.broadcast_to([0.2, 0.4, 0.6], (5, 5, 3)))
    _, plain = ras.soft_rasterize(F, _t(P), col, _t([0.5, 0.5]), silhouette=None, **kw)
    # SoftRas's 1 - (1 - 1/2)^2 on the diagonal
    np.testing.assert_allclose(np.diag(plain.numpy())[4], 0.75, atol=1e-12)


def _brute_force(P, F, colors, offsets, res, sigma, gamma, bg):
    """Dense numpy SoftRas (every face on every pixel, same culling rule): the reference."""
    pts = ras.pixel_centers(res, dtype=D64).numpy()
    T = P[F]  # (nf, 3, 2)
    n = len(F)
    x = np.empty((n, len(pts)))
    for f in range(n):  # tiny case: loops are fine in a reference
        a, b, c = T[f]
        d2 = np.full(len(pts), np.inf)
        for s, t in ((a, b), (b, c), (c, a)):
            e = t - s
            u = np.clip(((pts - s) @ e) / (e @ e), 0, 1)
            d2 = np.minimum(d2, (((pts - s) - u[:, None] * e) ** 2).sum(1))
        ins = _inside_oracle(T[f], pts) | _inside_oracle(T[f][[0, 2, 1]], pts)
        x[f] = np.where(ins, d2, -d2) / sigma
    D = 0.5 * (1 + np.tanh(0.5 * x))  # the logistic function without overflow
    D[D < ras.COVERAGE_CUTOFF] = 0.0
    alpha = 1 - np.prod(1 - D, axis=0)
    logit = np.log(np.where(D > 0, D, 1e-300)) + offsets[:, None] / gamma
    w = np.where(D > 0, np.exp(logit - logit.max(0)), 0.0)
    col = (w.T @ colors) / np.maximum(w.sum(0), 1e-300)[:, None]
    img = alpha[:, None] * col + (1 - alpha[:, None]) * np.asarray(bg)
    return img.reshape(res, res, 3), alpha.reshape(res, res)


def test_windowed_rasterizer_matches_dense_reference():
    rng = np.random.default_rng(3)
    P = rng.uniform(-1.1, 1.1, (12, 2))
    F = np.array([rng.choice(12, 3, replace=False) for _ in range(10)])
    colors = rng.uniform(0, 1, (10, 3))
    offsets = rng.uniform(0.2, 0.8, 10)
    res, sigma, gamma, bg = 24, 3e-3, 5e-2, (1.0, 0.9, 0.8)
    img, alpha = ras.soft_rasterize(
        _t(F, torch.long),
        _t(P),
        _t(colors),
        _t(offsets),
        res,
        sigma,
        gamma,
        bg,
        return_alpha=True,
        silhouette=None,
    )
    ref_img, ref_alpha = _brute_force(P, F, colors, offsets, res, sigma, gamma, bg)
    np.testing.assert_allclose(alpha.numpy(), ref_alpha, atol=1e-12)
    np.testing.assert_allclose(img.numpy(), ref_img, atol=1e-12)


def test_offsets_decide_the_z_order():
    P = _t([[-0.8, -0.8], [0.8, -0.8], [0.0, 0.8], [-0.8, 0.8], [0.0, -0.8], [0.8, 0.8]])
    F = _t([[0, 1, 2], [3, 4, 5]], torch.long)
    red_green = _t([[1.0, 0.0, 0.0], [0.0, 1.0, 0.0]])
    centre = 8 * 16 + 8  # pixel (8, 8) of 16 x 16, inside both
    for offsets, winner in (([0.3, 0.6], 1), ([0.6, 0.3], 0)):
        img = ras.soft_rasterize(F, P, red_green, _t(offsets), 16, 1e-4, 1e-3)
        np.testing.assert_allclose(img.reshape(-1, 3)[centre], red_green[winner], atol=1e-12)


def test_lambertian_hand_values():
    n = _t([[0.0, 0.0, 1.0], [0.0, 0.0, -1.0], [0.6, 0.0, 0.8]])
    c = ras.lambertian(n, [(0.0, 0.0, 2.0)], ambient=0.25).numpy()
    np.testing.assert_allclose(c[:, 0], [1.0, 0.25, 0.25 + 0.75 * 0.8])
    c = ras.lambertian(n, [(1, 0, 0), (0, 0, 1)], [(1, 0, 0), (0, 0, 1)], ambient=0.0).numpy()
    np.testing.assert_allclose(c, [[0, 0, 1], [0, 0, 0], [0.6, 0, 0.8]], atol=1e-15)
    with pytest.raises(MescherError, match="lights"):
        ras.lambertian(n, [(0.0, 0.0, 0.0)])
    with pytest.raises(MescherError, match="light_colors"):
        ras.lambertian(n, [(0.0, 0.0, 1.0)], light_colors=[(1, 1, 1), (1, 1, 1)])


def test_bad_input_names_the_argument():
    F = _t([[0, 1, 2]], torch.long)
    xy = _t([[0, 0], [1, 0], [0, 1]])
    col = _t([[1.0, 1.0, 1.0]])
    with pytest.raises(MescherError, match="offsets"):
        ras.soft_rasterize(F, xy, col, _t([0.1, 0.2]))
    with pytest.raises(MescherError, match="colors"):
        ras.soft_rasterize(F, xy, _t([[1.0], [1.0]]), _t([0.1]))
    with pytest.raises(MescherError, match="sigma"):
        ras.soft_rasterize(F, xy, col, _t([0.1]), sigma=0.0)
    with pytest.raises(MescherError, match="resolution"):
        ras.soft_rasterize(F, xy, col, _t([0.1]), resolution=(0, 4))
    with pytest.raises(MescherError, match="silhouette"):
        ras.soft_rasterize(F, xy, col, _t([0.1]), silhouette=np.ones((2, 3), bool))


def _random_mescher(seed=0, n=5):
    """A bumpy height-field grid as an (embeddable) mescher."""
    rng = np.random.default_rng(seed)
    g = np.linspace(-0.7, 0.7, n)
    X, Y = np.meshgrid(g, g)
    V = np.column_stack([X.ravel(), Y.ravel(), 0.3 * rng.standard_normal(n * n)])
    V[:, :2] += 0.03 * rng.standard_normal((n * n, 2))
    i, j = np.meshgrid(np.arange(n - 1), np.arange(n - 1), indexing="ij")
    a = (i * n + j).ravel()
    F = np.concatenate(
        [np.column_stack([a, a + 1, a + n + 1]), np.column_stack([a, a + n + 1, a + n])]
    )
    return Mescher.from_mesh(V, F), V, F


def test_normals_from_zeta_match_the_core_and_the_embedding():
    m, V, F = _random_mescher()
    n = ras.face_normals_from_zeta(
        _t(m.F, torch.long),
        _t(m.xy),
        _t(m.zeta),
        _t(m.face_edges, torch.long),
        _t(m.face_edge_signs),
    ).numpy()
    np.testing.assert_allclose(n, m.face_normals(), atol=1e-12)
    N = np.cross(V[F[:, 1]] - V[F[:, 0]], V[F[:, 2]] - V[F[:, 0]])
    np.testing.assert_allclose(n, N / np.linalg.norm(N, axis=1, keepdims=True), atol=1e-12)


def test_gradcheck_xy_colors_offsets():
    F = _t([[0, 1, 2], [1, 3, 2], [0, 4, 1]], torch.long)
    xy = _t([[-0.5, -0.5], [0.5, -0.45], [0.05, 0.6], [0.7, 0.5], [0.1, -0.9]]).requires_grad_()
    col = torch.rand(3, 3, dtype=D64, generator=torch.Generator().manual_seed(0)).requires_grad_()
    off = _t([0.3, 0.35, 0.33]).requires_grad_()

    def f(xy, col, off):
        return ras.soft_rasterize(F, xy, col, off, 8, 1e-2, 1e-2, return_alpha=True)

    assert torch.autograd.gradcheck(f, (xy, col, off), eps=1e-6, atol=1e-6)


def test_gradcheck_through_zeta_normals_and_shading():
    m, _, _ = _random_mescher(seed=1, n=3)
    F, fe, fs = _t(m.F, torch.long), _t(m.face_edges, torch.long), _t(m.face_edge_signs)
    xy = _t(m.xy).requires_grad_()
    zeta = _t(m.zeta).requires_grad_()
    off = _t(np.linspace(0.2, 0.4, m.n_faces))

    def f(xy, zeta):
        n = ras.face_normals_from_zeta(F, xy, zeta, fe, fs)
        col = ras.lambertian(n, [(0.3, 0.4, 1.0), (-0.5, 0.2, 0.6)], ambient=0.1)
        return ras.soft_rasterize(F, xy, col, off, 6, 5e-3, 1e-2)

    assert torch.autograd.gradcheck(f, (xy, zeta), eps=1e-6, atol=1e-6)


# --------------------------------------------------------------------------- parametrization


def test_torus_mescher_is_the_torus():
    m, off = tg.torus_mescher(0.6, 0.2, 16, 8)
    assert (m.n_vertices, m.n_faces, m.euler_characteristic()) == (128, 256, 0)
    np.testing.assert_allclose(m.periods(), 0.0, atol=1e-12)
    # offsets order the near half (normals toward the viewer) in front of the far half
    front = m.face_normals()[:, 2] > 0
    assert off[front].mean() > off[~front].mean()
    assert off.min() >= 0.25 - 1e-12 and off.max() <= 0.75 + 1e-12


def test_torus_for_target_recovers_annulus_radii():
    res = 128
    c = ras.pixel_centers(res, dtype=D64).numpy().reshape(res, res, 2) - [0.1, -0.05]
    r = np.linalg.norm(c, axis=-1)
    img = np.ones((res, res, 3))
    img[(r > 0.3) & (r < 0.7)] = 0.4
    m, _ = tg.torus_for_target(img, n_major=32, n_minor=8)
    rr = np.linalg.norm(np.asarray(m.xy) - [0.1, -0.05], axis=1)
    assert abs(rr.min() - 0.3) < 0.01 and abs(rr.max() - 0.7) < 0.01


def test_closed_harmonic_basis_is_closed_and_dual():
    m, _ = tg.torus_mescher(0.6, 0.2, 24, 8)
    H = sob.closed_harmonic_basis(m)
    assert np.abs(m.d12 @ H).max() < 1e-14
    # periods of h_j around generator i: the identity
    P = np.stack([m.with_zeta(H[:, k]).periods() for k in range(H.shape[1])], axis=1)
    np.testing.assert_allclose(P, np.eye(H.shape[1]), atol=1e-9)


def test_parametrization_round_trip_and_periods():
    m, off = tg.torus_mescher(0.6, 0.2, 16, 8)
    m = m.with_periods([0.3, -0.1])
    par = sob.MescherParametrization(m, off, lam=5.0)
    with torch.no_grad():
        np.testing.assert_allclose(par.xy().numpy(), m.xy, atol=1e-5)
        zeta = par.zeta().numpy()
    np.testing.assert_allclose(zeta, m.zeta, atol=1e-5)
    np.testing.assert_allclose(m.with_zeta(zeta).periods(), [0.3, -0.1], atol=1e-12)
    assert np.abs(m.d12 @ zeta).max() < 1e-13


def test_sobolev_matrix_is_spd_identity_plus_laplacian():
    m, _ = tg.torus_mescher(0.6, 0.2, 12, 6)
    for kind in ("cotan", "uniform"):
        M = sob.sobolev_matrix(m, 3.0, kind)
        np.testing.assert_allclose(M @ np.ones(m.n_vertices), 1.0, atol=1e-12)  # L 1 = 0
        assert abs(M - M.T).max() < 1e-12
        assert np.linalg.eigvalsh(M.toarray()).min() > 1.0 - 1e-9
    with pytest.raises(MescherError, match="laplacian"):
        sob.sobolev_matrix(m, 1.0, "robust")


# --------------------------------------------------------------------------- the fit


LIGHT = [(0.3, 0.5, 1.0)]


def _fit_tiny(iters=100, callback=None):
    """A 32 x 32 impossible-torus picture, fitted from a smaller ordinary torus."""
    truth, off = tg.torus_mescher(0.55, 0.25, 24, 8)
    truth = truth.with_periods([0.8, 0.0])
    target = ras.render_mescher(truth, off, lights=LIGHT, resolution=32, sigma=1e-6)
    init, off0 = tg.torus_mescher(0.5, 0.2, 24, 8)
    o = opt.InverseOptions(
        iters=iters, resolution=32, sigma_xy=(1e-3, 1e-4), sigma_zeta=(1e-3, 1e-4)
    )
    result = opt.fit_mescher(target, init, off0, lights=LIGHT, options=o, callback=callback)
    before = ras.render_mescher(init, off0, lights=LIGHT, resolution=32, sigma=o.final_sigma)
    return result, target, before


def test_fit_keeps_every_iterate_a_mescher_and_lowers_the_loss():
    seen = []

    def check(it, state):
        seen.append(float(np.abs(init_d12 @ state["zeta"]).max()))

    init_d12 = tg.torus_mescher(0.5, 0.2, 24, 8)[0].d12
    result, target, before = _fit_tiny(callback=check)
    o_final_sigma = opt.InverseOptions().final_sigma
    assert len(seen) == 100
    assert max(seen) < 1e-10 and result.max_residual < 1e-10
    # the loss at one sigma: the final render against the initial one, both nearly hard
    mse_before = np.mean((before - target) ** 2)
    mse_after = np.mean((result.image - target) ** 2)
    assert mse_after < 0.5 * mse_before
    # and the training loss, whose sigma shrinks, still falls over the first steps
    assert np.mean(result.losses[10:16]) < np.mean(result.losses[:6])
    # the returned mescher and offsets are what was rendered: re-rendering them gives the image
    again = ras.render_mescher(
        result.mescher, result.offsets, lights=LIGHT, resolution=32, sigma=o_final_sigma, gamma=1e-3
    )
    np.testing.assert_allclose(again, result.image, atol=1e-5)
    assert np.abs(result.mescher.integrability_residual()).max() < 1e-10
    assert result.image.shape == (32, 32, 3) and result.alpha.shape == (32, 32)
    # the fit moved toward the target's climb around the hole (harmonic part)
    assert result.mescher.periods()[0] > 0.05


def test_fit_rejects_bad_target():
    m, off = tg.torus_mescher(0.5, 0.2, 12, 6)
    with pytest.raises(MescherError, match="target"):
        opt.fit_mescher(np.ones((8, 9, 3)), m, off)
    with pytest.raises(MescherError, match="offsets"):
        opt.fit_mescher(np.ones((8, 8, 3)), m, np.zeros(3), options=opt.InverseOptions(iters=1))
    with pytest.raises(MescherError, match="init"):
        opt.fit_mescher(np.ones((8, 8, 3)), (m.F, m.xy), off)
    # a picture whose soft rasterization would not fit in memory is refused before any work
    huge = np.lib.stride_tricks.as_strided(np.ones(3), (200_000, 200_000, 3), (0, 0, 8))
    with pytest.raises(MescherError, match="fit_mescher at 200000"):
        opt.fit_mescher(huge, m, off)
    with pytest.raises(MescherError, match="device"):
        if torch.cuda.is_available():
            pytest.skip("CUDA present: the refusal of a missing device cannot be shown")
        opt.fit_mescher(np.ones((8, 8, 3)), m, off, device="cuda")


def test_metrics_hand_values():
    a = np.zeros((4, 4), bool)
    b = np.zeros((4, 4), bool)
    a[:2] = True
    b[1:3] = True
    assert met.silhouette_iou(a, b) == pytest.approx(4 / 12)
    assert met.image_psnr(np.zeros((2, 2)), np.full((2, 2), 0.1)) == pytest.approx(20.0)
    m, _ = tg.torus_mescher(0.6, 0.2, 12, 6)
    size = np.ptp(m.xy, axis=0).max()
    assert met.max_period_ratio(m.with_periods([0.16, 0.0])) == pytest.approx(0.16 / size)


def test_extract_order_puts_the_higher_offset_in_front():
    # two separate triangles overlapping on screen, and a third far away
    F = np.array([[0, 1, 2], [3, 4, 5], [6, 7, 8]])
    xy = np.array(
        [
            [-0.8, -0.8],
            [0.8, -0.8],
            [0.0, 0.8],
            [-0.8, 0.8],
            [0.0, -0.8],
            [0.8, 0.8],
            [2, 2],
            [3, 2],
            [2, 3],
        ],
        float,
    )
    m = Mescher.from_mesh(np.column_stack([xy, np.zeros(9)]), F)
    order = opt.extract_order(m, np.array([0.7, 0.2, 0.5]))
    np.testing.assert_array_equal(order.arcs, [[1, 0]])
    order = opt.extract_order(m, np.array([0.2, 0.7, 0.5]))
    np.testing.assert_array_equal(order.arcs, [[0, 1]])


def test_penrose_target_is_a_penrose_triangle():
    xy, F, N, off, _ = tg.penrose_soup()
    # three visible normals, the cube axes seen along (1, 1, 1): orthonormal, n_z = 1/sqrt(3)
    _, first = np.unique(N.round(9), axis=0, return_index=True)
    U = N[first]
    assert U.shape == (3, 3)
    np.testing.assert_allclose(U @ U.T, np.eye(3), atol=1e-12)
    np.testing.assert_allclose(U[:, 2], 1 / math.sqrt(3), atol=1e-12)
    img = tg.penrose_target(64)
    mask = tg.target_mask(img)
    from scipy import ndimage

    # a ring: one object with one hole
    assert ndimage.label(mask)[1] == 1 and ndimage.label(~mask)[1] == 2


# --------------------------------------------------------------------------- from the picture

from meschers_igl import shapes  # noqa: E402
from meschers_igl.inverse import models as mdl  # noqa: E402
from meschers_igl.inverse import picture as pic  # noqa: E402


def _ramp_annulus(period=0.4):
    """A ring whose depth is a gentle bump plus a climb of ``period`` per turn (n_z > 0)."""
    V, F = shapes.annulus(24, 4, 0.4, 0.8)
    V[:, 2] = 0.1 * V[:, 0] - 0.05 * V[:, 1] ** 2
    return Mescher.from_mesh(V, F).with_periods([period])


def test_lift_recovers_a_mescher_from_its_own_normals():
    m = _ramp_annulus(0.4)
    n = m.face_normals()
    assert n[:, 2].min() > 0.5
    lifted = pic.lift(m.xy, m.F, n)
    # consistent wishes are met exactly: the same relative depths and the same climb per turn
    np.testing.assert_allclose(lifted.face_normals(), n, atol=1e-9)
    np.testing.assert_allclose(np.abs(lifted.periods()), [0.4], atol=1e-9)
    assert np.abs(lifted.d12 @ lifted.zeta).max() < 1e-12


def test_normals_from_shading_recovers_the_tribar_frame():
    model = mdl.penrose_tribar()
    axes = model.axes_in_camera()  # true normals of the three visible faces (camera frame)
    light = np.array([0.6, -0.1, 1.0])
    shades = 0.2 + 0.8 * axes @ (light / np.linalg.norm(light))
    # boundaries along each pair's crease, plus one occlusion (30 degrees off) to be ignored
    pairs = np.array([[0, 1], [1, 2], [0, 2], [0, 1]])
    dirs = np.cross(axes[pairs[:, 0]], axes[pairs[:, 1]])[:, :2]
    rot = np.array([[np.cos(0.5), -np.sin(0.5)], [np.sin(0.5), np.cos(0.5)]])
    dirs[3] = rot @ dirs[3]
    normals, misfit = pic.normals_from_shading(shades, light, 0.2, dirs, pairs, n_angles=7200)
    np.testing.assert_allclose(normals, axes, atol=2e-3)
    assert misfit < 0.05
    # the cut line is flagged, the creases are not
    mis = pic.crease_misalignment(normals, dirs, pairs)
    np.testing.assert_array_equal(mis > np.sin(np.radians(15)), [False, False, False, True])


def test_tribar_model_ends_coincide_on_screen():
    model = mdl.penrose_tribar(5.0, 1.0)
    R = model.camera_frame()
    C = model.V @ R.T
    x_first = C[:8][[0, 1, 2, 3, 4, 5, 6, 7]]  # corners of the X bar's box are 0..7
    Vx, _ = mdl.boxes_mesh([((0, 0, 0), (1, 1, 1))])
    Vz, _ = mdl.boxes_mesh([((4, 4, 4), (5, 5, 5))])
    # the Z bar's last cube is X's first cube moved by (L - w)(1, 1, 1): same screen points
    np.testing.assert_allclose((Vx @ R.T)[:, :2], (Vz @ R.T)[:, :2], atol=1e-12)
    np.testing.assert_allclose((Vz @ R.T)[:, 2] - (Vx @ R.T)[:, 2], model.gap, atol=1e-12)
    assert model.gap == pytest.approx(math.sqrt(3) * 4)
    assert x_first.shape == (8, 3) and model.F.shape == (36, 3)


def test_boundary_loop_periods_and_axis_share_hand_values():
    m = _ramp_annulus(0.3)
    periods, areas = met.boundary_loop_periods(m)
    # outer loop counter-clockwise (area > 0), the hole clockwise; both climb 0.3 in size
    assert (areas > 0).sum() == 1 and (areas < 0).sum() == 1
    np.testing.assert_allclose(np.abs(periods), [0.3, 0.3], atol=1e-12)
    assert met.figure_period(m) == pytest.approx(0.3, abs=1e-12)
    vis = np.array([[-1, 0, 1], [1, 2, -1]])
    normals = np.array([[0, 0, 1.0], [np.sin(0.1), 0, np.cos(0.1)], [np.sin(0.3), 0, np.cos(0.3)]])
    # face 0 on the axis, face 1 5.7 degrees off, face 2 17 degrees off: 3 of 4 pixels
    assert met.axis_aligned_share(vis, normals, np.eye(3), 10.0) == pytest.approx(3 / 4)


def test_sobolev_power_one_step_is_the_inverse_applied_to_the_gradient():
    from scipy.sparse.linalg import spsolve

    m, _ = tg.torus_mescher(0.6, 0.2, 12, 6)
    M = sob.sobolev_matrix(m, 2.0, "uniform")
    Mt = sob.sparse_to_torch(M, torch.float32)
    x0 = torch.zeros(m.n_vertices, 2)
    leaf = sob.SobolevLeaf(Mt, x0, power=1)
    g = np.random.default_rng(0).standard_normal((m.n_vertices, 2))
    leaf.leaf.grad = torch.as_tensor(g, dtype=torch.float32)
    leaf.precondition()
    np.testing.assert_allclose(leaf.leaf.grad.numpy(), spsolve(M.tocsc(), g), atol=1e-4)
    with pytest.raises(MescherError, match="power"):
        sob.SobolevLeaf(Mt, x0, power=3)


@pytest.fixture(scope="module")
def tribar_128():
    pytest.importorskip("pyvista")
    import os

    os.environ.setdefault("VTK_DEFAULT_OPENGL_WINDOW", "vtkEGLRenderWindow")
    from meschers.inverse_cli import zbuffer_picture

    model = mdl.penrose_tribar()
    light = (0.6, -0.1, 1.0)
    image, scale = zbuffer_picture(model, 128, light=light, ambient=0.2)
    return model, image, scale, light


@pytest.mark.render
def test_zbuffer_target_shades_follow_the_lambertian_formula(tribar_128):
    model, image, _, light = tribar_128
    seg = pic.segment_picture(image)
    l_hat = np.asarray(light) / np.linalg.norm(light)
    expect = np.sort(0.2 + 0.8 * model.axes_in_camera() @ l_hat)
    np.testing.assert_allclose(np.sort(seg.shades), expect, atol=1.0 / 255)


@pytest.mark.render
@pytest.mark.parametrize("res", [64, 96])
def test_tribar_period_holds_at_other_resolutions(res):
    pytest.importorskip("pyvista")
    from meschers.inverse_cli import zbuffer_picture

    model = mdl.penrose_tribar()
    image, scale = zbuffer_picture(model, res, light=(0.6, -0.1, 1.0), ambient=0.2)
    m, _, _ = pic.mescher_from_picture(image, (0.6, -0.1, 1.0), 0.2)
    assert abs(met.figure_period(m) - model.gap * scale) < 0.1 * model.gap * scale


@pytest.mark.render
def test_mescher_from_a_zbuffered_tribar_picture(tribar_128):
    model, image, scale, light = tribar_128
    m, region, info = pic.mescher_from_picture(image, light, 0.2)
    # an annulus (plus slits along occlusion lines), impossible, with the model's depth gap
    assert m.n_faces > 20 and m.is_impossible()
    # the depth step the picture hides where the bars meet (the two corner cubes)
    assert abs(met.figure_period(m) - model.gap * scale) < 0.05 * model.gap * scale
    # faces take the model's three axis normals, within 2 degrees, over 95% of the area (the
    # rest: the bridges where an occlusion cut stops short of the outline)
    cos = np.abs(m.face_normals() @ model.axes_in_camera().T).max(axis=1)
    good = np.degrees(np.arccos(np.clip(cos, -1, 1))) < 2.0
    assert m.face_areas()[good].sum() > 0.95 * m.face_areas().sum()
    before = ras.render_mescher(m, None, lights=[light], resolution=128, sigma=1e-6)
    assert met.image_psnr(before, image) > 29.0
    # a short SoftRas + Sobolev refinement raises the PSNR and keeps every iterate a mescher
    o = pic.fit_options(iters=40, eval_every=20)
    res = opt.fit_mescher(image, m, None, lights=[light], ambient=0.2, options=o)
    assert res.max_residual < 1e-10
    assert max(p for _, p in res.psnr) >= met.image_psnr(before, image)
    assert met.silhouette_iou(res.alpha > 0.5, tg.target_mask(image)) > 0.95


def test_progress_bar_and_callback_see_every_step_and_the_psnr_checks(capsys):
    m, off = tg.torus_mescher(0.5, 0.2, 12, 6)
    target = ras.render_mescher(m.with_periods([0.3, 0.0]), off, lights=LIGHT, resolution=16)
    states = []
    o = opt.InverseOptions(iters=4, eval_every=2, keep_best=True)
    res = opt.fit_mescher(
        target,
        m,
        off,
        lights=LIGHT,
        options=o,
        progress=True,
        callback=lambda it, st: states.append((it, st.get("psnr"))),
    )
    assert [it for it, _ in states] == [0, 1, 2, 3]
    assert [p is not None for _, p in states] == [False, True, False, True]
    # the PSNR checks are what the result reports, and the best one is what is returned
    assert [s for s, _ in res.psnr] == [2, 4] and len(res.snapshots) == 2
    assert met.image_psnr(res.image, target) == pytest.approx(max(p for _, p in res.psnr))
    assert "inverse" in capsys.readouterr().err


def test_with_progress_picks_the_context_and_the_callback_once():
    import contextlib

    seen = []

    def cb(it, st):
        seen.append(it)

    # without a bar: a null context and the caller's own callback, untouched
    ctx, step = opt._with_progress(False, 5, cb)
    assert isinstance(ctx, contextlib.nullcontext) and step is cb
    ctx, step = opt._with_progress(False, 5, None)
    assert step is None
    # with one: the bar is the context; each step advances it once and reaches the caller
    ctx, step = opt._with_progress(True, 3, cb)
    with ctx:
        step(0, {"loss": 0.5})
        step(1, {"loss": 0.25, "psnr": 20.0})
        (task,) = ctx.tasks
        assert task.description == "loss 0.25000 PSNR 20.0 dB"
        step(2, {"loss": 0.125})
    assert task.completed == task.total == 3 and task.description == "loss 0.12500"
    assert seen == [0, 1, 2]


# ------------------------------------------------------------- honest impossible figures


def test_impossible_cube_pieces_meet_on_screen_a_cube_diagonal_apart():
    size, width = 10.0, 2.0
    model = mdl.impossible_cube(size, width)
    C = model.V @ model.camera_frame().T
    boxes = C.reshape(-1, 8, 3)
    Vb = model.V.reshape(-1, 8, 3)
    # ten bars; the two along y that were changed end on the cut plane x + 2y + z = w - 2h
    assert len(boxes) == 10
    h = 0.5 * (size + width)
    on_cut = np.abs(Vb[..., 0] + 2 * Vb[..., 1] + Vb[..., 2] - (width - 2 * h)) < 1e-9
    changed = np.nonzero(on_cut.sum(axis=1) == 4)[0]
    assert len(changed) == 2
    ends = [boxes[k][on_cut[k]] for k in changed]
    # the plane holds the view: both end faces are seen edge-on (their normal is off the view)
    assert abs(np.array([1.0, 2.0, 1.0]) @ model.view) < 1e-12
    # the two ends are the same screen segment, sqrt(3) size apart in depth (a cube diagonal)
    a, b = (e[np.lexsort(e[:, :2].round(9).T)] for e in ends)
    np.testing.assert_allclose(a[:, :2], b[:, :2], atol=1e-9)
    np.testing.assert_allclose(np.abs(a[:, 2] - b[:, 2]), math.sqrt(3) * size, atol=1e-9)
    assert model.gap == pytest.approx(math.sqrt(3) * size)


def test_impossible_cube_is_the_paradox_toolkit_model():
    igl = pytest.importorskip("igl")
    from meschers_igl.paradox import paradox_model

    p = paradox_model("impossible_cube")
    V, _ = igl.read_triangle_mesh(str(p.obj))
    model = mdl.impossible_cube(p.meta["parameters"]["size"], p.meta["parameters"]["thickness"])
    # every corner of our ten bars is a vertex of the Blender add-on's mesh (float32 there)
    d = np.linalg.norm(model.V[:, None] - V[None], axis=2).min(axis=1)
    assert d.max() < 1e-3
    np.testing.assert_allclose(model.view, p.view, atol=1e-4)
    assert model.gap == pytest.approx(p.meta["verification"]["depth_gaps"][0], abs=1e-3)


@pytest.mark.parametrize("steep", [1.0, 2.0])
def test_penrose_stairs_close_on_screen_after_one_turn(steep):
    flights, w, T = (4, 4, 2, 2), 1.0, 0.6
    model = mdl.penrose_stairs(flights, w, T, steep)
    lo = model.V.reshape(-1, 8, 3).min(axis=1)  # each step's block
    N = sum(flights)
    s = lo[1, 2] - lo[0, 2]
    np.testing.assert_allclose(np.diff(lo[:, 2]), s, atol=1e-12)  # every step the same rise
    # the step after the last (one more -y move) is the first moved by D along the view
    nxt = lo[-1] + np.array([0.0, -w, s])
    D = nxt - lo[0]
    assert D[2] == pytest.approx(N * s)  # the height gained per turn
    assert D[2] == pytest.approx(steep * (flights[0] - flights[2]) * w)
    np.testing.assert_allclose(np.cross(D, model.view), 0.0, atol=1e-12)
    assert model.gap == pytest.approx(np.linalg.norm(D))  # depth gained per turn
    with pytest.raises(MescherError, match="steep"):
        mdl.penrose_stairs(steep=0.0)
    with pytest.raises(MescherError, match="flights"):
        mdl.penrose_stairs((4, 3, 2, 2))
    with pytest.raises(MescherError, match="size, width"):
        mdl.impossible_cube(3.0, 2.0)


def _model_screen(model, extent=0.8):
    """Camera frame scaled as ``zbuffer_picture`` places the model (screen units, y up)."""
    C = model.V @ model.camera_frame().T
    lo, hi = C[:, :2].min(axis=0), C[:, :2].max(axis=0)
    scale = 2.0 * extent / float((hi - lo).max())
    return lambda P: ((P @ model.camera_frame().T)[:, :2] - 0.5 * (lo + hi)) * scale


def _assert_frame(normals, axes, deg):
    """Each row of ``normals`` within ``deg`` degrees of one of ``axes`` (either sign), all used."""
    cos = np.abs(np.asarray(normals) @ np.asarray(axes).T)
    assert sorted(cos.argmax(axis=1).tolist()) == [0, 1, 2]
    assert np.degrees(np.arccos(np.clip(cos.max(axis=1), -1, 1))).max() < deg


@pytest.mark.render
def test_cube_picture_gives_the_cubes_period():
    pytest.importorskip("pyvista")
    from meschers.inverse_cli import zbuffer_picture

    model = mdl.impossible_cube()
    image, scale = zbuffer_picture(model, 128, light=(0.6, -0.1, 1.0), ambient=0.2)
    m, _, info = pic.mescher_from_picture(image, (0.6, -0.1, 1.0), 0.2)
    _assert_frame(info["normals"], model.axes_in_camera(), 1.0)
    assert m.is_impossible() and not info["hidden_lines"]
    assert abs(met.figure_period(m) - model.gap * scale) < 0.05 * model.gap * scale
    assert np.abs(m.d12 @ np.asarray(m.zeta)).max() < 1e-10


@pytest.mark.render
def test_hidden_tread_edges_are_found_on_the_stairs():
    pytest.importorskip("pyvista")
    from meschers.inverse_cli import zbuffer_picture

    model = mdl.penrose_stairs()
    light = (0.6, -0.1, 1.0)
    image, scale, depth = zbuffer_picture(model, 128, light=light, ambient=0.2, return_depth=True)
    m, _, info = pic.mescher_from_picture(image, light, 0.2)
    m0, _, info0 = pic.mescher_from_picture(image, light, 0.2, complete=False)
    # not isometric: three unequal shades, and the frame the shading gives is the model's
    _assert_frame(info["normals"], model.axes_in_camera(), 1.0)
    # the true hidden edges: where a step moves +x or +y, the next tread's back edge (its
    # riser faces away from the viewer) passes in front of the tread below
    lo = model.V.reshape(-1, 8, 3).min(axis=1)
    top = model.V.reshape(-1, 8, 3).max(axis=1)
    true = []
    for k in range(len(lo) - 1):
        move = lo[k + 1, :2] - lo[k, :2]
        if move.max() > 0:  # +x or +y: the edge of box k+1 facing box k
            ax = int(np.argmax(move))
            p = np.array([lo[k + 1, 0], lo[k + 1, 1], top[k + 1, 2]])
            q = p.copy()
            q[1 - ax] += 1.0
            true.append((p, q))
    to_screen = _model_screen(model)
    T = [to_screen(np.stack(pq)) for pq in true]
    assert len(T) == 8
    px = 2.0 / 128
    # where a flight turns, other box edges hide between faces of one shade too: the stretches
    # of the model's box edges along which the z-buffer's depth jumps (by over a quarter of a
    # box, far more than a face's slope from one pixel to the next) between pixels of one shade
    size = float((top - lo).min()) * scale
    jump = np.zeros(depth.shape, dtype=bool)
    for ax in (0, 1):
        step = np.abs(np.diff(depth, axis=ax)) > 0.25 * size  # NaN (background) compares False
        same = np.abs(np.diff(image, axis=ax)).max(axis=-1) < 1e-3
        hit = step & same
        jump[(slice(None, -1), slice(None)) if ax == 0 else (slice(None), slice(None, -1))] |= hit
        jump[(slice(1, None), slice(None)) if ax == 0 else (slice(None), slice(1, None))] |= hit
    ji, jj = np.nonzero(jump)
    J = np.stack([(jj + 0.5) * px - 1.0, 1.0 - (ji + 0.5) * px], axis=1)
    for k in range(len(lo)):
        for ax in range(3):
            free = [a for a in range(3) if a != ax]
            for c in ((0, 0), (0, 1), (1, 0), (1, 1)):  # the box's four edges along ax
                p = lo[k].copy()
                p[free] = np.where(np.array(c) == 1, top[k, free], lo[k, free])
                q = p.copy()
                q[ax] = top[k, ax]
                a, b = to_screen(np.stack([p, q]))
                pts = a + np.linspace(0.0, 1.0, 41)[:, None] * (b - a)
                near = np.nonzero(np.sqrt(((pts[:, None] - J[None]) ** 2).sum(-1)).min(1) < px)[0]
                if near.size and np.linalg.norm(pts[near[-1]] - pts[near[0]]) > 2.0 * px:
                    T.append((pts[near[0]], pts[near[-1]]))  # the stretch that hides
    assert len(T) > 8
    found = info["hidden_lines"]
    assert len(found) >= 5 and not info0["hidden_lines"]
    # where a flight turns, the line that follows the front tread's edge on stands for the
    # next tread's edge, which runs parallel to it one riser (the model's step up, on
    # screen) away: that one line may lie on a true edge shifted by a riser
    rise = to_screen(np.array([[0.0, 0.0, lo[1, 2] - lo[0, 2]], [0.0, 0.0, 0.0]]))
    riser = rise[0] - rise[1]

    def off(seg):  # how far the line's inner points lie from the nearest true edge
        pts = seg[0] + np.linspace(0.1, 0.9, 5)[:, None] * (seg[1] - seg[0])
        dist = []
        for a, b in T:
            t = np.clip((pts - a) @ (b - a) / ((b - a) @ (b - a)), 0, 1)
            dist.append(np.linalg.norm(pts - (a + t[:, None] * (b - a)), axis=1).max())
        return min(dist)

    shifted = 0
    for seg in found:  # each found line lies on a true hidden edge, within 1.5 pixels
        if off(seg) >= 1.5 * px:
            u = (seg[1] - seg[0]) / np.linalg.norm(seg[1] - seg[0])
            across = riser - (riser @ u) * u  # a shift along the line does not move it
            assert min(off(seg + s * across) for s in (1.0, -1.0)) < 1.5 * px
            shifted += 1
    assert shifted <= 1
    # cutting them brings the picture's period toward the true one (depth gained per turn)
    gap = model.gap * scale
    assert abs(met.figure_period(m) - gap) < 0.2 * gap
    assert abs(met.figure_period(m) - gap) < 0.5 * abs(met.figure_period(m0) - gap)
    assert np.abs(m.d12 @ np.asarray(m.zeta)).max() < 1e-10
