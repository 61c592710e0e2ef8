"""A probabilistic roadmap built once, its edges certified, and queried many times.

:class:`Roadmap` samples free configurations and joins each to its nearest by candidate
edges, as :func:`rapp.prm.prm` does, and keeps them. Built for many queries, it certifies all its
edges at the build, in one call (each certified free or refuted), so that a query does not: a
query joins its start and goals to their nearest roadmap nodes, searches (A*) and certifies only
the edges of the path it found that join its own ends (:class:`rapp.prm.CandidateEdges`). A
query whose start and goals the roadmap does not join grows it by ``samples`` more free
configurations (up to ``max_samples``), certified alike. A query's own nodes and edges are
forgotten after it. (A roadmap loaded from a file that holds unchecked edges certifies them
when a query's path needs them, as the lazy PRM does.)

:meth:`Roadmap.save` writes a plain numpy archive (``.npz``, tagged with :data:`FORMAT` and
:data:`VERSION`) and :meth:`Roadmap.load` reads it back: the same arm, obstacles, nodes, edges,
what is known of them, and the random stream that grows the roadmap, so that the loaded roadmap
answers every later query as the saved one would.

References
----------
Kavraki, Švestka, Latombe and Overmars (1996), Probabilistic roadmaps for path planning in
high-dimensional configuration spaces. Bohlin and Kavraki (2000), Path planning using lazy PRM.
"""

from __future__ import annotations

import dataclasses
import json
import os
import zipfile
from typing import Iterable

import numpy as np
from numpy.typing import ArrayLike  # noqa: F401

from rapp.arm import Arm
from rapp.checks import positive_integer
from rapp.collision import scene
from rapp.errors import FileNotFound, InvalidFormat, InvalidSetting, NoPathFound
from rapp.files import atomic_output
from rapp.obstacles import Circle, Polygon
from rapp.paths import NODE_CAP, TIME_BUDGET_SPENT, PlannerResult, tree_result
from rapp.prm import (MEMORY_BUDGET, SEARCHES, CandidateEdges, OutOfTime, grow_roadmap, path_of,
                      roadmap_bytes)
from rapp.sampling import Budget, check_start_and_goals
from rapp.validity import DEFAULT_RESOLUTION, mark_sampled, user_validity

__all__ = ["Roadmap", "FORMAT", "VERSION"]

#: The archive's ``format`` entry: what the file is.
FORMAT = "rapp.Roadmap"
#: The archive's ``version`` entry: the layout :meth:`Roadmap.load` reads.
VERSION = 1
_ARRAYS = ("nodes", "ij", "w", "done")
#: What reading a damaged archive raises.
_UNREADABLE = (OSError, ValueError, EOFError, zipfile.BadZipFile)
_ARM_FIELDS = ("link_lengths", "joint_limits", "link_radius", "self_collision", "joint_names",
               "base", "joint_offsets")


class Roadmap:
    """A probabilistic roadmap of ``arm`` among ``obstacles``, for many queries.

    Parameters
    ----------
    arm, obstacles
        As :func:`rapp.prm.prm`.
    samples : int
        Free configurations the roadmap is built with, and added each time a query finds its
        ends not joined; their edges are certified when they are added.
    neighbours : int
        Candidate edges from each node to its nearest nodes.
    seed : int
        Seed of the samples.
    max_samples : int, optional
        Largest roadmap (default ``20 * samples``).
    margin : float
        Safety margin (metres, >= 0) every link keeps beyond its radius.
    validity, validity_resolution
        A user's checker and its sampling step, as :func:`rapp.prm.prm`: samples it rejects
        are not added, every edge is also sampled by it (numpy loop), and a query's result
        says its path was sampled. Such a roadmap cannot be saved (the checker is code).

    Examples
    --------
    >>> from rapp import Arm, Circle
    >>> arm = Arm([1.0, 1.0])
    >>> roadmap = Roadmap(arm, [Circle((0.0, 1.2), 0.3)], samples=200, seed=1)
    >>> a = roadmap.query([0.0, 0.0], [2.5, 0.0])
    >>> b = roadmap.query([2.5, 0.0], [-1.0, 0.5])
    >>> a.success, b.success, len(roadmap.nodes)
    (True, True, 200)
    """

    #: The file the roadmap was loaded from (:meth:`load`), never written over; None if built.
    source: str | None = None

    def __init__(self, arm: Arm, obstacles: Iterable[Circle | Polygon] = (), *,
                 samples: int = 500, neighbours: int = 10, seed: int = 0,
                 max_samples: int | None = None, margin: float = 0.0, validity=None,
                 validity_resolution: float = DEFAULT_RESOLUTION) -> None:
        self.checker = user_validity(validity, validity_resolution)
        self._setup(arm, list(obstacles), margin, samples, neighbours, max_samples)
        self.rng = np.random.default_rng(seed)
        self.nodes = np.empty((0, arm.n))
        self._grow()

    def _setup(self, arm, obstacles, margin, samples, neighbours, max_samples):
        if not isinstance(arm, Arm):
            raise InvalidSetting(f"arm must be a rapp.Arm, got {type(arm).__name__}", "arm")
        self.arm, self.obstacles, self.margin = arm, obstacles, float(margin)
        self._arm0, self._pieces = scene(arm, obstacles, margin)
        self._pieces = list(self._pieces)
        self.samples = positive_integer(samples, "samples")
        self.neighbours = positive_integer(neighbours, "neighbours")
        self.max_samples = (20 * self.samples if max_samples is None
                            else positive_integer(max_samples, "max_samples"))
        peak = roadmap_bytes(arm.n, self.max_samples + 2, self.neighbours)
        if peak > MEMORY_BUDGET:
            raise InvalidSetting(
                f"a roadmap of up to {self.max_samples} nodes with {self.neighbours} neighbours "
                f"each would need about {peak / 1e9:.3g} GB, over the {MEMORY_BUDGET / 1e9:g} GB "
                "budget: lower samples, max_samples or neighbours", "max_samples")
        self.edges = CandidateEdges(self._arm0, self._pieces, self.neighbours, fallback=True,
                                    checker=self.checker)

    @property
    def certified(self) -> int:
        """How many of the roadmap's edges are certified free."""
        return int(self.edges.state()[2].sum())

    def _grow(self, budget=None) -> None:
        """``samples`` more free nodes and their candidate edges (all or nothing)."""
        nodes = grow_roadmap(self._arm0, self.rng, self.nodes, self.samples, self._pieces, budget,
                             self.checker)
        m = self.edges.count
        try:
            self.edges.add(nodes, len(self.nodes), budget)
            # Built for many queries, the roadmap certifies its edges now, all in one call:
            # a query then certifies only the edges joining its own ends.
            self.edges.certify_all(nodes, budget)
        except OutOfTime:
            self.edges.keep(len(self.nodes), m)
            raise
        self.nodes = nodes

    def query(self, start: ArrayLike, goal: ArrayLike, *, max_iterations: int = 500,
              time_budget: float | None = None, raise_on_failure: bool = True) -> PlannerResult:
        """A certified path from ``start`` to a goal through the roadmap (as :func:`rapp.prm`).

        The result's ``nodes`` are the roadmap's, then the start, then the goals; ``parent``
        the last search's tree; ``iterations`` the searches this query ran.
        """
        budget = Budget(max_iterations, time_budget)
        start, goals = check_start_and_goals(self._arm0, start, goal, self._pieces, self.checker)
        ends = self._arm0.wrap(np.vstack((start, goals)))
        nodes, parent, status = self.nodes, np.full(len(self.nodes), -1), None
        try:
            while status is None:
                path, nodes, parent, status = self._search(start, ends, budget)
                if path is not None:
                    return mark_sampled(tree_result(self.arm, path, nodes, parent,
                                                    budget.iterations), self.checker)
                if status is None and len(self.nodes) >= self.max_samples:
                    budget.iterations += 1  # this search was counted before the roadmap was full
                    status = NODE_CAP
                elif status is None:
                    self._grow(budget)
        except OutOfTime:
            status = TIME_BUDGET_SPENT
        outcome = f"the roadmap of {len(self.nodes)} nodes joined no goal"
        if status == NODE_CAP:
            msg = (f"Roadmap query stopped: the roadmap reached max_samples {self.max_samples} "
                   f"after {budget.iterations} searches, {outcome}")
        elif status == TIME_BUDGET_SPENT:
            msg = (f"Roadmap query stopped: time_budget {budget.time_budget:g} s spent after "
                   f"{budget.iterations} searches, {outcome}")
        else:
            msg = budget.stopped("Roadmap query", outcome, unit="searches")
        if raise_on_failure:
            raise NoPathFound(msg)
        return mark_sampled(tree_result(self.arm, None, nodes, parent, budget.iterations, status),
                            self.checker)

    def _search(self, start, ends, budget):
        """Searches with the query's ends joined: ``(path, nodes, parent, status)``; ``path``
        None and ``status`` None when the roadmap joins no goal (grow it)."""
        base, m = len(self.nodes), self.edges.count
        nodes = np.vstack((self.nodes, ends))
        parent = np.full(len(nodes), -1)
        try:
            self.edges.add(nodes, base, budget)
            while True:
                rounds = budget.grant(SEARCHES)
                if not rounds:
                    return None, nodes, parent, budget.status()
                parent, hit, used, found = self.edges.search(
                    nodes, rounds, [base], np.arange(base + 1, len(nodes)), budget)
                budget.iterations += used
                if found:
                    return path_of(self._arm0, nodes, parent, hit, start), nodes, parent, None
                if hit < 0:
                    return None, nodes, parent, None
        finally:
            self.edges.keep(base, m)  # the query's own nodes and edges go

    def save(self, path) -> None:
        """Write the roadmap to ``path`` as a numpy archive (atomically; never over the file
        it was loaded from)."""
        path = os.fspath(path)
        if self.checker is not None:
            raise InvalidSetting("a roadmap built with a validity checker cannot be saved (the "
                                 "checker is Python code)", "validity")
        source = self.source
        if source is not None and os.path.exists(path) and os.path.samefile(path, source):
            raise InvalidSetting(f"{path} is the file this roadmap was loaded from: save it "
                                 "under another name", "path")
        ij, w, done = self.edges.state()
        meta = {"arm": {k: getattr(self.arm, k) for k in _ARM_FIELDS},
                "obstacles": [_obstacle_dict(o) for o in self.obstacles], "margin": self.margin,
                "samples": self.samples, "neighbours": self.neighbours,
                "max_samples": self.max_samples, "rng": self.rng.bit_generator.state}
        with atomic_output(path, suffix=".npz") as tmp, open(tmp, "wb") as f:
            np.savez(f, format=np.array(FORMAT), version=np.array(VERSION),
                     meta=np.array(json.dumps(meta, default=_plain)), nodes=self.nodes, ij=ij,
                     w=w, done=done)

    @classmethod
    def load(cls, path) -> "Roadmap":
        """The roadmap :meth:`save` wrote to ``path``; a file that is not one (or of another
        version) raises :class:`rapp.errors.InvalidFormat` naming the field."""
        path = os.fspath(path)
        try:
            archive = np.load(path, allow_pickle=False)
        except FileNotFoundError:
            raise FileNotFound(f"no roadmap file {path}", "path") from None
        except _UNREADABLE as e:
            raise InvalidFormat(f"{path} is not a numpy archive ({e})", "path") from None
        with archive:
            fields = _read_fields(archive, path)
        return cls._from(fields, path)

    @classmethod
    def _from(cls, fields, path) -> "Roadmap":
        meta = fields["meta"]
        self = cls.__new__(cls)
        self.checker = None
        try:
            arm = Arm(**meta["arm"])
            obstacles = [_obstacle(o) for o in meta["obstacles"]]
            self._setup(arm, obstacles, meta["margin"], meta["samples"], meta["neighbours"],
                        meta["max_samples"])
            self.rng = np.random.default_rng()
            self.rng.bit_generator.state = meta["rng"]
        except (KeyError, TypeError, ValueError) as e:
            raise InvalidFormat(f"{path}: the roadmap's settings are not readable ({e})",
                                "meta") from None
        nodes, ij, w, done = (fields[k] for k in _ARRAYS)
        n = arm.n
        if nodes.ndim != 2 or nodes.shape[1] != n or not np.isfinite(nodes).all():
            raise InvalidFormat(f"{path}: nodes must be finite, ({len(nodes)}, {n})", "nodes")
        m = len(w)
        if ij.shape != (m, 2) or ij.dtype.kind not in "iu" or (m and (
                ij.min() < 0 or ij.max() >= len(nodes) or (ij[:, 0] >= ij[:, 1]).any())):
            raise InvalidFormat(f"{path}: ij must be ({m}, 2) node pairs i < j", "ij")
        if w.ndim != 1 or np.isnan(w).any() or (w < 0).any():
            raise InvalidFormat(f"{path}: w must be edge lengths >= 0", "w")
        if done.shape != (m,) or done.dtype != bool:
            raise InvalidFormat(f"{path}: done must be ({m},) booleans", "done")
        self.nodes = nodes.astype(float)
        self.edges.restore(ij, w, done, len(nodes))
        self.source = path
        return self


def _read_fields(archive, path) -> dict:
    """The archive's entries, checked for presence, format and version."""
    fields = {}
    for key in ("format", "version", "meta") + _ARRAYS:
        if key not in archive.files:
            raise InvalidFormat(f"{path} has no {key!r} entry: not a saved rapp.Roadmap", key)
        try:
            fields[key] = archive[key]
        except _UNREADABLE as e:
            raise InvalidFormat(f"{path}: entry {key!r} is unreadable ({e})", key) from None
    if str(fields["format"]) != FORMAT:
        raise InvalidFormat(f"{path} is a {str(fields['format'])!r} file, not a {FORMAT}",
                            "format")
    if fields["version"].shape != () or int(fields["version"]) != VERSION:
        raise InvalidFormat(f"{path} is a roadmap of version {fields['version']}; this rapp "
                            f"reads version {VERSION}", "version")
    try:
        fields["meta"] = json.loads(str(fields["meta"]))
    except ValueError as e:
        raise InvalidFormat(f"{path}: meta is not JSON ({e})", "meta") from None
    if not isinstance(fields["meta"], dict):
        raise InvalidFormat(f"{path}: meta is not a JSON object", "meta")
    return fields


def _plain(x):
    """JSON for numpy numbers and arrays (the random stream's state holds them)."""
    if isinstance(x, np.ndarray):
        return x.tolist()
    if isinstance(x, np.generic):
        return x.item()
    raise TypeError(f"not JSON: {type(x).__name__}")


def _obstacle_dict(o) -> dict:
    return {"type": type(o).__name__,
            **{f.name: getattr(o, f.name) for f in dataclasses.fields(o) if f.init}}


def _obstacle(d: dict):
    kinds = {"Circle": Circle, "Polygon": Polygon}
    d = dict(d)
    return kinds[d.pop("type")](**d)
