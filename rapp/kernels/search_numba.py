"""A* compiled with numba: the search of :func:`rapp.search.astar_search` over flat cell numbers.

The same search in the same order: entries ordered by ``(f, -g, cell)`` (``f = g + w h``),
lazy deletion of stale entries, cells never re-expanded, the goal accepted when it is taken
off the open list, the same expansion limit; so it expands the same cells and returns the
same path.

Arrays instead of Python objects: ``g`` of grid size in int32, with ``g = -1`` marking a
closed cell (blocked cells are closed from the start, so the one test ``g(u) + 1 >= g[v]``
rejects closed cells and paths that are no better); the step that reached each cell in one
byte (``2 axis + (step < 0)``), from which the path is walked back; neighbours by stride
arithmetic with the wrap of each axis; GD1 updated per step from one table of per-axis
distances (a step changes one coordinate). An open entry is ``f`` and the key
``h << sb | packed`` (``h`` the unweighted GD1; ``packed`` the cell's coordinates in bit
fields, the last axis lowest, ``sb`` bits in all, which order as flat cell numbers do and are
read back without a division): among equal ``f`` a smaller ``h`` is a larger ``g``, so the
key orders the ties as ``(-g, cell)`` does.

What the loops share travels as named tuples (numba passes them as structs): the grid's
geometry (:data:`Geometry`), the search's arrays and limits (:data:`Search`) and the open list
(:data:`Open`).

The open list. With ``w = 1`` (the default) ``f`` is an integer, and since GD1 is consistent
and changes by at most 1 per unit step, a step raises ``f`` by 0, 1 or 2: the open entries
span three values ``F, F + 1, F + 2`` above the ``F`` being expanded. So the list is three
buckets by ``f mod 3`` (a bucket queue, Dial 1969), rows of ``bk`` with lengths ``bl``:
entries of ``F + 1`` and ``F + 2`` are appended unsorted, as negated keys; when level ``F``
runs out, the next level is sorted once and popped from its end. A step that keeps ``f``
lowers ``h``, so its key is below every key left in level ``F``: it is inserted at the end,
past only the entries of the same expansion. No comparison of ``f`` and no sift through a
heap; the pops are those of the binary heap, in the same order. With ``w > 1``, ``f`` is not
an integer, and the list is the binary heap of :mod:`rapp.heap` over the pairs ``(f, key)``
in ``hf`` and ``hk``.

Examples
--------
>>> import numpy as np
>>> k = kernel()
>>> blocked = np.zeros(16, bool)
>>> k is None or k(blocked, np.array([4, 4]), np.array([True, True]), np.array([3, 0]), 0, 12,
...                1.0, -1)[2].tolist() == [0, 12]
True
"""

from __future__ import annotations

import functools
from collections import namedtuple

import numpy as np

from rapp import heap
from rapp.jit import jit

__all__ = ["kernel", "Geometry", "Search", "Open"]

#: The grid: ``shape``, ``strides`` (flat numbers), ``shift`` and ``fmask`` (each axis' bit
#: field in a packed key), ``wraps``, ``dist``/``base`` (``dist[base[a] + c]``: the GD1 term of
#: coordinate ``c`` on axis ``a``) and ``sb`` (the packed coordinates' bits).
Geometry = namedtuple("Geometry", "shape strides shift fmask wraps dist base sb")
#: The search: ``g`` (cost so far, -1 closed), ``came`` (the step into each cell), the goal
#: ``t``, the ``weight`` and the expansion ``limit`` (-1: none).
Search = namedtuple("Search", "g came t weight limit")
#: The open list: buckets ``bk`` with lengths ``bl`` (w = 1), the heap ``hf``/``hk`` (w > 1), and
#: ``state`` = (F the level being expanded, open heap entries, expansions so far).
Open = namedtuple("Open", "bk bl hf hk state")


def _geometry(shape, wraps, goal):
    """The :data:`Geometry` of a grid of ``shape`` for the search toward ``goal``."""
    n = shape.shape[0]
    strides = np.empty(n, np.int64)
    acc = 1
    for a in range(n - 1, -1, -1):
        strides[a] = acc
        acc *= shape[a]
    base = np.zeros(n + 1, np.int64)
    for a in range(n):
        base[a + 1] = base[a] + shape[a]
    dist = np.empty(base[n], np.int64)
    for a in range(n):
        m = shape[a]
        for c in range(m):
            d = abs(c - goal[a])
            if wraps[a] and m - d < d:
                d = m - d
            dist[base[a] + c] = d
    # Packed coordinates: axis a in bits shift[a]..shift[a] + width, the last axis lowest, so
    # that packed numbers order as flat cell numbers do; sb bits hold them all.
    shift = np.zeros(n, np.int64)
    sb = 0
    for a in range(n - 1, -1, -1):
        shift[a] = sb
        while (1 << (sb - shift[a])) < shape[a]:
            sb += 1
    fmask = np.empty(n, np.int64)
    for a in range(n):
        fmask[a] = (1 << ((sb if a == 0 else shift[a - 1]) - shift[a])) - 1
    return Geometry(shape, strides, shift, fmask, wraps, dist, base, sb)


def _astar_kernel(blocked, shape, wraps, goal, s, t, weight, limit):
    """A* from flat cell ``s`` to ``t`` on the grid ``blocked`` (flat) of ``shape``.

    Returns ``(status, expansions, flat_path)``: status 0 found, 1 goal unreachable, 2
    expansion limit hit (``limit < 0``: no limit). The loop itself is :func:`_astar_loop`; it
    returns when the open list needs more room, and the longer arrays are made here (an array
    reassigned inside the loop would cost numba two atomic reference counts per iteration).
    """
    if s == t:
        path = np.empty(1, np.int64)
        path[0] = s
        return 0, 0, path
    geo = _geometry(shape, wraps, goal)
    size = blocked.shape[0]
    g = np.empty(size, np.int32)
    for i in range(size):
        g[i] = -1 if blocked[i] else 2147483647
    se = Search(g, np.empty(size, np.uint8), t, weight, limit)
    hs = 0
    ps = 0
    for a in range(shape.shape[0]):
        c = (s // geo.strides[a]) % shape[a]
        hs += geo.dist[geo.base[a] + c]
        ps |= c << geo.shift[a]
    g[s] = 0
    # Small to start with (the tests' grids make them grow): doubled when full.
    op = Open(np.empty((3, 16), np.int64), np.zeros(3, np.int64), np.empty(16, np.float64),
              np.empty(16, np.int64), np.array([hs, 0, 0]))
    if weight == 1.0:
        op.bk[hs % 3, 0] = -((hs << geo.sb) | ps)
        op.bl[hs % 3] = 1
    else:
        op.state[1] = heap.push(op.hf, op.hk, 0, weight * hs, (hs << geo.sb) | ps)
    while True:
        status = _astar_loop(geo, se, op)
        if status < 3:
            break
        op = _longer(op, weight == 1.0)
    if status > 0:
        return status, op.state[2], np.empty(0, np.int64)
    return 0, op.state[2], _walk_back(geo, se)


def _longer(op, unit):
    """The open list ``op`` with its entries in arrays twice as long."""
    if unit:
        bk = np.empty((3, 2 * op.bk.shape[1]), np.int64)
        bk[:, :op.bk.shape[1]] = op.bk
        return Open(bk, op.bl, op.hf, op.hk, op.state)
    hf, hk = np.empty(2 * op.hf.shape[0], np.float64), np.empty(2 * op.hf.shape[0], np.int64)
    hf[:op.hf.shape[0]] = op.hf
    hk[:op.hf.shape[0]] = op.hk
    return Open(op.bk, op.bl, hf, hk, op.state)


def _walk_back(geo, se):
    """The flat path from the start to the goal ``se.t``, read back from the steps ``se.came``."""
    g, came, t, shape, strides = se.g, se.came, se.t, geo.shape, geo.strides
    path = np.empty(g[t] + 1, np.int64)  # the loop left g[t] open: the goal's cost
    v = t
    for k in range(g[t], 0, -1):
        path[k] = v
        a = came[v] >> 1
        m = shape[a]
        c = (v // strides[a]) % m
        pc = c + 1 if came[v] & 1 else c - 1
        if pc < 0:
            pc = m - 1
        elif pc == m:
            pc = 0
        v += (pc - c) * strides[a]
    path[0] = v
    return path


def _pop_bucket(bk, bl, F, cur):
    """The next key of the bucket queue, the level ``F`` it is on and that level's bucket
    ``cur = F % 3`` (kept, not recomputed per pop); key -1 when the queue is empty."""
    if bl[cur] == 0:
        if bl[(cur + 1) % 3] > 0:
            F += 1
        elif bl[(cur + 2) % 3] > 0:
            F += 2
        else:
            return -1, F, cur
        cur = F % 3
        bk[cur, :bl[cur]].sort()
    bl[cur] -= 1
    return -bk[cur, bl[cur]], F, cur


def _push_bucket(bk, bl, b, same_level, kv):
    """Enter the key ``kv`` in bucket ``b``; on the level being expanded (``same_level``: same
    f, smaller h) it sorts below what is left of that level, so it goes in at the end."""
    i = bl[b]
    bl[b] = i + 1
    if same_level:
        while i > 0 and bk[b, i - 1] > -kv:
            bk[b, i] = bk[b, i - 1]
            i -= 1
    bk[b, i] = -kv


def _astar_loop(geo, se, op):
    """The loop of :func:`_astar_kernel`: expand until the goal (0), none is left (1), the limit
    (2), or the open list may not hold the next expansion's entries (3; resumed after)."""
    # The named tuples' arrays as locals, once: read through the tuple in the loop, each
    # access would count a reference.
    shape, strides, shift, fmask, wraps, dist, base, sb = geo
    g, came, t, weight, limit = se
    bk, bl, hf, hk, state = op
    n = shape.shape[0]
    mask = (1 << sb) - 1
    unit = weight == 1.0
    F, length, expansions = state[0], state[1], state[2]
    cur = F % 3
    coord = np.empty(n, np.int64)
    status = 1
    while True:
        if unit:
            if max(bl[0], bl[1], bl[2]) + 2 * n > bk.shape[1]:
                status = 3
                break
            key, F, cur = _pop_bucket(bk, bl, F, cur)
            if key < 0:
                break
        else:
            if length + 2 * n > hf.shape[0]:
                status = 3
                break
            if length == 0:
                break
            _, key, length = heap.pop(hf, hk, length)
        pu = key & mask
        u = 0
        for a in range(n):
            c = (pu >> shift[a]) & fmask[a]
            coord[a] = c
            u += c * strides[a]
        gu = g[u]
        if gu < 0:
            continue
        if u == t:
            status = 0
            break
        if expansions == limit:
            status = 2
            break
        g[u] = -1
        expansions += 1
        gv = gu + 1
        hu = key >> sb
        for a in range(n):
            m = shape[a]
            c = coord[a]
            for step in (1, -1):
                nc = c + step
                if nc == m or nc < 0:
                    if not wraps[a]:
                        continue
                    nc = 0 if nc == m else m - 1
                v = u + (nc - c) * strides[a]
                if gv >= g[v]:
                    continue
                g[v] = gv
                came[v] = 2 * a + (step < 0)
                hv = hu - dist[base[a] + c] + dist[base[a] + nc]
                kv = (hv << sb) | (pu + ((nc - c) << shift[a]))
                if unit:
                    b = (cur + 1 + hv - hu) % 3
                    _push_bucket(bk, bl, b, b == cur, kv)
                else:
                    length = heap.push(hf, hk, length, gv + weight * hv, kv)
    state[0], state[1], state[2] = F, length, expansions
    return status


@functools.cache
def kernel():
    """:func:`_astar_kernel` compiled by numba (cached on disk), or None without numba."""
    # The kernel calls the helpers, which call heap.push and heap.pop: those are compiled first.
    if not heap.compiled():
        return None
    g = globals()
    # The helpers of the loop are inlined into it (numba's own inlining): a call per expansion
    # would count its arrays' references each time.
    for name, inline in (("_geometry", "never"), ("_longer", "never"), ("_walk_back", "never"),
                         ("_pop_bucket", "always"), ("_push_bucket", "always"),
                         ("_astar_loop", "never")):
        if not hasattr(g[name], "py_func"):  # not yet a numba dispatcher
            g[name] = jit(g[name], inline=inline)
    return jit(_astar_kernel)
