"""Graph algorithms on depth orders: arcs as arrays, sorted and analysed on scipy CSR matrices.

A depth order (:class:`meschers_igl.order.DepthOrder`) is a directed graph over faces given by a
``(k, 2)`` int64 array of arcs ``(behind, in front)``.  These functions work on such arrays
directly: building a networkx ``DiGraph`` for 1M faces alone takes 11-20 s, while Kahn's
algorithm on a CSR adjacency sorts it in under a second.  networkx stays the
user-facing view (:attr:`DepthOrder.graph`); scipy's ``csgraph`` gives the strongly connected
components and breadth-first trees; the feedback-arc-set heuristic, which neither library
offers, is written by hand and runs over the faces of one cycle only.
"""

from __future__ import annotations

import heapq
from typing import Any

import numpy as np
import scipy.sparse as sp
import scipy.sparse.csgraph as csgraph

from .errors import MescherError
from .heap import heap_pop, heap_push
from .jit import kernel
from .overlap import unique_sorted_pairs
from .validate import as_int_array

__all__ = [
    "adjacency",
    "canonical_arcs",
    "eades_lin_smyth",
    "feedback_arc_set",
    "format_cycles",
    "in_sorted",
    "path_integrals",
    "reconcile_arcs",
    "shortest_cycle_through",
    "strong_components",
    "subgraph_arcs",
    "topological_sort",
]

# Work bound (removed arcs x arcs in the component) for the minimality pass after Eades-Lin-Smyth.
MINIMAL_FAS_WORK = 5_000_000


def canonical_arcs(arcs: Any, n: int, name: str = "arcs") -> np.ndarray:
    """Validated arcs: in range, without self-loops, unique and sorted lexicographically.

    Parameters
    ----------
    arcs : (k, 2) array_like of int or None
        Arcs ``(behind, in front)``; ``None`` or empty for none.
    n : int
        Number of faces (nodes).
    name : str
        Argument name for error messages.

    Returns
    -------
    (k', 2) int64
        Sorted by ``arcs[:, 0] * n + arcs[:, 1]``, duplicates removed.

    Raises
    ------
    MescherError
        On an index outside ``[0, n)`` or a self-loop.
    """
    if arcs is None or (np.ndim(arcs) <= 1 and np.size(arcs) == 0):
        return np.zeros((0, 2), dtype=np.int64)
    a = as_int_array(arcs, name, 2, 2)
    if a.shape[0] == 0:
        return np.zeros((0, 2), dtype=np.int64)
    bad = (a < 0) | (a >= n)
    if bad.any():
        r = int(np.flatnonzero(bad.any(axis=1))[0])
        raise MescherError(
            f"{name}: expected face indices in [0, {n}), found arc {r} = {a[r].tolist()}"
        )
    loops = a[:, 0] == a[:, 1]
    if loops.any():
        r = int(np.flatnonzero(loops)[0])
        raise MescherError(
            f"{name}: expected arcs between two different faces (a face cannot be behind "
            f"itself), found {int(loops.sum())} self-loop(s), first arc {r} = {a[r].tolist()}"
        )
    # compiled counting sort; a writable C array always (a read-only one is another type to
    # numba: a second compilation)
    return unique_sorted_pairs(np.require(a, np.int64, ["C", "W"]), int(n))


def adjacency(n: int, arcs: np.ndarray) -> sp.csr_matrix:
    """(n, n) int8 CSR adjacency matrix with ``A[i, j] = 1`` for each arc ``i -> j``."""
    return sp.csr_matrix(
        (np.ones(arcs.shape[0], dtype=np.int8), (arcs[:, 0], arcs[:, 1])), shape=(n, n)
    )


def topological_sort(n: int, arcs: np.ndarray) -> tuple[np.ndarray, bool]:
    """Kahn's topological sort, one level (all faces with no arc left into them) at a time.

    Within a level faces come in increasing index order, so the result is deterministic.

    Parameters
    ----------
    n : int
        Number of nodes.
    arcs : (k, 2) int64
        Arcs ``i -> j`` (``i`` must come before ``j``).

    Returns
    -------
    order : (r,) int64
        The nodes emitted, ``r == n`` on a DAG; fewer when a cycle blocks the rest.
    complete : bool
        Whether every node was emitted (the graph is acyclic).
    """
    if arcs.shape[0] == 0:
        return np.arange(n, dtype=np.int64), True
    arcs = np.asarray(arcs, dtype=np.int64)
    srt = np.argsort(arcs[:, 0], kind="stable")  # CSR by tail (canonical arcs: already sorted)
    indptr = np.concatenate(([0], np.cumsum(np.bincount(arcs[:, 0], minlength=n))))
    level = _kahn_levels(indptr, np.ascontiguousarray(arcs[srt, 1]), n)
    nodes = np.flatnonzero(level >= 0)
    # by level, then index: one sort of the key ``level * n + node`` (below n^2)
    order = np.sort(level[nodes] * n + nodes) % n
    return order, nodes.shape[0] == n


@kernel()
def _kahn_levels(indptr: np.ndarray, head: np.ndarray, n: int) -> np.ndarray:
    """Kahn's algorithm with a FIFO queue: the level of each node (0 with no arc in, else 1 + the
    largest level of its predecessors), -1 for the nodes a cycle blocks.

    The queue holds the nodes by nondecreasing level, so the predecessor that frees a node is one
    of largest level.  Sorting the levels is left to numpy (plain loops here: each line of a
    kernel costs first-run compilation).
    """
    indeg = np.empty(n, dtype=np.int64)  # zeroed in a loop: np.zeros is another compilation
    for v in range(n):
        indeg[v] = 0
    for a in range(head.shape[0]):
        indeg[head[a]] += 1
    level = np.empty(n, dtype=np.int64)
    queue = np.empty(n, dtype=np.int64)
    k = 0
    for v in range(n):
        level[v] = -1
        if indeg[v] == 0:
            level[v] = 0
            queue[k] = v
            k += 1
    t = 0
    while t < k:
        u = queue[t]
        t += 1
        for a in range(indptr[u], indptr[u + 1]):
            w = head[a]
            indeg[w] -= 1
            if indeg[w] == 0:
                level[w] = level[u] + 1
                queue[k] = w
                k += 1
    return level


def strong_components(n: int, arcs: np.ndarray) -> list[np.ndarray]:
    """Nodes of each strongly connected component with more than one node (i.e. on a cycle).

    Returns
    -------
    list of (c,) int64
        Sorted node indices of each such component, components ordered by their first node.
    """
    if arcs.shape[0] == 0:
        return []
    _, labels = csgraph.connected_components(adjacency(n, arcs), directed=True, connection="strong")
    counts = np.bincount(labels)
    big = np.flatnonzero(counts > 1)
    if big.size == 0:
        return []
    sel = np.flatnonzero(np.isin(labels, big))
    srt = np.argsort(labels[sel], kind="stable")
    sel = sel[srt]
    splits = np.cumsum(counts[big])[:-1]
    comps = np.split(sel, splits)
    comps.sort(key=lambda c: int(c[0]))
    return comps


def subgraph_arcs(arcs: np.ndarray, nodes: np.ndarray, n: int) -> np.ndarray:
    """Arcs with both ends in ``nodes``, renumbered to positions in ``nodes`` (sorted)."""
    local = np.full(n, -1, dtype=np.int64)
    local[nodes] = np.arange(nodes.size)
    la = local[arcs]
    return la[(la[:, 0] >= 0) & (la[:, 1] >= 0)]


def shortest_cycle_through(k: int, sub: np.ndarray, start: int = 0) -> list[int]:
    """A shortest directed cycle through local node ``start`` of a strongly connected graph."""
    A = adjacency(k, sub)
    bfs, pred = csgraph.breadth_first_order(A, start, directed=True, return_predecessors=True)
    closing = sub[sub[:, 1] == start, 0]  # nodes with an arc back into `start`
    rank = np.full(k, k, dtype=np.int64)
    rank[bfs] = np.arange(bfs.size)
    u = int(closing[np.argmin(rank[closing])])
    path = [u]
    while path[-1] != start:  # walk the BFS tree back to start: as long as the cycle
        path.append(int(pred[path[-1]]))
    return path[::-1]


def eades_lin_smyth(k: int, sub: np.ndarray) -> np.ndarray:
    """Vertex sequence of the Eades-Lin-Smyth greedy heuristic for a small feedback arc set.

    Sinks go to the end, sources to the front; otherwise the vertex with the largest
    ``outdeg - indeg`` goes to the front.  Arcs pointing backwards in the sequence form a
    feedback arc set of at most ``|A|/2 - |V|/6`` arcs.  Written by hand because neither
    networkx nor scipy offers a feedback-arc-set heuristic; the loop runs only over the faces
    of one strongly connected component (faces on cycles, normally a handful).

    Returns
    -------
    (k,) int64
        ``pos[v]``, the position of local node ``v`` in the sequence.
    """
    out_adj: list[list[int]] = [[] for _ in range(k)]
    in_adj: list[list[int]] = [[] for _ in range(k)]
    for a, b in sub.tolist():
        out_adj[a].append(b)
        in_adj[b].append(a)
    outd = [len(x) for x in out_adj]
    ind = [len(x) for x in in_adj]
    alive = [True] * k
    sinks = [v for v in range(k) if outd[v] == 0]
    sources = [v for v in range(k) if ind[v] == 0]
    heap = [(ind[v] - outd[v], v) for v in range(k)]
    heapq.heapify(heap)
    s1: list[int] = []
    s2: list[int] = []

    def remove(v: int) -> None:
        alive[v] = False
        for w in out_adj[v]:
            if alive[w]:
                ind[w] -= 1
                if ind[w] == 0:
                    sources.append(w)
                heapq.heappush(heap, (ind[w] - outd[w], w))
        for w in in_adj[v]:
            if alive[w]:
                outd[w] -= 1
                if outd[w] == 0:
                    sinks.append(w)
                heapq.heappush(heap, (ind[w] - outd[w], w))

    left = k
    while left:
        while sinks:
            v = sinks.pop()
            if alive[v]:
                s2.append(v)
                remove(v)
                left -= 1
        while sources:
            v = sources.pop()
            if alive[v]:
                s1.append(v)
                remove(v)
                left -= 1
        if left and not sinks:
            while True:  # lazy deletion: skip dead or stale heap entries
                key, v = heapq.heappop(heap)
                if alive[v] and key == ind[v] - outd[v]:
                    break
            s1.append(v)
            remove(v)
            left -= 1
    seq = s1 + s2[::-1]
    pos = np.empty(k, dtype=np.int64)
    pos[np.asarray(seq, dtype=np.int64)] = np.arange(k)
    return pos


def _reaches(adj: list[list[int]], src: int, dst: int) -> bool:
    seen = {src}
    stack = [src]
    while stack:
        v = stack.pop()
        if v == dst:
            return True
        for w in adj[v]:
            if w not in seen:
                seen.add(w)
                stack.append(w)
    return False


def feedback_arc_set(n: int, arcs: np.ndarray) -> np.ndarray:
    """A small set of arcs whose removal leaves a DAG (Eades-Lin-Smyth per strong component).

    After the greedy pass every removed arc is tried again and kept out only if adding it back
    would close a cycle, so the set is *minimal* (no arc in it is unnecessary), though not
    necessarily minimum (that problem is NP-hard).
    """
    out = []
    for comp in strong_components(n, arcs):
        k = comp.size
        sub = subgraph_arcs(arcs, comp, n)
        pos = eades_lin_smyth(k, sub)
        back = pos[sub[:, 0]] > pos[sub[:, 1]]
        removed = sub[back]
        if removed.shape[0] * sub.shape[0] <= MINIMAL_FAS_WORK:
            adj: list[list[int]] = [[] for _ in range(k)]
            for a, b in sub[~back].tolist():
                adj[a].append(b)
            needed = []
            for a, b in removed.tolist():
                if _reaches(adj, b, a):
                    needed.append((a, b))
                else:
                    adj[a].append(b)
            removed = np.asarray(needed, dtype=np.int64).reshape(-1, 2)
        out.append(comp[removed])
    return np.concatenate(out) if out else np.zeros((0, 2), dtype=np.int64)


def format_cycles(cycles: list[list[int]], limit: int = 5, width: int = 12) -> str:
    parts = []
    for c in cycles[:limit]:
        body = " -> ".join(map(str, c[:width])) + (" -> ..." if len(c) > width else "")
        parts.append(f"[{body} -> {c[0]}] ({len(c)} faces)")
    more = f" and {len(cycles) - limit} more" if len(cycles) > limit else ""
    return "; ".join(parts) + more


def in_sorted(sorted_keys: np.ndarray, q: np.ndarray) -> np.ndarray:
    """``np.isin(q, sorted_keys)`` by binary search (``sorted_keys`` sorted, non-empty)."""
    pos = np.minimum(np.searchsorted(sorted_keys, q), sorted_keys.size - 1)
    return sorted_keys[pos] == q


@kernel()
def _path_integrals(indptr, indices, weight, value, seeds, tstart, targets):
    nv = indptr.shape[0] - 1
    phi_out = np.empty(targets.shape[0], dtype=np.float64)
    dist = np.empty(nv, dtype=np.float64)  # valid where stamp is the current seed
    phi = np.empty(nv, dtype=np.float64)
    stamp = np.empty(nv, dtype=np.int64)  # seed whose search last touched the vertex
    done = np.empty(nv, dtype=np.int64)  # seed whose search settled the vertex
    want = np.empty(nv, dtype=np.int64)  # seed that still needs the vertex
    # loops, not np.full or np.zeros: the kernels' allocations share one spelling (np.empty
    # with ``dtype=``), so numba compiles its allocation code once per dtype and shape kind
    for t in range(targets.shape[0]):
        phi_out[t] = 0.0
    for v in range(nv):
        dist[v] = np.inf
        phi[v] = 0.0
        stamp[v] = done[v] = want[v] = -1
    cap = indices.shape[0] + 1
    hd = np.empty(cap, dtype=np.float64)
    hv = np.empty(cap, dtype=np.int64)
    for s in range(seeds.shape[0]):
        left = 0
        for t in range(tstart[s], tstart[s + 1]):
            v = targets[t]
            if want[v] != s:
                want[v] = s
                left += 1
        src = seeds[s]
        stamp[src], dist[src], phi[src] = s, 0.0, 0.0
        size = heap_push(hd, hv, 0, 0.0, src)
        while size > 0 and left > 0:
            d, u, size = heap_pop(hd, hv, size)
            if done[u] == s or d > dist[u]:
                continue  # a stale entry
            done[u] = s
            if want[u] == s:
                left -= 1
            for p in range(indptr[u], indptr[u + 1]):
                w = indices[p]
                nd = d + weight[p]
                if stamp[w] != s or nd < dist[w]:
                    stamp[w], dist[w], phi[w] = s, nd, phi[u] + value[p]
                    size = heap_push(hd, hv, size, nd, w)
        for t in range(tstart[s], tstart[s + 1]):
            phi_out[t] = phi[targets[t]] if done[targets[t]] == s else np.nan
    return phi_out


def path_integrals(
    edges: np.ndarray,
    weight: np.ndarray,
    value: np.ndarray,
    n_vertices: int,
    seeds: np.ndarray,
    targets: list[np.ndarray] | tuple[np.ndarray, np.ndarray],
) -> np.ndarray:
    """A 1-form integrated along shortest paths from seed vertices to target vertices.

    Dijkstra's algorithm from each seed over the undirected edge graph weighted by ``weight``,
    carrying ``phi(v) = phi(u) + value(u -> v)`` along each tree arc as it relaxes, and stopping
    as soon as the seed's targets are settled (a short search for nearby targets, where a full
    shortest-path tree costs ``O(#V log #V)`` per seed).  Compiled (numba); scipy's
    ``csgraph.dijkstra`` returns full trees only, with no early exit and no path integral.

    Parameters
    ----------
    edges : (#E, 2) int64
        Undirected edges ``(tail, head)``.
    weight : (#E,) float64
        Positive edge lengths.
    value : (#E,) float64
        The 1-form: ``value[e]`` integrates tail -> head (and ``-value[e]`` head -> tail).
    n_vertices : int
    seeds : (s,) int64
        Start vertices.
    targets : (tstart, target)
        CSR lists: the targets of seed ``k`` are ``target[tstart[k]:tstart[k+1]]``.

    Returns
    -------
    (#target,) float64
        The integral from the seed to each target along a shortest path; NaN where the target
        is unreachable.
    """
    tstart, target = targets
    rows = np.concatenate((edges[:, 0], edges[:, 1]))
    cols = np.concatenate((edges[:, 1], edges[:, 0]))
    srt = np.argsort(rows, kind="stable")
    indptr = np.concatenate(([0], np.cumsum(np.bincount(rows, minlength=n_vertices))))
    return _path_integrals(
        indptr.astype(np.int64),
        np.ascontiguousarray(cols[srt], dtype=np.int64),
        np.ascontiguousarray(np.concatenate((weight, weight))[srt], dtype=np.float64),
        np.ascontiguousarray(np.concatenate((value, -value))[srt], dtype=np.float64),
        np.ascontiguousarray(seeds, dtype=np.int64),
        np.ascontiguousarray(tstart, dtype=np.int64),
        np.ascontiguousarray(target, dtype=np.int64),
    )


def reconcile_arcs(n: int, hard: np.ndarray, soft: np.ndarray) -> np.ndarray:
    """``soft`` arcs adjusted so that they close no cycle with the ``hard`` ones.

    Used when an order is followed (:meth:`DepthOrder.follow`): the carried arcs are *hard*,
    the arcs of new overlaps ordered from local depth are *soft* (on an impossible figure the
    local depth along a path can contradict the order the figure was built with).  Within each
    strongly connected component of ``hard + soft``:

    1. a soft arc ``u -> v`` with a path ``v -> ... -> u`` of hard arcs contradicts what the hard
       arcs already imply, and is reversed (``v -> u`` is implied anyway);
    2. soft arcs still on a cycle after that are dropped.

    Arcs outside cycles are returned unchanged.  If ``hard`` is acyclic, so is the result.

    Parameters
    ----------
    n : int
        Number of nodes.
    hard, soft : (h, 2), (s, 2) int64
        Arcs ``i -> j``.

    Returns
    -------
    (s', 2) int64
        The adjusted soft arcs (``s' <= s``).
    """
    soft = np.asarray(soft, dtype=np.int64).reshape(-1, 2)
    hard = np.asarray(hard, dtype=np.int64).reshape(-1, 2)
    comps = strong_components(n, np.concatenate((hard, soft)))
    if not comps or soft.shape[0] == 0:
        return soft
    label = np.full(n, -1, dtype=np.int64)
    for k, c in enumerate(comps):
        label[c] = k
    soft = soft.copy()
    inside = np.flatnonzero((label[soft[:, 0]] >= 0) & (label[soft[:, 0]] == label[soft[:, 1]]))
    for k, c in enumerate(comps):  # the faces of each cycle: a handful, not all faces
        mine = inside[label[soft[inside, 0]] == k]
        if mine.size == 0:
            continue
        sub = subgraph_arcs(hard, c, n)
        A = adjacency(c.size, sub)
        local = np.searchsorted(c, soft[mine])
        for r, (u, v) in zip(mine.tolist(), local.tolist(), strict=True):
            reach = csgraph.breadth_first_order(A, v, directed=True, return_predecessors=False)
            if np.any(reach == u):
                soft[r] = soft[r, ::-1]
    comps = strong_components(n, np.concatenate((hard, soft)))
    if not comps:
        return soft
    label[:] = -1
    for k, c in enumerate(comps):
        label[c] = k
    cyc = (label[soft[:, 0]] >= 0) & (label[soft[:, 0]] == label[soft[:, 1]])
    return soft[~cyc]
