"""The numba kernels' shared min-heap (meschers_igl.heap), against Python's heapq."""

from __future__ import annotations

import heapq

import numpy as np
from numba import njit

from meschers_igl.heap import heap_pop, heap_push


@njit(cache=True)
def _run(ops, keys_in):
    """Apply pushes (op >= 0: push keys_in[op] with value op) and pops (op < 0)."""
    hk = np.empty(ops.size, np.float64)
    hv = np.empty(ops.size, np.int64)
    out_k = np.empty(ops.size, np.float64)
    out_v = np.empty(ops.size, np.int64)
    n = 0
    nout = 0
    for op in ops:
        if op >= 0:
            n = heap_push(hk, hv, n, keys_in[op], op)
        elif n > 0:
            k, v, n = heap_pop(hk, hv, n)
            out_k[nout] = k
            out_v[nout] = v
            nout += 1
    while n > 0:
        k, v, n = heap_pop(hk, hv, n)
        out_k[nout] = k
        out_v[nout] = v
        nout += 1
    return out_k[:nout], out_v[:nout]


def test_heap_pops_in_the_order_of_heapq():
    rng = np.random.default_rng(0)
    for _ in range(20):
        m = int(rng.integers(1, 400))
        keys = rng.integers(0, 50, m).astype(np.float64)  # ties included
        pushes = np.arange(m)
        pops = -np.ones(int(rng.integers(0, m + 1)), np.int64)
        ops = np.r_[pushes, pops]
        rng.shuffle(ops[1:])
        k, v = _run(ops.astype(np.int64), keys)
        ref, out = [], []
        for op in ops:
            if op >= 0:
                heapq.heappush(ref, keys[op])
            elif ref:
                out.append(heapq.heappop(ref))
        out += sorted(ref)
        np.testing.assert_array_equal(k, out)  # the same keys in the same order
        np.testing.assert_array_equal(keys[v], k)  # each value came with its own key
        assert sorted(v.tolist()) == list(range(m))  # every item once
