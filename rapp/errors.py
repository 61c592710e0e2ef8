"""The exceptions of rapp, one hierarchy so that callers can catch ``RappError``.

The names follow the MIS of 2D-RAPP (seed 001): ``loadParams`` raises
FileNotFound, InvalidFormat, MissingParameter and InvalidValue; ``planPath``
raises NoPathFound; ``solveIK`` raises NoIKSolution.

Examples
--------
>>> from rapp.errors import InvalidValue, ScenarioError, RappError
>>> issubclass(InvalidValue, ScenarioError) and issubclass(ScenarioError, RappError)
True
>>> from rapp.errors import InvalidCell, CertificationLimit, NoPathFound
>>> issubclass(InvalidCell, (NoPathFound, ValueError)), issubclass(CertificationLimit, ValueError)
(True, True)
"""

from __future__ import annotations


class RappError(Exception):
    """Base class of every error rapp raises on purpose."""


class ScenarioError(RappError, ValueError):
    """A scenario could not be loaded; ``field`` names the offending entry.

    Parameters
    ----------
    message : str
        One line saying what is wrong.
    field : str, optional
        Dotted path of the offending field, e.g. ``"arm.link_lengths[1]"``.
    """

    def __init__(self, message: str, field: str | None = None) -> None:
        self.field = field
        self.message = message
        super().__init__(f"{field}: {message}" if field else message)


class FileNotFound(ScenarioError):
    """The scenario file does not exist or cannot be read."""


class InvalidFormat(ScenarioError):
    """The file is not a JSON object of the scenario format."""


class MissingParameter(ScenarioError):
    """A required field is absent."""


class InvalidValue(ScenarioError):
    """A field is present but its value breaks a physical constraint."""


class NoPathFound(RappError):
    """The search space holds no collision-free path from start to goal."""


class InvalidCell(RappError, ValueError):
    """A start or goal cell that is not a cell of the search grid (outside it, or malformed).

    A bad argument, hence a ValueError, and not a NoPathFound: "no path" is a planning answer
    about a grid, which a cell outside that grid cannot get.
    """


class InvalidSetting(RappError, ValueError):
    """A planner's setting with which it cannot run or cannot succeed; ``setting`` names it.

    The planners know their own parameters (``step``, ``samples``), not the scenario file:
    :func:`rapp.plan` reports this as an :class:`InvalidValue` of ``planner.<setting>``.

    Examples
    --------
    >>> e = InvalidSetting("step must be at least 1e-06 rad, got 1e-09", setting="step")
    >>> e.setting, str(e)
    ('step', 'step must be at least 1e-06 rad, got 1e-09')
    """

    def __init__(self, message: str, setting: str) -> None:
        self.setting = setting
        self.message = message
        super().__init__(message)


class CertificationLimit(RappError, ValueError):
    """A joint-space segment could not be certified within the bisection's work limit.

    :func:`rapp.collision.segment_collision_free` bisects a segment until its
    motion bound fits inside the clearance. When the arm is huge relative to
    its clearance the pieces must be tiny and their number explodes; past
    :data:`rapp.collision.MAX_PENDING_INTERVALS` pending pieces it stops with
    this error, whose message states the link scale and the clearance.
    """


class GridTooCoarse(NoPathFound):
    """The occupancy grid has a path, but its moves could not be certified collision-free.

    The grid marks cell *centres*; a move between two free centres can still
    sweep an obstacle. A finer grid (``planner.cells``) usually finds a path.
    """


class NoIKSolution(RappError):
    """No joint configuration places the end effector at the target.

    ``reason`` is ``"out of reach"``, ``"joint limits"`` or ``"did not converge"``.
    """

    def __init__(self, message: str, reason: str = "out of reach") -> None:
        self.reason = reason
        super().__init__(message)


class PathNotFollowable(RappError):
    """The end effector cannot follow the requested workspace path (:func:`rapp.cartesian.line_path`).

    The message is one line saying what goes wrong and where. ``reason`` is
    ``"workspace"``, ``"singularity"``, ``"joint limits"`` or ``"obstacle"``;
    ``s`` is the line parameter in ``[0, 1]`` at which it happens.
    """

    def __init__(self, message: str, reason: str | None = None, s: float | None = None) -> None:
        self.reason = reason
        self.s = s
        super().__init__(message)
