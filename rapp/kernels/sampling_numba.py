"""The compiled inner loops of the sampling planners: trees as preallocated arrays.

With the collision kernel compiled (:mod:`rapp.kernels.collision_numba`), one clearance check costs
about a microsecond, and what is left of a planner's time is Python: the nearest-node scan,
the steering arithmetic, a dozen numpy calls on arrays of three numbers per step. Here the
whole iteration of RRT-Connect (nearest node by a linear scan under the torus metric, one
extend step, the connect chain, each edge certified) runs inside one numba function that
calls the collision kernel's compiled loops directly, for a batch of random samples drawn in
Python by the planner's own ``numpy.random.Generator``: the random stream is the numpy
path's, sample for sample.

The arithmetic is that of the numpy path (:func:`rapp.rrt_connect.rrt_connect` without
numba), operation by operation: the wrapped difference ``(d + pi) % 2pi - pi``, the steps
``base + (j step / dist) d``, the exact link clearances, the end-point certificate
``c0 + c1 > B + 2 touch`` and the bisection of :func:`rapp.collision.segment_collision_free`. The trees
are the same node for node (``tests/test_sampling_kernel.py`` checks it over many seeds);
where a sum of three products is rounded differently by numpy's vectorized loops than by a
plain loop (it would have to decide a tie in the nearest-node scan, or an end-point
certificate to the last bit), a tree could differ, and then only there.

:func:`kernels` compiles on first use (cached on disk, ``cache=True``) and returns None
without numba; importing this module does not import numba. Numba's disk cache does not see
changes to the collision kernel's file: after editing :mod:`rapp.kernels.collision_numba`, touch
this file (or clear ``__pycache__``) so that these loops are compiled again.

Examples
--------
>>> k = kernels()
>>> k is None or float(k.wrap(3 * np.pi / 2)) == -np.pi / 2
True
"""

from __future__ import annotations

import functools
import math
from collections import namedtuple

import numpy as np

from rapp.kernels import collision as collision_backend
from rapp.jit import jit

__all__ = ["kernels", "Loops", "Scene", "Trees", "EXTEND_ROWS", "StarProblem", "StarTree", "Cells", "NearSet",
           "StarWork", "CONNECT_MEET", "CONNECT_FULL", "CONNECT_LIMIT", "CONNECT_MORE"]

#: The compiled functions (see :func:`kernels`).
Loops = namedtuple("Loops", "wrap extend connect nearest_k star draw bisect")
#: What certifying a move needs: the arm (``lengths``, ``limited``, ``reach``: the
#: :func:`rapp.collision.reach_matrix`), the packed obstacles (``circles pv pn pr offsets``:
#: :func:`rapp.kernels.collision.pack`) and the certificate's ``touch``, ``min_interval`` and
#: ``cap`` (most pending intervals).
Scene = namedtuple("Scene", "lengths limited reach circles pv pn pr offsets touch min_interval cap")
#: RRT-Connect's two trees, tree ``t`` in row ``t``: ``nodes``, ``parent``, ``cost``, the
#: nodes' link clearances ``clear`` and the node counts ``m``.
Trees = namedtuple("Trees", "nodes parent cost clear m")
#: RRT*'s settings in its compiled loop: the ``step``, the largest near radius ``rcap``,
#: the radius constant ``gamma``, the distance within which a node is joined to a goal, the
#: ``goals`` (g, n) and their link clearances ``goal_clear``.
StarProblem = namedtuple("StarProblem", "step rcap gamma goal_threshold goals goal_clear")
#: RRT*'s tree: ``nodes``, their link clearances ``clear``, ``parent``, ``cost``, the child
#: lists (``first_child``, ``next_sib``, ``prev_sib``), the node count ``m`` (one element),
#: the best goal node ``best`` (-1: none) and its cost ``best_cost`` (one element each).
StarTree = namedtuple("StarTree", "nodes clear parent cost first_child next_sib prev_sib m best "
                                  "best_cost")
#: The grid that finds nearest and near nodes of a large tree: the lower corner ``lo``, the
#: cells' ``width`` and count ``shape`` per joint, each cell's first node ``head`` and each
#: node's next ``nxt`` (-1 ends a list), and how many nodes are ``indexed`` (one element).
Cells = namedtuple("Cells", "lo width shape head nxt indexed")
#: RRT*'s near-set buffers, a row per node: indices ``near``, differences ``dn``, distances
#: ``dist``, sort keys ``key`` and a ``stack`` (the grid's found nodes, the rewiring's walk).
NearSet = namedtuple("NearSet", "near dn dist key stack")
#: The small scratch arrays of one :func:`_star` call.
StarWork = namedtuple("StarWork", "scratch d q_new at off span c_new pts")

#: :func:`_extend`'s scratch is ``(EXTEND_ROWS + n, max(n, 2))``: eight rows of ``n`` numbers,
#: then the arm's ``n + 1`` joint positions.
EXTEND_ROWS = 9

#: What :func:`_connect` says when it returns: a batch ran out without a meeting, the trees
#: met, the trees are full, an edge needed more bisection intervals than allowed.
CONNECT_MORE, CONNECT_MEET, CONNECT_FULL, CONNECT_LIMIT = 0, 1, 2, 3

_TWO_PI = 2 * math.pi
#: Intervals a first bisection of an edge may keep pending; more, and it runs again with the
#: caller's full allowance (the answer does not depend on it, only the scratch memory does).
_FIRST_CAP = 64


def _clearances(*args):
    """The collision kernel's compiled ``clearances`` (set by :func:`_compile`)."""
    raise RuntimeError("compiled only")


_certify = _clearances_one = _clearances


def _wrap(x):
    """``(x + pi) % 2pi - pi`` to the bit, as numpy computes it (rapp.wrap_angle)."""
    y = x + math.pi
    # fmod(y, 2pi) is y itself for |y| < 2pi and the exact y - 2pi for 2pi <= y < 4pi; the
    # remainder then adds 2pi to a negative result. Differences of wrapped angles land here,
    # and there the sum is formed without a branch (selects; random signs mispredict). Adding
    # 0.0 changes nothing.
    if -_TWO_PI <= y < 2 * _TWO_PI:
        up = _TWO_PI if y < 0.0 else 0.0
        down = _TWO_PI if y >= _TWO_PI else 0.0
        return ((y + up) - down) - math.pi
    # numba's float remainder is Python's (fmod, then the sign of the divisor), as numpy's.
    return y % _TWO_PI - math.pi


def _delta(q, row, limited, out):
    """``out = q - row`` the short way round on every free joint; returns its sum of squares,
    joint by joint (rapp.sampling.squared_norms)."""
    s = 0.0
    for j in range(q.shape[0]):
        d = q[j] - row[j]
        if not limited[j]:
            d = _wrap(d)
        out[j] = d
        s += d * d
    return s


def _nearest(nodes, m, q, limited):
    """Index of the node of ``nodes[:m]`` nearest ``q`` (the first of equals, as argmin).

    ``nodes`` are wrapped; where ``q`` is too on every free joint, the differences lie
    within two turns and :func:`_wrap`'s sum needs no range check: every node's sum of
    squares in full, without a branch a random sample would mispredict (the sums and so the
    node found are the same)."""
    n = q.shape[0]
    for j in range(n):
        if not (limited[j] or -math.pi <= q[j] <= math.pi):
            return _nearest_scan(nodes, m, q, limited)
    best = np.inf
    bi = 0
    for i in range(m):
        s = 0.0
        for j in range(n):
            d = q[j] - nodes[i, j]
            if not limited[j]:
                y = d + math.pi
                up = _TWO_PI if y < 0.0 else 0.0
                down = _TWO_PI if y >= _TWO_PI else 0.0
                d = ((y + up) - down) - math.pi
            s += d * d
        if s < best:
            best = s
            bi = i
    return bi


def _nearest_scan(nodes, m, q, limited):
    """:func:`_nearest` for any ``q``: each sum stopped once it reaches the best so far."""
    n = q.shape[0]
    best = np.inf
    bi = 0
    for i in range(m):
        s = 0.0
        for j in range(n):
            d = q[j] - nodes[i, j]
            if not limited[j]:
                d = _wrap(d)
            s += d * d
            if s >= best:  # the sum only grows: this node is not the first nearest
                break
        if s < best:
            best = s
            bi = i
    return bi


def _extend(t, target, chain, room, step, scene, trees, scratch):
    """rapp.rrt_connect's ``_extend`` on tree ``t`` of ``trees`` (:data:`Trees`): one step
    toward ``target``, or (``chain``) steps until it is reached, an edge is blocked or ``room``
    nodes were added, every edge certified in ``scene`` (:data:`Scene`).

    Returns ``(last node added or -1, reached, status)``; ``status`` is CONNECT_LIMIT when
    an edge needed more than ``cap`` pending intervals (nothing is added then).
    """
    lengths, limited, reach, circles, pv, pn, pr, offsets, touch, min_interval, cap = scene
    nodes, parent, cost, clear, m = trees
    n = target.shape[0]
    base, d, p, prev = scratch[0, :n], scratch[1, :n], scratch[2, :n], scratch[3, :n]
    q0, dq, bnd, c = scratch[4:5, :n], scratch[5:6, :n], scratch[6:7, :n], scratch[7, :n]
    pts = scratch[8:9 + n, :2]
    i = _nearest(nodes[t], m[t], target, limited)
    for j in range(n):
        base[j] = nodes[t, i, j]
    dist = math.sqrt(_delta(target, base, limited, d))
    if dist == 0.0:
        return i, True, CONNECT_MORE
    k = min(int(math.ceil(dist / step)), room) if chain else 1
    if k <= 0:
        return -1, False, CONNECT_MORE
    last = -1
    par = i
    for j in range(n):
        prev[j] = base[j]
    c_prev = clear[t, i]
    frac = 0.0
    added = 0
    for s in range(k):
        frac = min((s + 1) * step / dist, 1.0)
        for j in range(n):
            p[j] = base[j] + frac * d[j]
        _clearances_one(lengths, p, pts, c, circles, pv, pn, pr, offsets)
        # An end within touching distance, this one or the node it leaves: not free
        # (rapp.sampling.EdgeCertifier), though a bisection could certify an edge leaving it.
        hit = False
        for j in range(n):
            if c[j] <= touch or c_prev[j] <= touch:
                hit = True
        if hit:
            break
        # The end-point certificate (rapp.sampling.endpoint_certified), else the bisection.
        ok = True
        for j in range(n):
            dq[0, j] = p[j] - prev[j]
        for l in range(n):
            b = 0.0
            for j in range(n):
                b += abs(dq[0, j]) * reach[j, l]
            bnd[0, l] = b
            if not (c_prev[l] + c[l] > b + 2 * touch and c_prev[l] > touch and c[l] > touch):
                ok = False
        if not ok:
            for j in range(n):
                q0[0, j] = prev[j]
            code = _certify(lengths, q0, dq, bnd, circles, pv, pn, pr,
                                                    offsets, min_interval, _FIRST_CAP, touch)[0]
            if code < 0:
                code = _certify(lengths, q0, dq, bnd, circles, pv, pn,
                                                        pr, offsets, min_interval, cap, touch)[0]
            if code < 0:
                return last, False, CONNECT_LIMIT
            if code == 0:
                break
        length = 0.0
        for j in range(n):
            length += dq[0, j] * dq[0, j]
        new = m[t]
        for j in range(n):
            nodes[t, new, j] = p[j] if limited[j] else _wrap(p[j])
            clear[t, new, j] = c[j]
        parent[t, new] = par
        cost[t, new] = cost[t, par] + math.sqrt(length)
        m[t] = new + 1
        par = new
        last = new
        added += 1
        c_prev = clear[t, new]
        for j in range(n):
            prev[j] = p[j]
    return last, added == k and frac == 1.0, CONNECT_MORE


def _connect(samples, it0, max_nodes, chain_room, step, scene, trees, meet):
    """Iterations ``it0 + 1, it0 + 2, ...`` of RRT-Connect, one per row of ``samples``.

    The loop of :func:`rapp.rrt_connect.rrt_connect`: tree ``a`` (the start's on odd
    iterations) extends one step toward the sample, then tree ``b`` connects toward the new
    node. Returns ``(status, iterations run)``; on CONNECT_MEET ``meet`` holds the two
    nodes that met (start's tree first). ``scene`` and ``trees`` as :func:`_extend`'s.
    """
    nodes, m = trees.nodes, trees.m
    n = samples.shape[1]
    scratch = np.empty((EXTEND_ROWS + n, max(n, 2)))
    target = np.empty(n)
    for s in range(samples.shape[0]):
        it = it0 + s + 1
        if m[0] + m[1] >= max_nodes:
            return CONNECT_FULL, s + 1
        a = 0 if it % 2 else 1
        b = 1 - a
        new, _, status = _extend(a, samples[s], False, max_nodes, step, scene, trees, scratch)
        if status != CONNECT_MORE:
            return status, s + 1
        if new < 0:
            continue
        for j in range(n):
            target[j] = nodes[a, new, j]
        room = min(chain_room, max_nodes - m[0] - m[1])
        other, reached, status = _extend(b, target, True, room, step, scene, trees, scratch)
        if status != CONNECT_MORE:
            return status, s + 1
        if reached:
            meet[a] = new
            meet[b] = other
            return CONNECT_MEET, s + 1
    return CONNECT_MORE, samples.shape[0]


def _nearest_k(nodes, first, k, limited, out_j, out_d):
    """The ``k`` nodes nearest each node ``i >= first`` (itself left out): PRM's candidates.

    Row ``i - first`` of ``out_j`` and ``out_d`` receives their indices and distances (the
    square root of the sum of squares joint by joint, as rapp.sampling.squared_norms), nearest
    first, equal distances by index. ``nodes`` are wrapped, so their differences lie within
    two turns and :func:`_wrap`'s sum needs no range check: a loop the compiler vectorizes
    over a column at a time, then one pass picks the nearest.
    """
    m, n = nodes.shape
    cols = np.ascontiguousarray(nodes.T)
    s = np.empty(m)
    for r in range(m - first):
        i = first + r
        s[:] = 0.0
        for c in range(n):
            col = cols[c]
            x = col[i]
            if limited[c]:
                for j in range(m):
                    d = col[j] - x
                    s[j] += d * d
            else:
                for j in range(m):
                    y = (col[j] - x) + math.pi
                    up = _TWO_PI if y < 0.0 else 0.0
                    down = _TWO_PI if y >= _TWO_PI else 0.0
                    d = ((y + up) - down) - math.pi
                    s[j] += d * d
        count = 0
        bound = np.inf
        for j in range(m):
            # Once the list is full, most nodes are farther than its last one: told from the
            # square (with a margin far above rounding), without the square root.
            if j == i or (count == k and s[j] > bound):
                continue
            dist = math.sqrt(s[j])
            if count < k:
                pos = count
                count += 1
            elif dist < out_d[r, k - 1]:
                pos = k - 1
            else:
                continue
            while pos > 0 and out_d[r, pos - 1] > dist:  # later indices stay behind equals
                out_d[r, pos] = out_d[r, pos - 1]
                out_j[r, pos] = out_j[r, pos - 1]
                pos -= 1
            out_d[r, pos] = dist
            out_j[r, pos] = j
            if count == k:
                bound = out_d[r, k - 1] * out_d[r, k - 1] * (1 + 1e-9)


def _edge_free(q0, d, c0, c1, scene, scratch):
    """rapp.sampling.EdgeCertifier for the edge ``q0 -> q0 + d`` whose ends have the link
    clearances ``c0``, ``c1`` in ``scene`` (:data:`Scene`): 1 free, 0 not, -1 over
    ``scene.cap`` pending intervals.

    ``dq`` is formed as segment_collision_free forms it and the bounds joint by joint (as
    rapp.sampling.motion_bounds_of); the ends' certificate first, else the bisection.
    """
    n = q0.shape[0]
    touch = scene.touch
    a, dq, bnd = scratch[0:1], scratch[1:2], scratch[2:3]
    _edge_bounds(q0, d, scene.reach, a, dq, bnd)
    ends = True
    for l in range(n):
        if c0[l] <= touch or c1[l] <= touch:
            return 0
        if not c0[l] + c1[l] > bnd[0, l] + 2 * touch:
            ends = False
    if ends:
        return 1
    return _bisect_bounded(a, dq, bnd, scene)


def _edge_bounds(q0, d, reach, a, dq, bnd):
    """``a = q0``, ``dq = (q0 + d) - q0`` and its motion bounds joint by joint, as rows."""
    n = q0.shape[0]
    for j in range(n):
        a[0, j] = q0[j]
        dq[0, j] = (q0[j] + d[j]) - q0[j]
    for l in range(n):
        b = 0.0
        for j in range(n):
            b += abs(dq[0, j]) * reach[j, l]
        bnd[0, l] = b


def _bisect_bounded(a, dq, bnd, scene):
    """The collision kernel's bisection of the edge row ``a``, ``dq`` (bounds ``bnd``) in
    ``scene``: first with a small allowance of pending intervals, then with ``scene.cap``."""
    s = scene
    code = _certify(s.lengths, a, dq, bnd, s.circles, s.pv, s.pn, s.pr, s.offsets,
                    s.min_interval, _FIRST_CAP, s.touch)[0]
    if code < 0:
        code = _certify(s.lengths, a, dq, bnd, s.circles, s.pv, s.pn, s.pr, s.offsets,
                        s.min_interval, s.cap, s.touch)[0]
    return code


def _bisect(q0, d, scene, scratch):
    """rapp.sampling.EdgeCertifier for the edge ``q0 -> q0 + d`` by the bisection alone: 1 free,
    0 not, -1 over ``scene.cap`` pending intervals. ``scene`` is any named tuple with the
    fields of :data:`Scene` (``lengths reach circles pv pn pr offsets touch min_interval cap``
    are read)."""
    a, dq, bnd = scratch[0:1], scratch[1:2], scratch[2:3]
    _edge_bounds(q0, d, scene.reach, a, dq, bnd)
    return _bisect_bounded(a, dq, bnd, scene)


#: Trees of more nodes than this find their nearest and near nodes through the grid of cells.
GRID_FROM = 256


def _cell(q, limited, lo, w, shape, at):
    """Cell coordinates of configuration ``q`` into ``at``; returns the flat cell index."""
    flat = 0
    for j in range(q.shape[0]):
        x = q[j] if limited[j] else _wrap(q[j])
        c = int(math.floor((x - lo[j]) / w[j]))
        c = min(max(c, 0), shape[j] - 1)
        at[j] = c
        flat = flat * shape[j] + c
    return flat


def _shifted_cell(at, off, shape, limited):
    """Flat index of the cell ``at + off`` (around the turn on a free joint; offsets stay
    within one turn, so no integer division), or -1 beyond a limited joint's range."""
    flat = 0
    for j in range(at.shape[0]):
        c = at[j] + off[j]
        if limited[j]:
            if c < 0 or c >= shape[j]:
                return -1
        elif c < 0:
            c += shape[j]
        elif c >= shape[j]:
            c -= shape[j]
        flat = flat * shape[j] + c
    return flat


def _grid_insert(v, nodes, limited, cells, at):
    """Node ``v`` pushed onto the list of its cell in ``cells`` (:data:`Cells`)."""
    c = _cell(nodes[v], limited, cells.lo, cells.width, cells.shape, at)
    cells.nxt[v] = cells.head[c]
    cells.head[c] = v


def _cell_nodes_nearest(q, c, nodes, limited, cells, best_s, best_v, d):
    """The nodes of cell ``c`` against the nearest so far ``(best_s, best_v)`` (sum of squares,
    index; equal sums: the lower index), with the arithmetic of :func:`_nearest`; ``d`` is
    scratch."""
    head, nxt = cells.head, cells.nxt
    v = head[c]
    while v >= 0:
        s = _delta(q, nodes[v], limited, d)
        if s < best_s or (s == best_s and v < best_v):
            best_s = s
            best_v = v
        v = nxt[v]
    return best_s, best_v


def _grid_nearest(q, nodes, m, limited, cells, at, off):
    """:func:`_nearest` through the grid ``cells`` (:data:`Cells`): cells in growing rings
    around ``q``'s until no unvisited cell can hold a nearer node; the linear scan once the
    rings would visit more cells than there are nodes."""
    n = q.shape[0]
    w, shape = cells.width, cells.shape
    _cell(q, limited, cells.lo, w, shape, at)
    wmin = np.inf
    gmin = shape[0]
    for j in range(n):
        wmin = min(wmin, w[j])
        gmin = min(gmin, shape[j])
    best_s = np.inf
    best_v = -1
    d = np.empty(n)
    rho = 0
    cells_seen = 0
    while True:
        cells_seen += (2 * rho + 1) ** n
        if cells_seen > m or 2 * rho + 1 > gmin:  # (a ring must not wrap onto itself)
            return _nearest(nodes, m, q, limited)
        for j in range(n):
            off[j] = -rho
        while True:
            shell = rho == 0
            for j in range(n):
                if off[j] == rho or off[j] == -rho:
                    shell = True
            flat = _shifted_cell(at, off, shape, limited) if shell else -1
            if flat >= 0:
                best_s, best_v = _cell_nodes_nearest(q, flat, nodes, limited, cells, best_s,
                                                     best_v, d)
            j = n - 1
            while j >= 0 and off[j] == rho:
                off[j] = -rho
                j -= 1
            if j < 0:
                break
            off[j] += 1
        # Every node not seen lies in a cell at least rho + 1 cells away on some axis: more
        # than rho cell widths away (the margin covers rounding at the cell borders).
        if best_v >= 0 and (rho * wmin * (1 - 1e-9)) ** 2 > best_s:
            return best_v
        rho += 1


def _grid_near(q, r, nodes, limited, cells, at, off, span, out):
    """Indices of the nodes within ``r`` of ``q`` (sum of squares ``<= r * r``, the
    arithmetic of the linear scan), ascending, into ``out``; returns how many. ``cells``
    is the grid (:data:`Cells`); ``at``, ``off``, ``span`` scratch."""
    n = q.shape[0]
    r2 = r * r
    w, shape, head, nxt = cells.width, cells.shape, cells.head, cells.nxt
    _cell(q, limited, cells.lo, w, shape, at)
    for j in range(n):
        reach = int(r / w[j]) + 1  # cells are wider than r by a margin over any rounding
        if 2 * reach + 1 >= shape[j]:
            span[j] = shape[j]  # every cell of this axis, once
            at[j] = 0
        else:
            span[j] = 2 * reach + 1
            at[j] -= reach
        off[j] = 0
    k = 0
    d = np.empty(n)
    while True:
        flat = _shifted_cell(at, off, shape, limited)
        if flat >= 0:
            v = head[flat]
            while v >= 0:
                if _delta(q, nodes[v], limited, d) <= r2:
                    out[k] = v
                    k += 1
                v = nxt[v]
        j = n - 1
        while j >= 0 and off[j] == span[j] - 1:
            off[j] = 0
            j -= 1
        if j < 0:
            break
        off[j] += 1
    out[:k].sort()
    return k


def _link(i, p, parent, first_child, next_sib, prev_sib):
    """Make ``p`` the parent of ``i`` in the child lists (``i`` unlinked before, if linked)."""
    parent[i] = p
    prev_sib[i] = -1
    next_sib[i] = first_child[p]
    if first_child[p] >= 0:
        prev_sib[first_child[p]] = i
    first_child[p] = i


def _unlink(i, parent, first_child, next_sib, prev_sib):
    if prev_sib[i] >= 0:
        next_sib[prev_sib[i]] = next_sib[i]
    else:
        first_child[parent[i]] = next_sib[i]
    if next_sib[i] >= 0:
        prev_sib[next_sib[i]] = prev_sib[i]


def _star(targets, problem, scene, tree, cells, buf):
    """Iterations of rapp.rrt_star.rrt_star's loop, one per row of ``targets`` (drawn by the
    planner's generator): nearest node, steer, near set, cheapest certified parent, rewiring
    (descendants' costs through child lists), the goal joined. ``problem`` is a
    :data:`StarProblem`, ``scene`` a :data:`Scene`, ``tree`` a :data:`StarTree`, ``cells``
    the grid of its nodes (:data:`Cells`), ``buf`` the near set's buffers (:data:`NearSet`).
    Returns ``(status, iterations run)``, status CONNECT_LIMIT when an edge needed more
    intervals than ``scene.cap``."""
    n = targets.shape[1]
    work = StarWork(np.empty((3, n)), np.empty(n), np.empty(n), np.empty(n, dtype=np.int64),
                    np.empty(n, dtype=np.int64), np.empty(n, dtype=np.int64), np.empty(n),
                    np.empty((n + 1, 2)))
    for v in range(cells.indexed[0], tree.m[0]):
        _grid_insert(v, tree.nodes, scene.limited, cells, work.at)
    cells.indexed[0] = tree.m[0]
    for it in range(targets.shape[0]):
        if _star_iteration(targets[it], problem, scene, tree, cells, buf, work) < 0:
            return CONNECT_LIMIT, it + 1
    return CONNECT_MORE, targets.shape[0]


def _star_iteration(target, problem, scene, tree, cells, buf, work):
    """One iteration of :func:`_star` toward ``target``: 0 done (a node added or not), -1 an
    edge needed more intervals than allowed."""
    nodes, limited, d, q_new = tree.nodes, scene.limited, work.d, work.q_new
    n = target.shape[0]
    mm = tree.m[0]
    if mm > GRID_FROM:
        i = _grid_nearest(target, nodes, mm, limited, cells, work.at, work.off)
    else:
        i = _nearest(nodes, mm, target, limited)
    dd = math.sqrt(_delta(target, nodes[i], limited, d))
    if dd == 0.0:
        return 0
    f = min(1.0, problem.step / dd)
    for j in range(n):
        q_new[j] = nodes[i, j] + f * d[j]
    s = scene
    c_new = work.c_new
    _clearances_one(s.lengths, q_new, work.pts, c_new, s.circles, s.pv, s.pn, s.pr, s.offsets)
    for j in range(n):
        if c_new[j] <= s.touch:  # no edge to it is free
            return 0
    k = _near_set(q_new, i, problem, scene, tree, cells, buf, work)
    # The cheapest parent whose edge is free (choose_parent_and_add).
    for v in range(k):
        buf.key[v] = tree.cost[buf.near[v]] + buf.dist[v]
    order = np.argsort(buf.key[:k], kind="mergesort")
    chosen = -1
    for o in order:
        p = buf.near[o]
        code = _edge_free(nodes[p], buf.dn[o], tree.clear[p], c_new, scene, work.scratch)
        if code < 0:
            return -1
        if code == 1:
            chosen = o
            break
    if chosen < 0:
        return 0
    p = buf.near[chosen]
    new = _add_node(q_new, c_new, p, tree.cost[p] + buf.dist[chosen], limited, tree, cells,
                    work.at)
    if _rewire(new, k, scene, tree, buf, work) < 0:
        return -1
    return _join_goal(new, problem, scene, tree, cells, work)


def _near_set(q_new, i, problem, scene, tree, cells, buf, work):
    """The nodes within the shrinking radius of ``q_new`` (and the nearest ``i`` always) into
    ``buf.near``, their differences to ``q_new`` into ``buf.dn`` and distances into
    ``buf.dist``; returns how many."""
    nodes, limited, near, dn, dist = tree.nodes, scene.limited, buf.near, buf.dn, buf.dist
    n = q_new.shape[0]
    mm = tree.m[0]
    radius = min(problem.rcap, problem.gamma * (math.log(mm + 1) / (mm + 1)) ** (1 / n))
    r2 = radius * radius
    k = 0
    has_i = False
    if mm > GRID_FROM:
        found = _grid_near(q_new, radius, nodes, limited, cells, work.at, work.off, work.span,
                           buf.stack)
    else:
        found = mm
    for t in range(found):
        v = buf.stack[t] if mm > GRID_FROM else t
        s = _delta(q_new, nodes[v], limited, dn[k])
        if s <= r2:
            near[k] = v
            dist[k] = math.sqrt(s)
            has_i = has_i or v == i
            k += 1
    if not has_i:
        near[k] = i
        dist[k] = math.sqrt(_delta(q_new, nodes[i], limited, dn[k]))
        k += 1
    return k


def _add_node(q, c, par, cost, limited, tree, cells, at):
    """Node ``m`` of ``tree`` at ``q`` (wrapped), its link clearances ``c``, child of ``par``
    at ``cost``, filed in ``cells``; returns its index."""
    new = tree.m[0]
    for j in range(q.shape[0]):
        tree.nodes[new, j] = q[j] if limited[j] else _wrap(q[j])
        tree.clear[new, j] = c[j]
    tree.cost[new] = cost
    tree.first_child[new] = -1
    _link(new, par, tree.parent, tree.first_child, tree.next_sib, tree.prev_sib)
    tree.m[0] = new + 1
    _grid_insert(new, tree.nodes, limited, cells, at)
    cells.indexed[0] = tree.m[0]
    return new


def _rewire(new, k, scene, tree, buf, work):
    """Rewire the ``k`` near nodes (but the new node's parent) through node ``new`` where
    cheaper (rapp.rrt_star's ``_rewire``): which are cheaper is decided first, then each
    certified edge applied. Returns -1 when an edge needed more intervals than allowed."""
    nodes, cost, parent, near, dn, key = tree.nodes, tree.cost, tree.parent, buf.near, buf.dn, buf.key
    n = nodes.shape[1]
    kb = 0
    for v in range(k):
        u = near[v]
        if u == parent[new]:
            continue
        through = cost[new] + math.sqrt(_delta(nodes[u], nodes[new], scene.limited, dn[v]))
        if through < cost[u] - 1e-12:
            near[kb] = u
            key[kb] = through
            for j in range(n):
                dn[kb, j] = dn[v, j]
            kb += 1
    for v in range(kb):
        u = near[v]
        code = _edge_free(nodes[new], dn[v], tree.clear[new], tree.clear[u], scene,
                          work.scratch)
        if code < 0:
            return -1
        if code == 0:
            continue
        delta = key[v] - cost[u]
        _unlink(u, parent, tree.first_child, tree.next_sib, tree.prev_sib)
        _link(u, new, parent, tree.first_child, tree.next_sib, tree.prev_sib)
        cost[u] = key[v]
        _shift_descendants(u, delta, tree, buf.stack)
    return 0


def _shift_descendants(u, delta, tree, stack):
    """``delta`` added to the cost of every descendant of ``u`` (a depth-first walk of the
    child lists on ``stack``)."""
    first_child, next_sib, cost = tree.first_child, tree.next_sib, tree.cost
    top = 0
    c = first_child[u]
    while c >= 0:
        stack[top] = c
        top += 1
        c = next_sib[c]
    while top:
        top -= 1
        w = stack[top]
        cost[w] += delta
        c = first_child[w]
        while c >= 0:
            stack[top] = c
            top += 1
            c = next_sib[c]


def _join_goal(new, problem, scene, tree, cells, work):
    """A node close to a goal is joined to it exactly (the edge certified too): node ``new``
    against the nearest of ``problem.goals``. Returns -1 when that edge needed more
    intervals than allowed, else 0."""
    nodes, limited, cost, d = tree.nodes, scene.limited, tree.cost, work.d
    goals = problem.goals
    best, best_cost = tree.best, tree.best_cost
    g = 0
    best_s = np.inf
    for h in range(goals.shape[0]):
        s = _delta(goals[h], nodes[new], limited, d)
        if s < best_s:
            best_s = s
            g = h
    _delta(goals[g], nodes[new], limited, d)
    gd = math.sqrt(best_s)
    # Against the best goal node's cost now: rewiring may have lowered it since.
    if best[0] >= 0:
        best_cost[0] = cost[best[0]]
    if not (gd <= problem.goal_threshold and cost[new] + gd < best_cost[0]):
        return 0
    if gd == 0.0:
        best[0] = new
        best_cost[0] = cost[new]
        return 0
    code = _edge_free(nodes[new], d, tree.clear[new], problem.goal_clear[g], scene, work.scratch)
    if code < 0:
        return -1
    if code == 1:
        gi = _add_node(goals[g], problem.goal_clear[g], new, cost[new] + gd, limited, tree,
                       cells, work.at)
        best[0] = gi
        best_cost[0] = cost[gi]
    return 0


def _draw(buf, pos, bias, lower, span, goal, out):
    """Targets from a block of the generator's doubles, as ``rng.random() < bias`` then the
    goal or ``rng.uniform(lower, upper)`` draw them one by one (numpy's uniform is
    ``lower + span * double``; with one goal ``rng.integers(1)`` draws nothing). Fills rows
    of ``out`` while ``buf`` lasts; returns ``(rows filled, next position)``."""
    n = out.shape[1]
    t = 0
    while t < out.shape[0] and pos + 1 + n <= buf.shape[0]:
        u = buf[pos]
        pos += 1
        if u < bias:
            for j in range(n):
                out[t, j] = goal[j]
        else:
            for j in range(n):
                out[t, j] = lower[j] + span[j] * buf[pos + j]
            pos += n
        t += 1
    return t, pos


@functools.cache
def _compile():
    ck = collision_backend.kernels()
    if ck is None:
        return None

    g = globals()
    g["_clearances"], g["_certify"], g["_clearances_one"] = (ck.clearances, ck.certify,
                                                            ck.clearances_one)
    g["_wrap"] = jit(_wrap)
    g["_delta"] = jit(_delta)
    g["_nearest_scan"] = jit(_nearest_scan)
    g["_nearest"] = jit(_nearest)
    g["_extend"] = jit(_extend)
    for name in ("_shifted_cell", "_edge_bounds", "_bisect_bounded", "_bisect", "_edge_free",
                 "_link", "_unlink", "_cell", "_grid_nearest", "_grid_near"):
        g[name] = jit(g[name])
    # RRT*'s iteration in parts, inlined into its loop: a call that passes the named tuples
    # costs a reference count per array in them, a fifth of the loop's time when not inlined.
    for name in ("_grid_insert", "_cell_nodes_nearest", "_near_set", "_add_node",
                 "_shift_descendants", "_rewire", "_join_goal", "_star_iteration"):
        g[name] = jit(g[name], inline="always")
    return Loops(g["_wrap"], g["_extend"], jit(_connect), jit(_nearest_k), jit(_star),
                 jit(_draw), g["_bisect"])


def kernels():
    """The compiled :class:`Loops`, or None without numba (or when the collision
    kernel is switched off: :func:`rapp.kernels.collision.kernels` returns None)."""
    if collision_backend.kernels() is None:
        return None
    return _compile()
