"""The compiled numerical IK: one target at a time, start, Newton-Raphson and check in one loop.

:func:`rapp.ik_numeric` solves a batch with a handful of numpy calls per iteration; for
three links the fixed cost of those calls (and of building the start and checking the
answer) is most of its time. The loops here do the same work per target on scalars,
compiled by numba: the closed-form start of :func:`rapp.ik.closed_form_start` (exact for
most targets, so Newton-Raphson usually has nothing left to do), then the damped
least-squares iteration of :func:`rapp.ik.dls_step` with joint clamping, the step cap and
the wrap, as the numpy version does it (the rotation inside the step by half-angle
formulas rather than ``atan2``, ``cos`` and ``sin``), and finally the tip error
against the target: after Newton-Raphson evaluated as :meth:`rapp.Arm.end_effector`
evaluates it, for a closed-form start summed from the link directions the start computed
(its angles are their ``atan2``, within 2 ulp), which saves the ``cos`` and ``sin``.

That last check decides ``ok``. Either evaluation may differ from numpy's in the last bits
(compiled ``cos``/``sin``; the directions), so a tip error within 64 rounding errors of the
reach of ``tol`` is reported as *undecided* and the caller re-evaluates those few with
numpy: ``ok`` is then exactly the caller's own check. :func:`solver` compiles the loops on first use (cached on
disk, ``cache=True``) and returns None when numba cannot be imported; ``ik_numeric`` then
runs its numpy iteration, which gives the same successes. Importing this module does not
import numba.

Examples
--------
>>> s = solver()
>>> rows = np.array([[1.2, 0.7], [5.0, 0.0]])
>>> q, hopeless = np.zeros((2, 3)), np.zeros(2, bool)
>>> free = np.zeros(3, bool), np.full(3, -np.pi), np.full(3, np.pi)
>>> s is None or s.solve(np.array([1.0, 0.8, 0.5]), *free, rows, q, np.ones(2, bool), hopeless,
...                      1e-12, 1e-10, 30, 1.0).tolist() == [OK, NOT_OK]
True
>>> s is None or hopeless.tolist() == [False, True]
True
"""

from __future__ import annotations

import functools
import math
from collections import namedtuple

import numpy as np

from rapp.jit import jit, numba_available

__all__ = ["Kernels", "Joints", "solver", "LOAD_FROM", "SIGMA_FLOOR", "LAMBDA_MAX", "NOT_OK", "OK", "UNSURE",
           "NO_START"]

#: The compiled functions (see :func:`solver`): ``solve`` is :func:`_solve`, ``start_errors``
#: :func:`_start_errors` and ``atan2`` :func:`_atan2` (the last two for the tests).
Kernels = namedtuple("Kernels", "solve start_errors atan2")
#: The arm as the iteration sees it: link ``lengths`` (scaled to total length 1), which
#: joints are ``limited`` and their bounds ``lo``, ``hi``.
Joints = namedtuple("Joints", "lengths limited lo hi")

#: The damping constants of the iteration (on the arm scaled to total length 1), shared
#: with the numpy version.
SIGMA_FLOOR = 1e-3
LAMBDA_MAX = 1e-2

#: Batches of at least this many targets load the compiled solver even when numba is not
#: imported yet (importing it costs a few tenths of a second, more than numpy spends on
#: a few hundred targets); smaller ones use it once numba is imported.
LOAD_FROM = 2048


# The rational approximation of atan on [-0.66, 0.66] from Cephes (S. L. Moshier's atan.c):
# atan(r) = r + r z P(z) / Q(z), z = r^2, relative error about 1e-16.
_ATAN_P = (-8.750608600031904122785e-1, -1.615753718733365076637e1, -7.500855792314704667340e1,
           -1.228866684490136173410e2, -6.485021904942025371773e1)
_ATAN_Q = (2.485846490142306297962e1, 1.650270098316988542046e2, 4.328810604912902668951e2,
           4.853903996359136964868e2, 1.945506571482613964425e2)


def _atan2(y, x):
    """``atan2(y, x)`` within 2 ulp of libm's (4 tested), in a third of its time.

    The ratio ``t`` of the smaller to the larger of ``|x|, |y|`` (in [0, 1]) is taken to
    [-0.66, 0.66] by ``atan t = pi/4 + atan((t - 1) / (t + 1))`` above 0.66, where the
    rational approximation holds; then the octant and the signs put the angle back. Zeros,
    infinities and NaN go to libm. The closed-form start calls it three times per target
    (its check sums the directions these angles are taken of, and ``tests/test_ik_kernel.py``
    compares it with ``math.atan2``).
    """
    ay = abs(y)
    ax = abs(x)
    swap = ay > ax
    hi = ay if swap else ax
    lo = ax if swap else ay
    if not (hi > 0.0 and hi < math.inf):
        return math.atan2(y, x)
    big = lo > 0.66 * hi
    # (t - 1) / (t + 1) with t = lo / hi, in one division
    r = (lo - hi) / (lo + hi) if big else lo / hi
    z = r * r
    p = (((_ATAN_P[0] * z + _ATAN_P[1]) * z + _ATAN_P[2]) * z + _ATAN_P[3]) * z + _ATAN_P[4]
    q = ((((z + _ATAN_Q[0]) * z + _ATAN_Q[1]) * z + _ATAN_Q[2]) * z + _ATAN_Q[3]) * z + _ATAN_Q[4]
    a = r + r * z * p / q
    if big:
        a += 0.25 * math.pi
    if swap:
        a = 0.5 * math.pi - a
    if x < 0.0:
        a = math.pi - a
    return math.copysign(a, y)


def _arm_constants(lengths):
    """What :func:`_closed_form` needs of the (scaled) arm, computed once per batch:
    ``L1, L2``, the tail length ``L_t``, ``1 / L_t`` (0 without a tail) and ``1 / (2 L1 L2)``."""
    n = lengths.size
    out = np.zeros(5)
    out[0] = lengths[0]
    if n > 1:
        out[1] = lengths[1]
        for j in range(2, n):
            out[2] += lengths[j]
        out[3] = 1.0 / out[2] if out[2] > 0.0 else 0.0
        out[4] = 0.5 / (lengths[0] * lengths[1])
    return out


def _closed_form(arm, tx, ty, q, dirs):
    """The start of :func:`rapp.ik.closed_form_start` for one target, into ``q``; False
    where it does not exist (``q`` untouched). ``arm`` from :func:`_arm_constants`.

    The same geometry with the directions carried as unit vectors, so that only the
    three joint angles need an ``atan2`` (no ``acos``, ``cos`` or ``sin``).
    """
    n = q.size
    if n == 1:
        q[0] = math.atan2(ty, tx)
        r = math.sqrt(tx * tx + ty * ty)
        dirs[0], dirs[1] = (tx / r, ty / r) if r > 0.0 else (1.0, 0.0)
        return True
    l1, l2, lt, inv_lt, inv_two = arm[0], arm[1], arm[2], arm[3], arm[4]
    r = math.sqrt(tx * tx + ty * ty)
    a = max(abs(l1 - l2), abs(r - lt))
    b = min(l1 + l2, r + lt)
    if not a <= b:
        return False
    d = 0.5 * (a + b)
    if r > 0.0:
        inv_r = 1.0 / r
        ux = tx * inv_r
        uy = ty * inv_r
        ca = min(1.0, max(-1.0, (r * r + lt * lt - d * d) * (0.5 * inv_r * inv_lt)))
    else:
        ux, uy, ca = 1.0, 0.0, 1.0
    sa = math.sqrt((1.0 - ca) * (1.0 + ca))
    # The tail's direction: the target's turned by alpha.
    ex = ux * ca - uy * sa
    ey = uy * ca + ux * sa
    wx = tx - lt * ex
    wy = ty - lt * ey
    rw = math.sqrt(wx * wx + wy * wy)
    r_out = l1 + l2
    r_in = abs(l1 - l2)
    one_minus = max(0.0, (r_out - rw) * (r_out + rw)) * inv_two
    one_plus = max(0.0, (rw - r_in) * (rw + r_in)) * inv_two
    c2 = min(1.0, max(-1.0, (rw * rw - l1 * l1 - l2 * l2) * inv_two))
    s2 = math.sqrt(one_minus * one_plus)
    # The wrist seen from link 1's frame is k; link 1 points along w turned back by k.
    kx = l1 + l2 * c2
    ky = l2 * s2
    cx = wx * kx + wy * ky
    cy = wy * kx - wx * ky
    q[0] = _atan2(cy, cx)
    q[1] = _atan2(s2, c2)
    norm = math.sqrt(cx * cx + cy * cy)
    inv = 1.0 / norm if norm > 0.0 else 0.0
    c1, s1 = (cx * inv, cy * inv) if norm > 0.0 else (1.0, 0.0)
    vx = wx - l1 * c1
    vy = wy - l1 * s1
    if n > 2:
        q[2] = _atan2(ey * vx - ex * vy, ex * vx + ey * vy)
        for j in range(3, n):
            q[j] = 0.0
    # The links' directions, for the tip check: link 2 along v, normalized.
    nv = math.sqrt(vx * vx + vy * vy)
    inv = 1.0 / nv if nv > 0.0 else 0.0
    dirs[0] = c1
    dirs[1] = s1
    dirs[2], dirs[3] = (vx * inv, vy * inv) if nv > 0.0 else (c1, s1)
    dirs[4] = ex
    dirs[5] = ey
    return True


def _project(q, limited, lo, hi):
    """Clip limited joints, wrap free ones to [-pi, pi), as ``rapp.ik`` does."""
    for j in range(q.size):
        if limited[j]:
            q[j] = min(max(q[j], lo[j]), hi[j])
        elif not -math.pi <= q[j] < math.pi:
            q[j] = (q[j] + math.pi) % (2.0 * math.pi) - math.pi
            if q[j] >= math.pi:  # just below -pi: the sum rounded up to 2 pi
                q[j] = -math.pi


def _dls(jx, jy, ex, ey, dq):
    """:func:`rapp.ik.dls_step` for one column, into ``dq``.

    The same step; only the rotation ``(cos t, sin t)`` that diagonalises ``J J^T`` comes
    from half-angle formulas instead of ``atan2``, ``cos`` and ``sin`` of
    ``t = atan2(2 b, a - c) / 2`` (the larger of the two square roots taken, the other
    from ``sin t cos t = b / h``, so that neither cancels).
    """
    n = jx.size
    a = 0.0
    b = 0.0
    c = 0.0
    for j in range(n):
        a += jx[j] * jx[j]
        b += jx[j] * jy[j]
        c += jy[j] * jy[j]
    d = a - c
    h = math.sqrt(d * d + 4.0 * b * b)
    if not h > 0.0:
        ct, st = 1.0, 0.0
    elif d >= 0.0:
        ct = math.sqrt((h + d) / (2.0 * h))
        st = b / (h * ct)
    else:
        st = math.copysign(math.sqrt((h - d) / (2.0 * h)), b)
        ct = b / (h * st)
    sig2_min = 0.0
    sig2_big = 0.0
    for j in range(n):
        w_big = jx[j] * ct + jy[j] * st
        w_small = jy[j] * ct - jx[j] * st
        sig2_min += w_small * w_small
        sig2_big += w_big * w_big
    lam2 = (1.0 - min(sig2_min / SIGMA_FLOOR**2, 1.0)) * min(
        LAMBDA_MAX**2, math.sqrt(ex * ex + ey * ey))
    den_big = sig2_big + lam2
    den_small = sig2_min + lam2
    f_big = (ex * ct + ey * st) / den_big if den_big > 0.0 else 0.0
    f_small = (ey * ct - ex * st) / den_small if den_small > 0.0 else 0.0
    for j in range(n):
        dq[j] = (jx[j] * ct + jy[j] * st) * f_big + (jy[j] * ct - jx[j] * st) * f_small


def _newton(joints, tx, ty, q, stop2, max_iter, max_step, jx, jy, dq):
    """``rapp.ik``'s Newton-Raphson with damped least squares on one configuration ``q`` of
    the arm ``joints`` (:data:`Joints`)."""
    lengths, limited, lo, hi = joints
    n = lengths.size
    any_limited = False
    for j in range(n):
        any_limited = any_limited or limited[j]
    for _ in range(max_iter):
        c = math.cos(q[0])
        s = math.sin(q[0])
        jy[0] = lengths[0] * c
        jx[0] = lengths[0] * s
        for j in range(1, n):
            cq = math.cos(q[j])
            sq = math.sin(q[j])
            c, s = c * cq - s * sq, s * cq + c * sq
            jy[j] = lengths[j] * c
            jx[j] = lengths[j] * s
        for j in range(n - 2, -1, -1):
            jy[j] += jy[j + 1]
            jx[j] += jx[j + 1]
        ex = tx - jy[0]
        ey = ty - jx[0]
        if ex * ex + ey * ey <= stop2:
            return
        for j in range(n):
            jx[j] = -jx[j]
        _dls(jx, jy, ex, ey, dq)
        if any_limited:
            # Joint clamping, as in rapp.ik: a limited joint the step would push out is
            # frozen and the step recomputed.
            blocked = False
            for j in range(n):
                if limited[j] and (q[j] + dq[j] < lo[j] or q[j] + dq[j] > hi[j]):
                    jx[j] = 0.0
                    jy[j] = 0.0
                    blocked = True
            if blocked:
                _dls(jx, jy, ex, ey, dq)
        norm2 = 0.0
        for j in range(n):
            norm2 += dq[j] * dq[j]
        if norm2 > max_step * max_step:
            f = max_step / math.sqrt(norm2)
            for j in range(n):
                dq[j] *= f
        for j in range(n):
            q[j] += dq[j]
        _project(q, limited, lo, hi)


def _tip_error(lengths, q, x, y):
    """``norm(arm.end_effector(q) - (x, y))`` summed in the order numpy sums it."""
    phi = 0.0
    px = 0.0
    py = 0.0
    for j in range(lengths.size):
        phi += q[j]
        px += math.cos(phi) * lengths[j]
        py += math.sin(phi) * lengths[j]
    dx = px - x
    dy = py - y
    return math.sqrt(dx * dx + dy * dy)


#: Status of a target after :func:`_solve`.
NOT_OK, OK, UNSURE, NO_START = 0, 1, 2, 3


def _start_error(arm, dirs, x, y):
    """Tip error of a closed-form start from the link directions ``dirs`` it computed
    (``arm`` from :func:`_arm_constants` of the true lengths): no ``cos`` or ``sin``.

    Each joint angle of the start is the ``atan2`` of the directions used here (within
    2 ulp, :func:`_atan2`), so this differs from numpy's evaluation of the returned angles by a few
    rounding errors of the reach (``tests/test_ik_kernel.py`` bounds it by 16 of them;
    at most 3.4 were seen).
    """
    px = arm[0] * dirs[0] + arm[1] * dirs[2] + arm[2] * dirs[4] - x
    py = arm[0] * dirs[1] + arm[1] * dirs[3] + arm[2] * dirs[5] - y
    return math.sqrt(px * px + py * py)


def _start_errors(true_lengths, rows, q):
    """The closed-form start of every target (m, 2) into ``q`` (m, n) and its tip error as
    :func:`_solve` evaluates it (NaN where there is no start); for the tests."""
    m, n = q.shape
    scale = 0.0
    for j in range(n):
        scale += true_lengths[j]
    arm = _arm_constants(true_lengths / scale)
    big = _arm_constants(true_lengths)
    dirs = np.zeros(6)
    out = np.full(m, np.nan)
    for i in range(m):
        if _closed_form(arm, rows[i, 0] / scale, rows[i, 1] / scale, q[i], dirs):
            out[i] = _start_error(big, dirs, rows[i, 0], rows[i, 1])
    return out


def _solve(true_lengths, limited, lo, hi, rows, q, closed, hopeless, stop_tol, tol, max_iter,
           max_step):
    """One attempt of ``rapp.ik_numeric`` for every row of ``q`` (m, n), in place.

    ``rows`` (m, 2) are the targets. Where ``closed`` the start is the closed form, or for
    a target beyond the outer circle the stretched arm facing it; elsewhere ``q``'s row.
    The iteration runs on the arm and targets scaled to total length 1, as numpy's does.
    Fills ``hopeless`` (m,) (beyond the outer circle: never iterated) and returns the
    int8 status (m,): OK, NOT_OK, UNSURE (tip error within rounding of ``tol``: re-check
    with numpy) or NO_START (no closed form: ``q``'s row untouched, give it a start).
    """
    m, n = q.shape
    status = np.zeros(m, dtype=np.int8)
    jx = np.empty(n)
    jy = np.empty(n)
    dq = np.empty(n)
    scale = 0.0
    for j in range(n):
        scale += true_lengths[j]
    lengths = true_lengths / scale
    joints = Joints(lengths, limited, lo, hi)
    arm = _arm_constants(lengths)
    big = _arm_constants(true_lengths)
    dirs = np.zeros(6)
    eps = 2.220446049250313e-16
    # The closed-form start needs no iteration where its error meets the iteration's own stop.
    done = min(stop_tol * scale, tol - 64.0 * eps * scale)
    for i in range(m):
        qi = q[i]
        x = rows[i, 0]
        y = rows[i, 1]
        tx = x / scale
        ty = y / scale
        # numpy's test (hypot), taken only where the cheap one cannot tell.
        far = not tx * tx + ty * ty < 1.0 and (
            math.hypot(x, y) > scale * (1.0 + 1e-12)
            or not (math.isfinite(tx) and math.isfinite(ty)))
        hopeless[i] = far
        err = math.inf
        if far:
            if closed[i]:
                qi[0] = math.atan2(y, x)
                for j in range(1, n):
                    qi[j] = 0.0
            _project(qi, limited, lo, hi)
        elif closed[i]:
            if not _closed_form(arm, tx, ty, qi, dirs):
                status[i] = NO_START
                continue
            clipped = False
            for j in range(n):
                clipped = clipped or (limited[j] and not lo[j] <= qi[j] <= hi[j])
            _project(qi, limited, lo, hi)
            # Usually exact: then no Newton-Raphson (whose first look would stop it anyway).
            err = _tip_error(true_lengths, qi, x, y) if clipped else _start_error(big, dirs, x, y)
        else:
            _project(qi, limited, lo, hi)
        if not far and not err <= done:
            _newton(joints, tx, ty, qi, stop_tol * stop_tol, max_iter, max_step, jx, jy, dq)
            err = math.inf
        if err == math.inf:
            err = _tip_error(true_lengths, qi, x, y)
        inside = True
        for j in range(n):
            if limited[j] and not lo[j] <= qi[j] <= hi[j]:
                inside = False
        # cos/sin one ulp apart move the tip by at most a few eps * reach.
        margin = 64.0 * eps * (scale + abs(x) + abs(y)) + 4.0 * eps * tol
        if not inside or err > tol + margin:
            status[i] = NOT_OK
        elif err <= tol - margin:
            status[i] = OK
        else:
            status[i] = UNSURE
    return status


@functools.cache
def solver():
    """The compiled :class:`Kernels` (numba, cached on disk), or None without numba.

    The first call imports numba and loads the compiled code from its cache (or compiles
    it once, some seconds).
    """
    if not numba_available():
        return None
    g = globals()
    # Every function is replaced before the first call compiles them: _solve then finds
    # the compiled helpers.
    for name in ("_atan2", "_arm_constants", "_closed_form", "_project", "_dls", "_newton", "_tip_error",
                 "_start_error", "_start_errors", "_solve"):
        g[name] = jit(g[name], error_model="numpy")
    return Kernels(g["_solve"], g["_start_errors"], g["_atan2"])
