"""The planar N-link arm: forward kinematics of every joint (TM:FWDKinematics, DD1).

Angles are relative joint angles in radians, zero along +x, counter-clockwise
positive, base at the origin. Every function takes a batch of configurations
of shape ``(..., n)`` and works on it in one numpy call.
"""

from __future__ import annotations

import copy
from dataclasses import dataclass, field
from typing import Sequence

import numpy as np
from typing import TYPE_CHECKING, Iterable, Sequence  # noqa: F401  (annotations)

from numpy.typing import ArrayLike  # noqa: F401

__all__ = ["Arm", "wrap_angle", "MAX_COORDINATE", "MAX_ANGLE"]

#: Largest accepted size of the workspace, in length units: the link lengths of an
#: :class:`Arm` add up to at most this, and obstacles (:mod:`rapp.obstacles`) lie
#: within it. Squares and cross products of such coordinates stay below about
#: 1e201, far from the float64 overflow at 1.8e308, so no distance computation
#: can overflow. A real arm is many orders of magnitude smaller in any unit.
MAX_COORDINATE = 1e100

#: Largest accepted magnitude of a joint angle (and of a joint limit), radians.
#: Sums and differences of angles and their products with lengths up to
#: :data:`MAX_COORDINATE` then stay finite. (Far below this bound an angle has no
#: direction left: from 2**55 rad, about 3.6e16, consecutive floats are > 2 pi apart.)
MAX_ANGLE = 1e100


_TWO_PI = 2 * np.pi


def wrap_angle(q: ArrayLike) -> np.ndarray:
    """Wrap angles into ``[-pi, pi)``.

    Examples
    --------
    >>> float(wrap_angle(3 * np.pi / 2))
    -1.5707963267948966
    """
    x = np.asarray(q, dtype=float) + np.pi
    if x.size < 64 or not (x.min() >= -_TWO_PI and x.max() < 2 * _TWO_PI):
        return x % _TWO_PI - np.pi
    # Bit for bit the same as ``x % 2pi`` when -2pi <= x < 4pi (differences of two wrapped
    # angles, as in every nearest-node search), without numpy's slow float remainder:
    # fmod(x, 2pi) is x itself for |x| < 2pi and the exact x - 2pi (Sterbenz) for
    # 2pi <= x < 4pi, and ``%`` then adds 2pi to a negative result.
    neg, big = x < 0, x >= _TWO_PI
    x += neg * _TWO_PI  # adding (subtracting) 0.0 leaves the other entries as they are
    x -= big * _TWO_PI
    x -= np.pi
    return x


def _joint_limit(i: int, lim):
    """Entry ``i`` of ``joint_limits`` as ``None`` or a float pair, or a ValueError naming it."""
    if lim is None:
        return None
    bad = ValueError(
        f"joint_limits[{i}] must be None or a pair (lo, hi) of finite angles with lo < hi "
        f"and |lo|, |hi| <= {MAX_ANGLE:g} rad, got {lim!r}"
    )
    if isinstance(lim, (str, bytes)):
        raise bad
    try:
        lo, hi = lim
        lo, hi = float(lo), float(hi)
    except (TypeError, ValueError):
        raise bad from None
    if not (np.isfinite(lo) and np.isfinite(hi) and lo < hi and max(-lo, hi) <= MAX_ANGLE):
        raise bad
    return (lo, hi)


def _link_radius(value, n: int) -> tuple:
    """``link_radius`` as ``n`` floats, or a ValueError naming it."""
    bad = ValueError(
        f"link_radius must be one number or one per link ({n}), each finite, >= 0 and at most "
        f"{MAX_COORDINATE:g}, got {value!r}"
    )
    try:
        r = np.asarray(value, dtype=float)
    except (TypeError, ValueError):
        raise bad from None
    if r.shape not in ((), (n,)):
        raise bad
    r = np.broadcast_to(r, (n,))
    if not (np.all(np.isfinite(r)) and np.all(r >= 0) and np.all(r <= MAX_COORDINATE)):
        raise bad
    return tuple(float(v) for v in r)


@dataclass(frozen=True, eq=False)
class Arm:
    """A planar serial arm of revolute joints.

    Parameters
    ----------
    link_lengths : sequence of float
        ``L_1 .. L_n``, each finite and positive, adding up to at most
        :data:`MAX_COORDINATE`.
    joint_limits : sequence of (lo, hi) or None, optional
        One entry per joint; ``None`` (or ``None`` for the whole argument)
        means the joint turns freely and its angle wraps (a torus axis).
        Limits may be asymmetric (LC5) and must satisfy ``lo < hi`` and
        ``|lo|, |hi| <= MAX_ANGLE``.
    link_radius : float or sequence of float, optional
        The half-width of each link (one number for all, or one per link), finite and
        ``>= 0``, default 0: link ``j`` is the capsule of points within ``link_radius[j]``
        of its centre segment. Every collision test of :mod:`rapp.collision` and
        :mod:`rapp.cspace` keeps link ``j`` at least ``link_radius[j] + margin`` from every
        obstacle.
    self_collision : bool, optional
        Default False (the SRS's arm, whose links lie in layers and pass over each other).
        True: every NON-ADJACENT pair of links ``i, j`` must also keep
        ``pair_radius[i] + pair_radius[j] + margin`` apart (:func:`rapp.collision.self_gaps`);
        :func:`rapp.collision.collides`, :func:`rapp.collision.segment_collision_free` (hence
        every planner) and :mod:`rapp.verify` test it.

    Attributes
    ----------
    pair_radius : tuple of float
        The radius each link keeps from the other links in the self-collision test:
        ``link_radius``, except on :meth:`centre_lines` ``(margin)``, which keeps the original
        radii plus half the margin here so that the zero-width arm asks the same question.
    joint_names : sequence of str, optional
        One distinct name per joint (default ``joint1 .. jointn``): the names
        exports such as :func:`rapp.results.joint_trajectory` give the joints.
    base : (x, y, heading), optional
        Where the arm's base frame lies in the world (length units, radians;
        default ``(0, 0, 0)``). The arm's own kinematics (:meth:`joint_positions`,
        and every planner, collision test and IK solver with it) work in that
        frame; :meth:`world_positions` and :meth:`to_world` give world coordinates.
    joint_offsets : sequence of float, optional
        What each joint's encoder reads when the joint is at the model's zero
        (radians, default zeros): ``encoder = q - offset`` (:meth:`to_encoder`),
        ``q = encoder + offset`` (:meth:`from_encoder`).

    Raises
    ------
    ValueError
        Naming ``link_lengths``, the offending ``joint_limits[i]``, ``link_radius`` or ``self_collision``.

    Examples
    --------
    >>> arm = Arm([1.0, 1.0])
    >>> arm.end_effector([0.0, np.pi / 2]).round(12)
    array([1., 1.])
    >>> arm.joint_positions([0.0, 0.0]).tolist()
    [[0.0, 0.0], [1.0, 0.0], [2.0, 0.0]]
    >>> arm.reach
    (0.0, 2.0)
    >>> Arm([1.0, 1.0], link_radius=[0.05, 0.02]).link_radius
    (0.05, 0.02)
    >>> Arm([1.0, 1.0], [1.0, 2.0])
    Traceback (most recent call last):
    ...
    ValueError: joint_limits[0] must be None or a pair (lo, hi) of finite angles with lo < hi and |lo|, |hi| <= 1e+100 rad, got 1.0
    """

    link_lengths: tuple
    joint_limits: tuple | None = None
    link_radius: tuple = ()
    self_collision: bool = field(default=False, repr=False)
    pair_radius: tuple = field(default=(), repr=False)
    joint_names: tuple = field(default=(), repr=False)
    base: tuple = field(default=(0.0, 0.0, 0.0), repr=False)
    joint_offsets: tuple = field(default=(), repr=False)

    def __init__(self, link_lengths: Sequence[float],
                 joint_limits: Sequence[tuple[float, float] | None] | None = None,
                 link_radius: float | Sequence[float] = 0.0, self_collision: bool = False, *,
                 joint_names: Sequence[str] | None = None,
                 base: Sequence[float] = (0.0, 0.0, 0.0),
                 joint_offsets: Sequence[float] | None = None) -> None:
        try:
            lengths = np.asarray(link_lengths, dtype=float)
        except (TypeError, ValueError):
            raise ValueError(f"link_lengths must be a non-empty list of numbers, got {link_lengths!r}") from None
        if lengths.ndim != 1 or lengths.size == 0:
            raise ValueError("link_lengths must be a non-empty list of numbers")
        if not np.all(np.isfinite(lengths)) or np.any(lengths <= 0):
            raise ValueError(f"link_lengths must be finite and > 0, got {lengths.tolist()}")
        # Checked link by link first so that the sum below cannot overflow.
        if np.any(lengths > MAX_COORDINATE) or lengths.sum() > MAX_COORDINATE:
            raise ValueError(
                f"link_lengths must add up to at most {MAX_COORDINATE:g} (rapp.arm.MAX_COORDINATE), "
                f"beyond which distances overflow float64, got {lengths.tolist()}"
            )
        n = lengths.size
        if joint_limits is None:
            limits = (None,) * n
        else:
            try:
                if isinstance(joint_limits, (str, bytes)):
                    raise TypeError
                joint_limits = list(joint_limits)
            except TypeError:
                raise ValueError(
                    f"joint_limits must be None or a list of one (lo, hi) or None per joint, "
                    f"got {joint_limits!r}"
                ) from None
            if len(joint_limits) != n:
                raise ValueError(
                    f"joint_limits has {len(joint_limits)} entries but the arm has {n} joints"
                )
            limits = tuple(_joint_limit(i, lim) for i, lim in enumerate(joint_limits))
        object.__setattr__(self, "link_lengths", tuple(float(v) for v in lengths))
        object.__setattr__(self, "joint_limits", limits)
        object.__setattr__(self, "link_radius", _link_radius(link_radius, n))
        if not isinstance(self_collision, (bool, np.bool_)):
            raise ValueError(f"self_collision must be true or false, got {self_collision!r}")
        object.__setattr__(self, "self_collision", bool(self_collision))
        object.__setattr__(self, "pair_radius", self.link_radius)
        _set_frame(self, n, joint_names, base, joint_offsets)
        # Read-only arrays built once: planners ask for them per configuration.
        cached = {
            "_lengths": np.array(self.link_lengths),
            "_limited": np.array([lim is not None for lim in limits]),
            "_lower": np.array([-np.pi if lim is None else lim[0] for lim in limits]),
            "_upper": np.array([np.pi if lim is None else lim[1] for lim in limits]),
        }
        for name, arr in cached.items():
            arr.setflags(write=False)
            object.__setattr__(self, name, arr)

    def __eq__(self, other: object) -> bool:
        return (
            isinstance(other, Arm)
            and self.link_lengths == other.link_lengths
            and self.joint_limits == other.joint_limits
            and self.link_radius == other.link_radius
            and self.self_collision == other.self_collision
            and self.pair_radius == other.pair_radius
            and self.joint_names == other.joint_names
            and self.base == other.base
            and self.joint_offsets == other.joint_offsets
        )

    def __hash__(self) -> int:
        return hash((self.link_lengths, self.joint_limits, self.link_radius, self.self_collision))

    def centre_lines(self, margin: float = 0.0) -> "Arm":
        """This arm with zero-width links (``link_radius`` 0), every other field the same.

        With ``self_collision``, :attr:`pair_radius` keeps the original radii plus
        ``margin / 2`` (so a pair still keeps ``r_i + r_j + margin`` apart).

        Examples
        --------
        >>> Arm([1.0], link_radius=0.1).centre_lines().link_radius
        (0.0,)
        >>> Arm([1.0, 1.0, 1.0], link_radius=0.1, self_collision=True).centre_lines(0.1).pair_radius
        (0.15000000000000002, 0.15000000000000002, 0.15000000000000002)
        """
        if not any(self.link_radius) and not (self.self_collision and margin):
            return self
        thin = copy.copy(self)
        object.__setattr__(thin, "link_radius", (0.0,) * self.n)
        if self.self_collision:
            object.__setattr__(thin, "pair_radius", tuple(float(p + margin / 2) for p in self.pair_radius))
        return thin

    @property
    def n(self) -> int:
        """Number of joints (and links)."""
        return len(self.link_lengths)

    @property
    def lengths(self) -> np.ndarray:
        """Link lengths as a read-only float array of shape ``(n,)``."""
        return self._lengths

    @property
    def limited(self) -> np.ndarray:
        """Boolean ``(n,)``, read-only: True where a joint has limits (a bounded axis)."""
        return self._limited

    @property
    def lower(self) -> np.ndarray:
        """Lower joint bounds, ``-pi`` for a free joint (read-only)."""
        return self._lower

    @property
    def upper(self) -> np.ndarray:
        """Upper joint bounds, ``pi`` for a free joint (read-only)."""
        return self._upper

    @property
    def reach(self) -> tuple[float, float]:
        """Inner and outer radius of the workspace annulus of the free arm.

        The outer radius is the sum of the links. The inner radius is
        ``max(0, 2 max(L) - sum(L))``: the longest link folded back on all the
        others; for two links it is ``|L1 - L2|``. Joint limits can only shrink
        the workspace, so for a limited arm this annulus is an outer bound.
        """
        lengths = self.lengths
        total = float(lengths.sum())
        return (max(0.0, 2.0 * float(lengths.max()) - total), total)

    def check_q(self, q, name: str = "q", *, max_abs: float = MAX_ANGLE) -> np.ndarray:
        """``q`` as a float array of configurations ``(..., n)``, or a ValueError naming ``name``.

        Every function that takes configurations calls this first, so a wrong
        shape or a NaN/infinite angle is refused with the argument's name
        instead of turning into a wrong answer further down. Angles larger in
        magnitude than ``max_abs`` (default :data:`MAX_ANGLE`) are refused too:
        the kinematics and collision bounds would overflow on them.

        Examples
        --------
        >>> Arm([1.0, 1.0]).check_q([[0.0, 1.0]]).shape
        (1, 2)
        >>> Arm([1.0, 1.0]).check_q([0.0, float("nan")], "start")
        Traceback (most recent call last):
        ...
        ValueError: start must be finite joint angles, got [0.0, nan]
        """
        try:
            q = np.asarray(q, dtype=float)
        except (TypeError, ValueError):
            raise ValueError(f"{name} must be an array of joint angles of shape (..., {self.n})") from None
        if q.ndim == 0 or q.shape[-1] != self.n:
            raise ValueError(f"{name} must have shape (..., {self.n}), got {q.shape}")
        if not np.isfinite(q).all():
            shown = q.tolist() if q.size <= 8 else "an array with non-finite entries"
            raise ValueError(f"{name} must be finite joint angles, got {shown}")
        if np.any(np.abs(q) > max_abs):
            shown = q.tolist() if q.size <= 8 else "an array with larger entries"
            which = " (rapp.arm.MAX_ANGLE)" if max_abs == MAX_ANGLE else ""
            raise ValueError(
                f"{name} must be joint angles of magnitude at most {max_abs:g} rad{which}, got {shown}"
            )
        return q

    def joint_delta(self, q_from, q_to) -> np.ndarray:
        """``q_to - q_from``, taken the short way round on every free joint.

        A free joint lives on a circle, so its difference is wrapped into
        ``[-pi, pi)``; a limited joint lives on an interval and keeps the plain
        difference. Broadcasts over leading axes.

        Examples
        --------
        >>> arm = Arm([1.0, 1.0], [None, (-3.0, 3.0)])
        >>> arm.joint_delta([3.0, -2.9], [-3.0, 2.9]).round(4).tolist()
        [0.2832, 5.8]
        """
        d = np.asarray(q_to, dtype=float) - np.asarray(q_from, dtype=float)
        if d.shape[-1:] == self.limited.shape and not self.limited.any():  # np.where's values
            return wrap_angle(d)
        return np.where(self.limited, d, wrap_angle(d))

    def wrap(self, q) -> np.ndarray:
        """``q`` with every free joint wrapped into ``[-pi, pi)``; limited joints untouched.

        Examples
        --------
        >>> Arm([1.0, 1.0], [None, (-4.0, 4.0)]).wrap([3.5, 3.5]).round(4).tolist()
        [-2.7832, 3.5]
        """
        q = np.asarray(q, dtype=float)
        return np.where(self.limited, q, wrap_angle(q))

    def absolute_angles(self, q) -> np.ndarray:
        """Angle of every link measured from +x: the running sum of ``q``.

        Examples
        --------
        >>> Arm([1.0, 1.0]).absolute_angles([0.5, 0.25]).tolist()
        [0.5, 0.75]
        """
        q = self.check_q(q)
        return np.cumsum(q, axis=-1)

    def joint_positions(self, q) -> np.ndarray:
        """Positions of the base, every joint, and the end effector.

        Parameters
        ----------
        q : array_like, shape (..., n)

        Returns
        -------
        ndarray, shape (..., n + 1, 2)
            Base first (the origin), end effector last.

        Examples
        --------
        >>> Arm([1.0, 2.0]).joint_positions(np.zeros((5, 2))).shape
        (5, 3, 2)
        """
        return self.joint_positions_unchecked(self.check_q(q))

    def joint_positions_unchecked(self, q: np.ndarray) -> np.ndarray:
        """:meth:`joint_positions` of a float array already checked (or known to be in range)."""
        phi = np.cumsum(q, axis=-1)
        steps = np.empty(phi.shape + (2,))
        np.multiply(np.cos(phi), self._lengths, out=steps[..., 0])
        np.multiply(np.sin(phi), self._lengths, out=steps[..., 1])
        out = np.zeros(phi.shape[:-1] + (self.n + 1, 2))
        np.cumsum(steps, axis=-2, out=out[..., 1:, :])
        return out

    def to_world(self, xy) -> np.ndarray:
        """Points ``(..., 2)`` of the arm's base frame in world coordinates (see ``base``).

        Examples
        --------
        >>> Arm([1.0], base=(2.0, 1.0, np.pi / 2)).to_world([1.0, 0.0]).round(12).tolist()
        [2.0, 2.0]
        """
        x, y, heading = self.base
        p = np.asarray(xy, dtype=float)
        c, s = np.cos(heading), np.sin(heading)
        return np.stack((x + c * p[..., 0] - s * p[..., 1], y + s * p[..., 0] + c * p[..., 1]),
                        axis=-1)

    def from_world(self, xy) -> np.ndarray:
        """World points ``(..., 2)`` in the arm's base frame: :meth:`to_world` undone.

        Examples
        --------
        >>> arm = Arm([1.0], base=(2.0, 1.0, np.pi / 2))
        >>> arm.from_world(arm.to_world([0.3, -0.4])).round(12).tolist()
        [0.3, -0.4]
        """
        x, y, heading = self.base
        p = np.asarray(xy, dtype=float)
        dx, dy = p[..., 0] - x, p[..., 1] - y
        c, s = np.cos(heading), np.sin(heading)
        return np.stack((c * dx + s * dy, -s * dx + c * dy), axis=-1)

    def world_positions(self, q) -> np.ndarray:
        """:meth:`joint_positions` placed in the world by ``base``: shape ``(..., n + 1, 2)``.

        Examples
        --------
        >>> Arm([1.0, 1.0], base=(0.5, 0.0, np.pi)).world_positions([0.0, 0.0]).round(12).tolist()
        [[0.5, 0.0], [-0.5, 0.0], [-1.5, 0.0]]
        """
        return self.to_world(self.joint_positions(q))

    def to_encoder(self, q) -> np.ndarray:
        """Joint angles ``(..., n)`` as the encoders read them: ``q - joint_offsets``.

        Examples
        --------
        >>> Arm([1.0, 1.0], joint_offsets=[0.5, 0.0]).to_encoder([1.0, 1.0]).tolist()
        [0.5, 1.0]
        """
        return np.asarray(q, dtype=float) - np.asarray(self.joint_offsets)

    def from_encoder(self, readings) -> np.ndarray:
        """Encoder readings ``(..., n)`` as the model's joint angles: ``readings + joint_offsets``.

        Examples
        --------
        >>> Arm([1.0, 1.0], joint_offsets=[0.5, 0.0]).from_encoder([0.5, 1.0]).tolist()
        [1.0, 1.0]
        """
        return np.asarray(readings, dtype=float) + np.asarray(self.joint_offsets)

    def end_effector(self, q) -> np.ndarray:
        """End-effector position ``x = f(q)`` of DD1, shape ``(..., 2)``.

        Examples
        --------
        >>> Arm([1.0, 2.0]).end_effector([[0.0, 0.0], [np.pi, 0.0]]).round(12).tolist()
        [[3.0, 0.0], [-3.0, 0.0]]
        """
        return self.joint_positions(q)[..., -1, :]

    def within_limits(self, q, tol: float = 0.0) -> np.ndarray:
        """True where every limited joint lies in ``[lo - tol, hi + tol]``.

        Examples
        --------
        >>> Arm([1.0, 1.0], [None, (-1.0, 1.0)]).within_limits([[3.0, 0.5], [0.0, 1.5]]).tolist()
        [True, False]
        """
        q = self.check_q(q)
        lim = self.limited
        ok = (q >= self.lower - tol) & (q <= self.upper + tol)
        return np.all(ok | ~lim, axis=-1)


def _set_frame(arm: Arm, n: int, joint_names, base, joint_offsets) -> None:
    """Check and set an arm's ``joint_names``, ``base`` and ``joint_offsets`` (ValueErrors name them)."""
    if joint_names is None:
        names = tuple(f"joint{i + 1}" for i in range(n))
    else:
        if isinstance(joint_names, str):
            raise ValueError(f"joint_names must be a list of {n} names, got {joint_names!r}")
        names = tuple(joint_names)
        if len(names) != n or not all(isinstance(s, str) and s for s in names):
            raise ValueError(f"joint_names must be {n} non-empty strings, got {list(names)!r}")
        if len(set(names)) != n:
            raise ValueError(f"joint_names must be distinct, got {list(names)!r}")
    try:
        pose = tuple(float(v) for v in base)
    except (TypeError, ValueError):
        raise ValueError(f"base must be (x, y, heading), got {base!r}") from None
    if len(pose) != 3 or not all(np.isfinite(pose)) or max(abs(pose[0]), abs(pose[1])) > MAX_COORDINATE \
            or abs(pose[2]) > MAX_ANGLE:
        raise ValueError(f"base must be finite (x, y, heading), got {base!r}")
    try:
        offsets = (0.0,) * n if joint_offsets is None else tuple(float(v) for v in joint_offsets)
    except (TypeError, ValueError):
        raise ValueError(f"joint_offsets must be {n} angles, got {joint_offsets!r}") from None
    if len(offsets) != n or not all(np.isfinite(offsets)) or max(map(abs, offsets)) > MAX_ANGLE:
        raise ValueError(f"joint_offsets must be {n} finite angles, got {joint_offsets!r}")
    object.__setattr__(arm, "joint_names", names)
    object.__setattr__(arm, "base", pose)
    object.__setattr__(arm, "joint_offsets", offsets)
