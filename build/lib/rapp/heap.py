"""A binary min-heap over two preallocated arrays, for the compiled searches.

The entries are pairs ``(key, item)`` held in two parallel arrays, ``keys[:length]`` and
``items[:length]``, and ordered as :mod:`heapq` orders the tuples ``(key, item)``: by key,
ties by item. The functions hold no state and allocate nothing, so that numba compiles them
into the loops that call them: PRM's Dijkstra (:mod:`rapp.prm`, distance and node) and
weighted A* (:mod:`rapp.search`, ``f`` and a key that orders the ties). They are plain
Python, and run as such without numba; :func:`compiled` swaps them for their compiled
versions before those loops are compiled.

Examples
--------
>>> import numpy as np
>>> keys, items = np.empty(4), np.empty(4, dtype=np.int64)
>>> n = 0
>>> for k, i in [(2.0, 7), (1.0, 9), (2.0, 3)]:
...     n = push(keys, items, n, k, i)
>>> out = []
>>> while n:
...     k, i, n = pop(keys, items, n)
...     out.append((float(k), int(i)))
>>> out
[(1.0, 9), (2.0, 3), (2.0, 7)]
"""

from __future__ import annotations

from rapp.jit import jit

__all__ = ["push", "pop", "before", "compiled"]


def push(keys, items, length, key, item):
    """Insert ``(key, item)`` into the heap of ``length`` entries; return ``length + 1``.

    The arrays must have room for one more entry. The hole left at the
    end moves up past every parent that orders after the new pair.
    """
    i = length
    while i > 0 and before(key, item, keys[(i - 1) >> 1], items[(i - 1) >> 1]):
        p = (i - 1) >> 1
        keys[i], items[i] = keys[p], items[p]
        i = p
    keys[i], items[i] = key, item
    return length + 1


def pop(keys, items, length):
    """Remove the smallest pair of a non-empty heap; return ``(key, item, length - 1)``.

    The last entry moves down from the root past every smaller child.
    """
    key, item = keys[0], items[0]
    length -= 1
    if length > 0:
        xk, xi = keys[length], items[length]
        i = 0
        c = 1
        while c < length:
            if c + 1 < length and before(keys[c + 1], items[c + 1], keys[c], items[c]):
                c += 1
            if not before(keys[c], items[c], xk, xi):
                break
            keys[i], items[i] = keys[c], items[c]
            i = c
            c = 2 * i + 1
        keys[i], items[i] = xk, xi
    return key, item, length


def before(key_a, item_a, key_b, item_b):
    """Whether the pair ``(key_a, item_a)`` orders before ``(key_b, item_b)``."""
    return key_a < key_b or (key_a == key_b and item_a < item_b)


def compiled():
    """Compile :func:`before`, :func:`push` and :func:`pop` with numba.

    Replaces this module's functions by their compiled versions (cached on disk), so that
    a kernel compiled afterwards, which calls ``heap.push``, finds compiled code there.
    Returns False without numba: the plain functions stay, and a later call tries again.
    """
    g = globals()
    if hasattr(g["push"], "py_func"):  # a numba dispatcher: compiled already
        return True
    jitted = {name: jit(g[name]) for name in ("before", "push", "pop")}
    if None in jitted.values():
        return False
    g.update(jitted)
    return True
