"""rapp.heap against heapq: the same pairs come out in the same order, plain and compiled.

The oracle is Python's heapq over tuples ``(key, item)``; keys are drawn from a few values so
that ties (broken by the item) are common, as in Dijkstra's equal distances and A*'s equal f.
"""

import heapq

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from rapp import heap

# A push is a pair (key, item); None is a pop (of a non-empty heap).
operations = st.lists(
    st.one_of(st.tuples(st.sampled_from([0.0, 0.5, 1.0, 2.0, 3.5]), st.integers(0, 40)),
              st.none()),
    max_size=120)


def run(ops, push, pop):
    """Apply ``ops`` with ``push`` and ``pop`` and with heapq; return both pop sequences."""
    keys, items = np.empty(len(ops) + 1), np.empty(len(ops) + 1, dtype=np.int64)
    length, ours, theirs, ref = 0, [], [], []
    for op in ops:
        if op is not None:
            length = push(keys, items, length, op[0], op[1])
            heapq.heappush(ref, op)
        elif ref:
            key, item, length = pop(keys, items, length)
            ours.append((float(key), int(item)))
            theirs.append(heapq.heappop(ref))
    while ref:  # drain what is left
        key, item, length = pop(keys, items, length)
        ours.append((float(key), int(item)))
        theirs.append(heapq.heappop(ref))
    assert length == 0
    return ours, theirs


@settings(max_examples=200, deadline=None)
@given(operations)
def test_pops_come_in_heapq_order(ops):
    # The plain Python functions, also once compiled() has swapped in numba's versions.
    ours, theirs = run(ops, getattr(heap.push, "py_func", heap.push),
                       getattr(heap.pop, "py_func", heap.pop))
    assert ours == theirs


@settings(max_examples=100, deadline=None)
@given(operations)
def test_the_compiled_heap_is_the_same_heap(ops):
    pytest.importorskip("numba")
    assert heap.compiled() is True
    assert hasattr(heap.push, "py_func") and hasattr(heap.pop, "py_func")
    ours, theirs = run(ops, heap.push, heap.pop)
    assert ours == theirs


@given(st.floats(-5, 5), st.integers(-5, 5), st.floats(-5, 5), st.integers(-5, 5))
def test_before_is_the_tuple_order(ka, ia, kb, ib):
    before = getattr(heap.before, "py_func", heap.before)
    assert before(ka, ia, kb, ib) == ((ka, ia) < (kb, ib))
