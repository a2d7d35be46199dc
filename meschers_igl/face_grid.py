"""Triangles binned once into a uniform screen grid, for box queries (the line drawing's
visibility tests ask which faces a segment or a point may lie on)."""

from __future__ import annotations

import numpy as np

from .geometry2d import _grid_cells

__all__ = ["FaceGrid", "ranges"]


def ranges(n: np.ndarray) -> np.ndarray:
    """``concatenate([arange(k) for k in n])`` without a loop."""
    n = np.asarray(n, dtype=np.int64)
    total = int(n.sum())
    if total == 0:
        return np.zeros(0, dtype=np.int64)
    return np.arange(total, dtype=np.int64) - np.repeat(np.cumsum(n) - n, n)


class FaceGrid:
    """The faces that cover something, binned once into a uniform grid (cell size by
    :func:`meschers_igl.geometry2d.candidate_pairs`' rule), for box queries."""

    def __init__(self, T: np.ndarray, area2: np.ndarray):
        self.faces = np.flatnonzero(area2 != 0)
        Tf = T[self.faces]
        # corner by corner (a reduction over an axis of length 3 is several times slower)
        self.lo = np.minimum(np.minimum(Tf[:, 0], Tf[:, 1]), Tf[:, 2])
        self.hi = np.maximum(np.maximum(Tf[:, 0], Tf[:, 1]), Tf[:, 2])
        if len(self.faces) == 0:
            return
        self.origin = self.lo.min(axis=0)
        self.h = self._cell()
        c0, c1 = _grid_cells(self.lo, self.hi, self.origin, self.h)
        self.n = c1.max(axis=0) + 1  # cells along x and y
        item, cell = self._entries(c0, c1)
        o = np.argsort(cell)
        self.item, self.cell = item[o], cell[o]

    def _cell(self) -> float:
        """Half the median face box: queries (thin segments, points) meet few faces per cell
        even where several sheets overlap; doubled while faces would fill > 16 cells each."""
        d = self.hi - self.lo
        ext = np.maximum(d[:, 0], d[:, 1])
        span = float((self.hi.max(axis=0) - self.lo.min(axis=0)).max())
        if span == 0.0:
            return 1.0
        h = max(0.5 * float(np.median(ext)), span / (4.0 * len(ext) + 1.0))
        for _ in range(16):
            c0, c1 = _grid_cells(self.lo, self.hi, self.origin, h)
            k = (c1 - c0 + 1).astype(np.float64)
            if float((k[:, 0] * k[:, 1]).sum()) <= 16.0 * len(ext):
                break
            h *= 2.0
        return h

    def _entries(self, c0: np.ndarray, c1: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        nx_, ny_ = c1[:, 0] - c0[:, 0] + 1, c1[:, 1] - c0[:, 1] + 1
        k = nx_ * ny_
        item = np.repeat(np.arange(len(c0)), k)
        local = ranges(k)
        cx = c0[item, 0] + local // ny_[item]
        cy = c0[item, 1] + local % ny_[item]
        return item, cx * self.n[1] + cy

    def pairs(self, lo: np.ndarray, hi: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """``(i, face)`` for every query box ``[lo_i, hi_i]`` meeting a face's box, once each
        (a pair is kept in the cell of the lower-left corner of the two boxes' intersection)."""
        if len(lo) == 0 or len(self.faces) == 0:
            return np.zeros(0, dtype=np.int64), np.zeros(0, dtype=np.int64)
        top = self.n - 1
        c0, c1 = (
            np.clip(c, 0, top) for c in _grid_cells(lo, hi, self.origin, self.h)
        )  # cells outside the grid hold no face
        ia, ca = self._entries(c0, np.maximum(c1, c0))
        start = np.searchsorted(self.cell, ca, "left")
        k = np.searchsorted(self.cell, ca, "right") - start
        pa = np.repeat(ia, k)
        cell = np.repeat(ca, k)
        pb = self.item[np.repeat(start, k) + ranges(k)]
        keep = np.ones(len(pa), dtype=bool)
        code = np.zeros(len(pa), dtype=np.int64)
        for j, stride in ((0, self.n[1]), (1, 1)):  # column by column: no axis reductions
            ilo = np.maximum(lo[pa, j], self.lo[pb, j])
            keep &= ilo <= np.minimum(hi[pa, j], self.hi[pb, j])
            c = np.floor((ilo - self.origin[j]) / self.h).astype(np.int64)
            code += np.clip(c, 0, top[j]) * stride
        keep &= code == cell
        return pa[keep], self.faces[pb[keep]]
