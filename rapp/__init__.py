"""rapp: 2D robot-arm path planning, the package behind the rapp book.

Examples
--------
>>> import rapp
>>> arm = rapp.Arm([1.0, 1.0])
>>> arm.end_effector([0.0, 0.0]).tolist()
[2.0, 0.0]
"""

from rapp.errors import (
    FileNotFound,
    InvalidFormat,
    InvalidValue,
    MissingParameter,
    NoIKSolution,
    NoPathFound,
    RappError,
    ScenarioError,
)
from rapp.arm import Arm, wrap_angle
from rapp.obstacles import Circle, Polygon

# Each module adds its public names below its own marker line; keep one import block per module.
# -- collision --
# -- cspace --
# -- search --
# -- ik --
# -- symbolic --
# -- trajectory --
# -- scenario --
# -- planner --
# -- verify --
# -- rrt --
# -- viapoint --

__version__ = "0.1.0"
