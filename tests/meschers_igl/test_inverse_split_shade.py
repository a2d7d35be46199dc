"""Two faces of one shade: which end of a chord names a pixel's face (inverse.faces)."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.ndimage import maximum_filter, minimum_filter

from meschers_igl import MescherError
from meschers_igl.inverse import faces as fc

AMBIENT = 0.2
GROUND = (0.55, 0.7, 0.9)


def _ends(*rows):
    """Per end pair ``(vote, dist, on outline)`` rows -> the votes, dists, grounds pairs."""
    a = np.array(rows, dtype=object)
    v = [np.array(a[:, k], dtype=np.int64) for k in (0, 3)]
    d = [np.array(a[:, k], dtype=np.float64) for k in (1, 4)]
    g = [np.array(a[:, k], dtype=bool) for k in (2, 5)]
    return v, d, g


def test_resolve_ends_weighs_the_outline_by_distance():
    inf = np.inf
    votes, dists, grounds = _ends(
        (0, 4.2, False, 1, 84.2, True),  # a crease 4 px away, the outline 84 px: the crease
        (0, 10.0, False, 1, 40.0, True),  # the outline 4 times farther: the outline
        (1, 30.0, True, 0, 5.0, False),  # the same, the ends swapped
        (0, 3.0, False, 1, 2.0, False),  # both inside the figure: the nearer
        (0, 3.0, True, 1, 2.0, True),  # both on the outline: the nearer
        (1, 50.0, False, 1, 2.0, True),  # agreeing
        (-1, inf, True, 1, 70.0, False),  # one end names nothing: the other
        (0, 9.0, False, -1, inf, False),
        (-1, inf, False, -1, inf, True),  # neither
    )
    got = fc._resolve_ends(votes, dists, grounds, 8.0)
    np.testing.assert_array_equal(got, [0, 1, 1, 1, 1, 1, 1, 0, -1])
    # just within the ratio the outline wins, just past it the crease does
    v, d, g = _ends((0, 5.0, False, 1, 39.99, True), (0, 5.0, False, 1, 40.01, True))
    np.testing.assert_array_equal(fc._resolve_ends(v, d, g, 8.0), [1, 0])
    # an infinite ratio puts the outline always first (no warning from inf / inf)
    with np.errstate(all="raise"):
        got = fc._resolve_ends(votes, dists, grounds, np.inf)
    np.testing.assert_array_equal(got, [1, 1, 1, 1, 1, 1, 1, 0, -1])
    with pytest.raises(MescherError, match="outline_ratio"):
        fc._resolve_ends(votes, dists, grounds, 0.5)
    mask = np.ones((4, 4), dtype=bool)
    with pytest.raises(MescherError, match="smooth"):
        fc.split_shared_shade(
            mask, np.zeros((4, 4)), np.zeros((4, 4), int), [0, 0, 1], 0.2, smooth=-1
        )


def _camera(view) -> np.ndarray:
    """(3, 3) rows: the model axes in the camera frame (x right, y up, z toward the viewer)."""
    v = np.asarray(view, dtype=np.float64) / np.linalg.norm(view)
    up = np.array([0.0, 0.0, 1.0]) - v[2] * v
    up /= np.linalg.norm(up)
    return np.stack([np.cross(up, v), up, v], axis=1)


def _boxes_picture(boxes, N: np.ndarray, light: np.ndarray, res: int):
    """Axis-aligned boxes z-buffered at the pixel centres, flat Lambertian on :data:`GROUND`.

    Returns the image, the orientation (model axis) per pixel and the face id per pixel
    (``3 * box + axis``; -1 on the ground).
    """
    quads = []
    for b, (lo, hi) in enumerate(boxes):
        lo, hi = np.asarray(lo, dtype=np.float64), np.asarray(hi, dtype=np.float64)
        for k in range(3):  # the face of each axis the viewer sees
            o = lo.copy()
            o[k] = hi[k] if N[k, 2] > 0 else lo[k]
            i, j = [a for a in range(3) if a != k]
            e1, e2 = np.zeros(3), np.zeros(3)
            e1[i], e2[j] = hi[i] - lo[i], hi[j] - lo[j]
            quads.append((o @ N, e1 @ N, e2 @ N, k, 3 * b + k))
    P = np.array([q[0] + s * q[1] + t * q[2] for q in quads for s in (0, 1) for t in (0, 1)])
    lo2, hi2 = P[:, :2].min(axis=0), P[:, :2].max(axis=0)
    scale, shift = 1.8 / (hi2 - lo2).max(), -0.5 * (lo2 + hi2)
    c = -1.0 + (2.0 * np.arange(res) + 1.0) / res
    X, Y = np.meshgrid(c, -c)
    q = np.stack([X, Y], axis=-1) / scale - shift
    depth = np.full((res, res), -np.inf)
    axis = np.full((res, res), -1)
    fid = np.full((res, res), -1)
    for o, e1, e2, k, f in quads:
        A = np.stack([e1[:2], e2[:2]], axis=1)
        st = np.linalg.solve(A, (q - o[:2]).reshape(-1, 2).T).T.reshape(res, res, 2)
        z = o[2] + st[..., 0] * e1[2] + st[..., 1] * e2[2]
        on = np.all((st >= 0) & (st <= 1), axis=-1) & (z > depth)
        depth[on], axis[on], fid[on] = z[on], k, f
    shade = AMBIENT + (1 - AMBIENT) * np.maximum(np.sign(N[:, 2]) * (N @ light), 0.0)
    grey = np.repeat(shade[np.maximum(axis, 0)][..., None], 3, axis=2)
    return np.where(axis[..., None] >= 0, grey, np.asarray(GROUND)), axis, fid


def test_a_near_crease_outweighs_a_far_outline_across_an_unseen_edge():
    # A post (along z) in front of a long bar (along x) behind it.  The light shows the x
    # faces and turns the y and z faces away: the post's front face (y) and the bar's top (z)
    # have one shade and meet along an edge no line shows.  A chord along the bar's direction
    # from a pixel of the post's front face ends a few pixels away on the post's own crease
    # with its lit x face, and the other way crosses onto the bar's top and runs along it to
    # the bar's far end on the outline, which names the bar's top: put first, the outline
    # puts a band of the post's face on the wrong orientation.
    N = _camera([1.0, 1.0, 1.0])
    light = np.array([0.9, -0.35, -0.3]) @ N
    light /= np.linalg.norm(light)
    s = np.sign(N[:, 2]) * (N @ light)
    assert s[0] > 0.5 and s[1] < 0 and s[2] < 0  # x lit, y and z at the ambient shade
    post, bar = ([0, 0, 0], [1, 1, 8]), ([-14, -4, 3], [0, -1, 4])
    img, axis, fid = _boxes_picture([post, bar], N, light, res=96)
    grey = img.mean(axis=-1)
    mask = axis >= 0
    dark = grey[mask].min()
    assert np.ptp(grey[mask & (axis > 0)]) == 0.0  # the y and z faces: one shade, no line
    group = np.where(mask, (grey > dark + 1e-6).astype(np.int64), -1)
    # interior pixels of each face (a pixel from every edge, seen or not)
    inner = maximum_filter(fid, 3) == minimum_filter(fid, 3)
    front = (fid == 1) & inner  # the post's face along y
    assert front.sum() > 100

    def read(ratio):
        lab, _, normals = fc.split_shared_shade(
            mask, grey, group, light, AMBIENT, outline_ratio=ratio
        )
        cos = np.abs(normals @ N.T)
        assert np.degrees(np.arccos(np.clip(cos.max(axis=1), -1, 1))).max() < 1.0
        which = np.argmax(cos, axis=1)
        assert sorted(which) == [0, 1, 2]
        return np.where(lab >= 0, which[np.maximum(lab, 0)], -1)

    got = read(fc.OUTLINE_RATIO)
    assert np.array_equal(got >= 0, mask)
    assert np.all(got[front] == 1)
    # the outline put first (the far end always over the crease): a band of the front face
    # on the bar's top orientation
    old = read(np.inf)
    assert np.mean(old[front] != 1) > 0.15
    # over the whole picture's interior pixels fewer are wrong
    assert np.sum((got != axis) & inner & mask) < np.sum((old != axis) & inner & mask)


def test_majority_removes_single_pixels_and_keeps_straight_faces():
    region = np.zeros((9, 12), dtype=bool)
    region[1:8, 1:11] = True
    labels = np.where(region, 1, 0)
    labels[:, 6:] = np.where(region[:, 6:], 2, 0)  # two faces, a straight crease between
    labels[0, :] = -1
    noisy = labels.copy()
    noisy[3, 3] = 2  # a single pixel of the other face
    noisy[5, 8] = 1
    noisy[2, 6] = 1  # a tooth on the crease
    got = fc._majority(noisy, region, 1)
    np.testing.assert_array_equal(got, labels)
    # a straight crease is a fixed point; outside the region nothing changes
    np.testing.assert_array_equal(fc._majority(labels, region, 3), labels)
    far = ~region
    np.testing.assert_array_equal(got[far], noisy[far])
    np.testing.assert_array_equal(fc._majority(noisy, region, 0), noisy)
