"""Case studies: what belongs to one source document, built on the core.

* :mod:`rapp.cases.via_point_detour` -- seed 002: a via point that steers a
  cubic trajectory (and a 2-link arm) around a disc;
* :mod:`rapp.cases.rrt_report` -- seed 003: the 3-link RRT report's angle
  conventions, its printed Jacobian, its set-up and its alpha/beta experiment;
* :mod:`rapp.cases.two_dof_workspace` -- seed 004: the 2-link workspace and a
  motion through every IK solution.

Each has a figures module beside it that only draws what the chapter computes
(:mod:`rapp.cases.via_point_figures`, :mod:`rapp.cases.rrt_report_figures`,
:mod:`rapp.cases.two_dof_figures`): chapters 11-13 call them instead of hiding
plotting code in their cells.

They call the core (:func:`rapp.ik_2link`, :func:`rapp.trajectory.cubic_local`,
:attr:`rapp.Arm.reach`, :func:`rapp.rrt`) and keep no copy of its maths.
Import them by path: ``from rapp.cases import via_point_detour``.
"""

__all__ = ["via_point_detour", "rrt_report", "two_dof_workspace",
           "via_point_figures", "rrt_report_figures", "two_dof_figures"]
