"""A* in Python over flat cell numbers: the search :func:`rapp.search.astar_search` shows, and
:func:`rapp.search.astar`'s backend without numba (or on a small grid before numba is loaded).

The neighbour table (with the wrap of each axis built in) and the heuristic of every cell are
computed once with numpy; the inner loop only reads Python lists and a bytearray, which is
several times faster than tuples of indices.

Examples
--------
>>> import numpy as np
>>> occ = np.zeros((4, 4), bool)
>>> status, flat, expansions, graph = astar(occ, (True, True), (True, True), (0, 0), (3, 0), 1.0, -1)
>>> status, graph.path(flat).tolist(), expansions
(0, [[0, 0], [3, 0]], 1)
"""

from __future__ import annotations

import heapq

import numpy as np

__all__ = ["astar", "PaddedGraph", "heuristic_grid"]


def heuristic_grid(shape, goal, wraps) -> np.ndarray:
    """GD1 (toroidal Manhattan distance to ``goal``) of every cell, as a grid."""
    h = np.zeros(shape, dtype=np.int64)
    for axis, (m, gi, w) in enumerate(zip(shape, goal, wraps)):
        d = np.abs(np.arange(m) - gi)
        if w:
            d = np.minimum(d, m - d)
        view = [1] * len(shape)
        view[axis] = m
        h += d.reshape(view)
    return h


class PaddedGraph:
    """The grid as a graph for the Python search loops, in padded flat numbers.

    The grid is embedded in one of shape ``M_i + 2`` on every axis, so that the
    neighbours of any real cell are at the constant offsets ``+-stride_i``. A
    pad cell of a bounded axis is closed from the start (off the grid); a pad
    cell of a wrapping axis redirects (``red``) to the real cell on the other
    side. Blocked cells are closed from the start too, so the inner loop needs
    one lookup and one test per neighbour and no table of size ``N x 2n``,
    whose construction would cost more than a typical search.
    """

    def __init__(self, occ, wraps):
        n = occ.ndim
        self.shape = occ.shape
        self.pshape = tuple(m + 2 for m in occ.shape)
        self.inner = (slice(1, -1),) * n
        size = int(np.prod(self.pshape))
        self.size = size
        blocked = np.ones(self.pshape, dtype=np.uint8)
        blocked[self.inner] = occ
        red = np.arange(size).reshape(self.pshape)
        for axis, (m, w) in enumerate(zip(occ.shape, wraps)):
            if w:
                for pad, real in ((0, m), (m + 1, 1)):
                    dst = list(self.inner)
                    src = list(self.inner)
                    dst[axis], src[axis] = pad, real
                    red[tuple(dst)] = red[tuple(src)]
        self.closed = bytearray(blocked.tobytes())
        self.red = red.ravel().tolist()
        strides = [int(np.prod(self.pshape[i + 1:])) for i in range(n)]
        self.offsets = [d for st in strides for d in (st, -st)]

    def flat(self, idx):
        """The padded flat number of the cell ``idx``."""
        return int(np.ravel_multi_index(tuple(i + 1 for i in idx), self.pshape))

    def padded(self, values):
        """A grid of values, padded by one cell on every side and flattened."""
        return np.pad(values, 1).ravel()

    def path(self, flat):
        """The cells ``(k, n)`` of padded flat numbers (read-only)."""
        cells = np.stack(np.unravel_index(np.asarray(flat, dtype=np.int64), self.pshape), axis=-1) - 1
        cells.setflags(write=False)
        return cells

    def expanded(self, occ):
        """The cells closed by the search (not the blocked ones), as a read-only bool grid."""
        done = np.frombuffer(bytes(self.closed), dtype=np.uint8).reshape(self.pshape)[self.inner]
        out = done.astype(bool) & ~occ
        out.setflags(write=False)
        return out


def astar(occ, wraps, heuristic_wraps, start, goal, weight, limit):
    """A* from cell ``start`` to ``goal`` on the free cells of ``occ`` (checked by the caller).

    Returns ``(status, flat, expansions, graph)``: status 0 found (``flat`` the padded flat
    numbers of the path, read by ``graph.path``), 1 goal unreachable, 2 the expansion
    ``limit`` hit (-1: none); ``graph`` (:class:`PaddedGraph`) also knows the closed cells.
    """
    G = PaddedGraph(occ, wraps)
    size, closed, red, offs = G.size, G.closed, G.red, G.offsets
    hgrid = G.padded(heuristic_grid(occ.shape, goal, heuristic_wraps))
    s, t = G.flat(start), G.flat(goal)
    g = [size + 1] * size
    parent = {}
    g[s] = 0
    expansions = 0
    push, pop = heapq.heappush, heapq.heappop
    status = 0 if s == t else 1
    # Heap entries (f, -g, cell): lowest f first, ties toward the larger g (deeper nodes, so
    # equal-f plateaus are crossed fast), then the cell index, so the order is deterministic.
    wh = hgrid.tolist() if weight == 1.0 else (weight * hgrid).tolist()
    heap = [(wh[s], 0, s)]
    while heap and status:
        u = pop(heap)[2]
        if closed[u]:
            continue
        if u == t:
            status = 0
            break
        if expansions == limit:
            status = 2
            break
        closed[u] = 1
        expansions += 1
        gv = g[u] + 1
        for d in offs:
            v = red[u + d]
            if closed[v] or gv >= g[v]:
                continue
            g[v] = gv
            parent[v] = u
            push(heap, (gv + wh[v], -gv, v))
    if status:
        return status, [], expansions, G
    flat = [t]
    while flat[-1] != s:
        flat.append(parent[flat[-1]])
    return 0, flat[::-1], expansions, G
