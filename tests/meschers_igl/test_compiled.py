"""The order kernels' compilation: one specialisation each, hand-written sorts equal numpy's."""

from __future__ import annotations

import numpy as np
import pytest
from numba import njit

from meschers_igl import compiled, jit, overlap
from meschers_igl.geometry2d import candidate_pairs
from meschers_igl.order_graph import topological_sort


# a kernel only compiled code calls has no CPython wrapper: called from here through this
@njit(cache=False)
def _cell_lists(c0, c1, ny, ncell, ok):
    return overlap._cell_lists(c0, c1, ny, ncell, ok)


@pytest.mark.parametrize("n", [1, 2, 255, 256, 70_000])
def test_sort_pairs_is_numpys_stable_lexsort(n):
    """The pair sort (which also sorts a sparse grid's cells) is the stable lexicographic
    permutation: ties keep their order."""
    rng = np.random.default_rng(n)
    for k in (0, 1, 7, 1000):
        # few distinct values (long runs of ties: stability shows) and the extremes
        vals = np.array([0, (n - 1) // 3, (n - 1) // 2, n - 1], dtype=np.int64)
        pairs = rng.choice(vals, size=(k, 2))
        want = np.lexsort((pairs[:, 1], pairs[:, 0]))
        assert np.array_equal(overlap.sort_pairs(pairs, n), want)
        pairs = rng.integers(0, n, size=(k, 2), dtype=np.int64)
        want = np.lexsort((pairs[:, 1], pairs[:, 0]))
        assert np.array_equal(overlap.sort_pairs(pairs, n), want)


def _levels_reference(n: int, arcs: np.ndarray) -> np.ndarray:
    """Level-by-level Kahn in plain Python, each level sorted."""
    indeg = np.bincount(arcs[:, 1], minlength=n)
    out = {i: [] for i in range(n)}
    for a, b in arcs:
        out[int(a)].append(int(b))
    level = sorted(i for i in range(n) if indeg[i] == 0)
    order = []
    while level:
        order += level
        nxt = []
        for u in level:
            for w in out[u]:
                indeg[w] -= 1
                if indeg[w] == 0:
                    nxt.append(w)
        level = sorted(nxt)
    return np.array(order, dtype=np.int64)


@pytest.mark.parametrize("seed", [0, 1])
def test_topological_sort_levels_sorted_short_and_long(seed):
    """Levels of 1 to ~400 nodes (insertion sort below 33, radix sort above), and a cycle."""
    rng = np.random.default_rng(seed)
    n = 3000
    rank = rng.permutation(n)  # a DAG: arcs go up in rank; wide and narrow levels
    a = rng.integers(0, n, 4000)
    b = rng.integers(0, n, 4000)
    keep = rank[a] < rank[b]
    arcs = np.stack([a[keep], b[keep]], axis=1)
    by_rank = rank.argsort()
    chain = np.stack([by_rank[:40], by_rank[1:41]], axis=1)  # a path through 41 levels
    arcs = np.concatenate([arcs, chain])
    order, complete = topological_sort(n, arcs)
    assert complete
    assert np.array_equal(order, _levels_reference(n, arcs))
    pos = np.empty(n, dtype=np.int64)
    pos[order] = np.arange(n)
    assert np.all(pos[arcs[:, 0]] < pos[arcs[:, 1]])
    # a cycle blocks what it reaches: fewer nodes, the same prefix as the reference's
    cyc = np.concatenate([arcs, [[int(by_rank[40]), int(by_rank[0])]]])  # closes the path
    part, complete = topological_sort(n, cyc)
    assert not complete and np.array_equal(part, _levels_reference(n, cyc))


def _brute_pairs(lo, hi, tol):
    i, j = np.triu_indices(len(lo), 1)
    ok = (np.minimum(hi[i], hi[j]) - np.maximum(lo[i], lo[j]) > tol).all(axis=1)
    return np.stack([i[ok], j[ok]], axis=1)


def test_cell_lists_sorted_and_counted_agree():
    """The grid's two ways to list each cell's boxes (counting sort of the cells, sort of their
    ``(cx, cy)``) agree."""
    rng = np.random.default_rng(3)
    n, ny = 300, 97
    c0 = rng.integers(0, 90, (n, 2))
    c1 = c0 + rng.integers(0, 4, (n, 2))
    ok = rng.random(n) > 0.1
    ncell = 97 * 97
    dense = _cell_lists(c0, c1, ny, ncell, ok)  # ncell small: counting sort
    sparse = _cell_lists(c0, c1, ny, 10**9, ok)  # huge ncell: the sorted keys
    for x, y in zip(dense, sparse):
        assert np.array_equal(x, y)


def test_candidate_pairs_on_a_sparse_grid_match_brute_force():
    """Tiny boxes far apart (most grid cells empty: the path sorting the cells) and a cluster."""
    rng = np.random.default_rng(5)
    far = rng.random((200, 2)) * 1e4
    near = rng.random((100, 2))
    lo = np.concatenate([far, near])
    hi = lo + rng.random(lo.shape) * 0.3
    got = candidate_pairs(lo, hi)
    assert np.array_equal(got, _brute_pairs(lo, hi, 0.0))


def test_order_kernels_compile_one_specialisation_each():
    """After the warm-up, the order group's kernels hold one signature each (no second
    compilation for literal arguments, layouts or integer widths); those with two are
    listed with why."""
    compiled.warm("order")
    two = {
        "extent": "screen points arrive writable or read-only",
    }
    counts = {
        d.py_func.__name__: len(d.signatures)
        for d in compiled.kernels(compiled.GROUPS["order"])
        if d.targetoptions.get("inline", "never") == "never" and d.signatures
    }
    assert counts["grid_overlaps"] == 1
    over = {k: v for k, v in counts.items() if v > (2 if k in two else 1)}
    assert not over, f"kernels compiled more than once: {over}"


def test_every_kernel_is_compiled_with_the_policy():
    """Each kernel of each group (the rendering package's too) is declared through
    ``jit.kernel``: cached, numpy's error model, no C-callable wrapper (each of those a
    share of the first run's compile time), so a raw ``njit`` added later is caught here."""
    from meschers.warmup import _modules

    found = []
    for group in (*compiled.GROUPS, "render"):
        for d in compiled.kernels(_modules(group)):
            found.append(d)
            name = f"{d.py_func.__module__}.{d.py_func.__qualname__}"
            assert d.targetoptions.get("error_model") == "numpy", name
            assert d.targetoptions.get("no_cfunc_wrapper") is True, name
            assert d._cache.__class__.__name__ != "NullCache", name  # cache=True
    assert len(found) >= 40  # the groups' modules were found at all


def test_kernel_options_extend_the_policy():
    """``kernel(**options)`` adds to (or overrides) the policy; the result computes."""
    k = jit.kernel(cache=False, nogil=True)(lambda x: x / 0.0)
    assert k(1.0) == np.inf  # numpy's error model: no ZeroDivisionError
    assert k.targetoptions["nogil"] is True and k.targetoptions["no_cfunc_wrapper"] is True
