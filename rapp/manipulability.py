"""How well the arm can move its tip: manipulability, condition number, velocity ellipse.

The end-effector velocity is ``xdot = J(q) qdot`` with ``J`` the 2 x n
Jacobian of :func:`rapp.ik.jacobian`. The joint velocities of unit norm,
``|qdot| <= 1``, map to an ellipse of tip velocities whose semi-axes are the
singular values ``sigma1 >= sigma2`` of ``J``, along its left singular vectors.
From them:

* :func:`manipulability` -- Yoshikawa's measure ``w = sqrt(det(J J^T)) =
  sigma1 sigma2``, proportional to the ellipse's area; zero at a singular
  configuration (stretched or folded arm), where the tip cannot move in some
  direction. For a 2-link arm ``w = L1 L2 |sin q2|``
  (:func:`rapp.symbolic.manipulability_symbolic` derives it).
* :func:`condition_number` -- ``sigma1 / sigma2 >= 1``, the ellipse's
  elongation: 1 for a round (isotropic) ellipse, ``inf`` at a singularity.
* :func:`manipulability_ellipse` -- the semi-axes and the direction of the
  major axis, to draw the ellipse.

``J J^T`` is only 2 x 2, so everything is in closed form over the whole batch
of configurations; there is no SVD and no loop over configurations.
"""

from __future__ import annotations

import numpy as np
from typing import TYPE_CHECKING, Iterable, Sequence  # noqa: F401  (annotations)

from numpy.typing import ArrayLike  # noqa: F401

from rapp.arm import Arm
from rapp.ik import jacobian

__all__ = ["manipulability", "condition_number", "manipulability_ellipse"]


def _scaled_jacobian(arm, q):
    """``J / s`` and the scale ``s`` (...,): the largest entry of each ``J``, so ``|J / s| <= 1``.

    ``det(J J^T)`` is a fourth power of lengths: for the longest arms
    :class:`rapp.Arm` accepts (up to ``MAX_COORDINATE`` = 1e100) it would
    overflow float64, for very short ones underflow. Working on ``J / s`` and
    putting ``s`` back afterwards avoids both. ``s > 0`` always: the last
    column of ``J`` has length ``L_n > 0``.
    """
    if not isinstance(arm, Arm):
        raise ValueError(f"arm must be a rapp.Arm, got {type(arm).__name__}")
    # jacobian -> Arm.absolute_angles -> Arm.check_q refuses a bad q, naming "q".
    jac = jacobian(arm, q)
    scale = np.abs(jac).max(axis=(-2, -1))
    return jac / scale[..., None, None], scale


def _unit_manipulability(js: np.ndarray) -> np.ndarray:
    """``sqrt(det(Js Js^T))`` of scaled Jacobians ``Js`` (..., 2, n), entries at most 1.

    Cauchy-Binet: ``det(J J^T) = a c - b^2`` (``a``, ``c`` the squared row
    norms, ``b`` their dot product) equals the sum of the squared 2 x 2 minors
    ``m_ij = Jx_i Jy_j - Jx_j Jy_i`` over the column pairs ``i < j``. The sum of
    squares is never negative and is accurate to round-off in ``w`` itself,
    whereas ``a c - b^2`` cancels to round-off in ``w**2`` next to a
    singularity, which leaves an error of about 1e-8 (``sqrt(eps)``) in ``w``.
    The minors are then normalised by their largest one so that squaring a
    tiny minor cannot underflow to zero (``w`` would read exactly singular).
    """
    jx, jy = js[..., 0, :], js[..., 1, :]
    minors = jx[..., :, None] * jy[..., None, :] - jx[..., None, :] * jy[..., :, None]
    if minors.shape[-1] < 2:
        # One link: J is 2 x 1, of rank one, so J J^T is always singular.
        return np.zeros(minors.shape[:-2])
    big = np.abs(minors).max(axis=(-2, -1))
    safe = np.where(big > 0, big, 1.0)[..., None, None]
    # The full n x n matrix of minors is antisymmetric: every pair i < j twice.
    return big * np.sqrt(0.5 * ((minors / safe) ** 2).sum(axis=(-2, -1)))


def _singular_values(js: np.ndarray):
    """``(sigma1, sigma2)`` of scaled Jacobians ``Js`` (..., 2, n), ``sigma1 >= sigma2 >= 0``.

    With ``f = |Js|_F`` (``f**2 = sigma1**2 + sigma2**2``, the trace of
    ``Js Js^T``) and ``w = sigma1 sigma2``: ``sigma1 +- sigma2 =
    sqrt(f**2 +- 2 w)``. ``sigma2`` is then taken as ``w / sigma1`` rather
    than the half-difference, which cancels exactly when ``sigma2`` is small
    (the interesting case). ``sigma1 >= f / sqrt(2) > 0``, so the division is
    safe.
    """
    w = _unit_manipulability(js)
    f2 = (js * js).sum(axis=(-2, -1))
    # Round-off can make f2 - 2 w (= (sigma1 - sigma2)**2) slightly negative at a round ellipse.
    sigma1 = 0.5 * (np.sqrt(f2 + 2.0 * w) + np.sqrt(np.maximum(f2 - 2.0 * w, 0.0)))
    return sigma1, w / sigma1


def manipulability(arm: Arm, q: ArrayLike) -> np.ndarray:
    """Yoshikawa's manipulability ``w = sqrt(det(J J^T))`` for a batch of configurations.

    ``w = sigma1 sigma2``, the product of the singular values of the Jacobian
    ``J`` (:func:`rapp.ik.jacobian`): proportional to the area of the velocity
    ellipse. It is zero exactly at a singular configuration (the arm stretched
    or folded onto one line through the tip's radial direction), where the tip
    loses a direction of motion. Units: length squared per radian.

    Parameters
    ----------
    arm : Arm
    q : array_like, shape (..., n)
        Joint angles, radians.

    Returns
    -------
    ndarray, shape (...)
        ``w >= 0``; always 0 for a one-link arm (``J`` has rank one).

    Raises
    ------
    ValueError
        Naming ``arm`` (not a :class:`rapp.Arm`) or ``q`` (wrong shape,
        non-finite or oversized angles).

    Examples
    --------
    For two links ``w = L1 L2 |sin q2|``: largest with the elbow at a right
    angle, zero stretched.

    >>> arm = Arm([1.0, 0.5])
    >>> manipulability(arm, [[0.3, np.pi / 2], [0.3, 0.0]]).round(12).tolist()
    [0.5, 0.0]
    >>> manipulability(Arm([1.0, 1.0, 1.0]), np.zeros((3, 4, 3))).shape
    (3, 4)
    """
    js, scale = _scaled_jacobian(arm, q)
    return _unit_manipulability(js) * scale**2


def condition_number(arm: Arm, q: ArrayLike) -> np.ndarray:
    """Condition number ``sigma1 / sigma2`` of the Jacobian for a batch of configurations.

    How elongated the velocity ellipse is: 1 when the tip moves equally
    easily in every direction (isotropic), growing without bound towards a
    singularity, ``inf`` at one. Unlike :func:`manipulability` it has no
    units, so it compares arms of different sizes.

    Parameters
    ----------
    arm : Arm
    q : array_like, shape (..., n)

    Returns
    -------
    ndarray, shape (...)
        ``>= 1`` (up to round-off); ``inf`` where ``sigma2 == 0``, and always
        for a one-link arm.

    Raises
    ------
    ValueError
        Naming ``arm`` or ``q``, as :func:`manipulability`.

    Examples
    --------
    A 2-link arm with ``L1 = sqrt(2) L2`` and the elbow at 135 degrees is
    isotropic; stretched it is singular.

    >>> arm = Arm([np.sqrt(2.0), 1.0])
    >>> condition_number(arm, [[0.0, 3 * np.pi / 4], [0.0, 0.0]]).round(9).tolist()
    [1.0, inf]
    """
    js, _ = _scaled_jacobian(arm, q)
    sigma1, sigma2 = _singular_values(js)
    # The scale cancels in the ratio. Singular (sigma2 == 0) is inf, without a divide warning.
    return np.divide(sigma1, sigma2, out=np.full_like(sigma1, np.inf), where=sigma2 > 0)


def manipulability_ellipse(arm: Arm, q: ArrayLike) -> tuple[np.ndarray, np.ndarray]:
    """Semi-axes and orientation of the velocity ellipse, for a batch of configurations.

    The tip velocities ``J qdot`` reachable with ``|qdot| <= 1`` fill an
    ellipse centred on the tip. Its semi-axes are the singular values of
    ``J``; its major axis points along the top left singular vector of ``J``,
    the eigenvector of ``J J^T = [[a, b], [b, c]]`` of the larger eigenvalue,
    at angle ``atan2(2 b, a - c) / 2``.

    Parameters
    ----------
    arm : Arm
    q : array_like, shape (..., n)

    Returns
    -------
    axes : ndarray, shape (..., 2)
        ``(sigma1, sigma2)``, ``sigma1 >= sigma2 >= 0``: the semi-major and
        semi-minor axis, length per radian. ``sigma1 * sigma2`` is
        :func:`manipulability`.
    angle : ndarray, shape (...)
        Direction of the major axis, radians from +x, in ``(-pi/2, pi/2]``
        (an axis has no sign). A round ellipse (``sigma1 == sigma2``) has no
        major axis; ``0`` is returned there.

    Raises
    ------
    ValueError
        Naming ``arm`` or ``q``, as :func:`manipulability`.

    Examples
    --------
    Stretched along +x the tip can only move sideways: a segment along +y.

    >>> axes, angle = manipulability_ellipse(Arm([1.0, 1.0]), [0.0, 0.0])
    >>> axes.round(6).tolist(), float(angle.round(6))
    ([2.236068, 0.0], 1.570796)
    >>> axes, angle = manipulability_ellipse(Arm([1.0, 1.0]), np.zeros((5, 2)))
    >>> axes.shape, angle.shape
    ((5, 2), (5,))
    """
    js, scale = _scaled_jacobian(arm, q)
    sigma1, sigma2 = _singular_values(js)
    jx, jy = js[..., 0, :], js[..., 1, :]
    a = (jx * jx).sum(axis=-1)
    b = (jx * jy).sum(axis=-1)
    c = (jy * jy).sum(axis=-1)
    # The double-angle form gives the principal axis of the larger eigenvalue;
    # atan2(0, 0) = 0 covers the round ellipse without a special case.
    angle = 0.5 * np.arctan2(2.0 * b, a - c)
    # atan2(-0.0, negative) is -pi: a vertical axis reads +pi/2 whatever the sign of zero.
    angle = np.where(angle <= -0.5 * np.pi, angle + np.pi, angle)
    axes = np.stack((sigma1, sigma2), axis=-1) * scale[..., None]
    return axes, angle
