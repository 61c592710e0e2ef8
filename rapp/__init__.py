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
from rapp.collision import (
    clearance,
    closest_point_on_segment,
    collides,
    line_distance_mis,
    path_collision_free,
    segment_circle_distance,
    segment_collision_free,
    segment_hits_circle,
    segment_hits_polygon,
    segment_polygon_distance,
)
# -- cspace --
from rapp.cspace import JointGrid, grid_q, occupancy
# -- search --
from rapp.search import (
    HeuristicCheck,
    SearchResult,
    astar,
    astar_search,
    bfs,
    bfs_distances,
    check_heuristic,
    greedy_best_first,
    toroidal_manhattan,
)
# -- ik --
from rapp.ik import ik, ik_2link, ik_numeric, jacobian
# -- symbolic --
# rapp.symbolic is imported on demand (`from rapp import symbolic`): sympy takes ~2 s to load.
# -- trajectory --
from rapp.trajectory import (
    PiecewisePolynomial,
    cubic,
    polyval,
    quintic,
    time_path,
    via_points,
)
# -- scenario --
from rapp.scenario import Scenario, echo, list_scenarios, load_scenario
# -- planner --
from rapp.planner import PLANNERS, GridTooCoarse, Plan, load_result, plan, save_result
# -- verify --
from rapp.verify import Check, Report, verify
# -- rrt --
from rapp.rrt import RRTResult, alpha_beta_experiment, plan_rrt, rrt
# -- viapoint --
from rapp.viapoint import (
    ViaPoint,
    first_arm_collision,
    path_clearance,
    search_via_point,
    spline_vs_cubic,
    tangent_via_point,
)
# -- workspace --
from rapp.workspace import (
    elbow_solutions,
    motion_through_solutions,
    reachable,
    workspace_radii,
)

__version__ = "0.1.0"
