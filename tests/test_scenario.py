"""Scenario loading (R1, NFR5, MIS loadParams) and echo (R2): valid files round-trip,
every bad input is refused with the right error class and a field naming the culprit."""

import copy
import json
import math
import warnings

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings, strategies as st

from rapp import Circle, Polygon, collides
from rapp.errors import (FileNotFound, InvalidFormat, InvalidValue, MissingParameter,
                         ScenarioError)
from rapp.scenario import echo, list_scenarios, load_scenario, max_cells

BASE = {
    "arm": {"link_lengths": [1.0, 1.0], "joint_limits": None},
    "obstacles": [{"type": "circle", "center": [1.75, 0.75], "radius": 0.4},
                  {"type": "rectangle", "corner": [-1.5, -0.5], "width": 0.3, "height": 0.4,
                   "angle": 0.2},
                  {"type": "polygon", "vertices": [[0, -1.6], [0.4, -1.6], [0.2, -1.3]]}],
    "start": [0.0, 0.0],
    "goal": {"joints": [2.0, 0.5]},
    "planner": {"algorithm": "astar", "cells": 50},
    "trajectory": {"duration": 4.0, "profile": "cubic", "samples": 50},
}


def mutate(path, value):
    """BASE with the entry at ``path`` (a tuple of keys/indices) set, or deleted if value is DEL."""
    d = copy.deepcopy(BASE)
    node = d
    for k in path[:-1]:
        node = node[k]
    if value is DEL:
        del node[path[-1]]
    else:
        node[path[-1]] = value
    return d


class _Deleted:
    """The marker for "remove this key"; its repr is stable, so test ids match across workers."""

    def __repr__(self):
        return "DEL"


DEL = _Deleted()


def test_every_embedded_scenario_loads_and_round_trips():
    names = list_scenarios()
    assert {"default", "srs_typical", "three_link", "rectangles", "no_solution"} <= set(names)
    for name in names:
        s = load_scenario(name)
        again = load_scenario(s.to_dict())
        assert again == s
        assert json.loads(json.dumps(s.to_dict(), allow_nan=False)) == s.to_dict()


def test_srs_typical_documents_the_inconsistent_goal():
    s = load_scenario("srs_typical")
    # Table 2's typical goal (1.5, 1.5) lies outside the reach of two 1 m links ...
    assert math.hypot(1.5, 1.5) > s.arm.reach[1]
    with pytest.raises(InvalidValue) as e:
        load_scenario({**s.to_dict(), "goal": {"position": [1.5, 1.5]}})
    assert e.value.field == "goal.position"
    # ... so the file keeps the typical links and obstacle and says what it chose.
    assert s.arm.link_lengths == (1.0, 1.0)
    assert s.obstacles == (Circle((0.5, 0.5), 0.3),)
    assert "out of reach" in s.description and "2.12" in s.description


@settings(max_examples=60, deadline=None)
@given(st.lists(st.floats(-180, 180), min_size=2, max_size=2),
       st.lists(st.floats(-180, 180), min_size=2, max_size=2),
       st.floats(-360, 360))
def test_degrees_are_converted_everywhere(start, goal, angle):
    d = mutate(("start",), start)
    d["goal"] = {"joints": goal}
    d["obstacles"] = [{"type": "rectangle", "corner": [5, 5], "width": 1, "height": 2,
                       "angle": angle}]
    d["units"] = {"angle": "deg", "length": "m"}
    s = load_scenario(d)
    assert np.allclose(s.start, np.radians(start)) and np.allclose(s.goal_q, np.radians(goal))
    expected = Polygon.rectangle((5, 5), 1, 2, math.radians(angle))
    assert np.allclose(s.obstacles[0].array, expected.array)
    assert s == load_scenario(s.to_dict())  # canonical form is radians


def test_joint_limits_in_degrees_and_start_outside_them():
    d = mutate(("arm", "joint_limits"), [[-90, 90], None])
    d["units"] = {"angle": "deg"}
    d["start"], d["goal"] = [0, 0], {"joints": [45, 170]}
    s = load_scenario(d)
    assert s.arm.joint_limits[0] == pytest.approx((-math.pi / 2, math.pi / 2))
    d["start"] = [100, 0]
    with pytest.raises(InvalidValue) as e:
        load_scenario(d)
    assert e.value.field == "start[0]"


def test_rrt_stars_radius_null_is_the_step_and_a_number_is_checked():
    d = dict(BASE, planner={"algorithm": "rrt_star", "step": 0.2})
    s = load_scenario(d)
    assert s.planner.radius is None and "radius       the step" in echo(s)
    s = load_scenario(dict(d, planner={"algorithm": "rrt_star", "radius": 0.4}))
    assert s.planner.values()["radius"] == 0.4 and "radius       0.4 rad" in echo(s)
    assert load_scenario(s.to_dict()) == s
    with pytest.raises(InvalidValue) as info:
        load_scenario(dict(d, planner={"algorithm": "rrt_star", "radius": 0.0}))
    assert info.value.field == "planner.radius"


def test_echo_shows_every_input_with_units_and_the_warnings():
    d = mutate(("arm", "link_lengths"), [2.5, 1.0])
    d["obstacles"][0]["radius"] = 0.7
    d["obstacles"][0]["center"] = [3.0, 1.5]
    s = load_scenario(d)
    text = echo(s)
    for needle in ("2.5", "circle centre (3, 1.5) m, radius 0.7 m", "polygon", "start",
                   "goal (joints)", "[2, 0.5] rad", "astar", "50 x 50", "cubic, 4 s, 50 samples"):
        assert needle in text, needle
    assert len(s.warnings) == 2  # L = 2.5 m > L_max and r = 0.7 m > r_max (SRS Table 4)
    for w in s.warnings:
        assert f"warning: {w}" in text
    assert any("link_lengths[0]" in w for w in s.warnings)
    assert any("obstacles[0].radius" in w for w in s.warnings)


def test_typical_ranges_give_no_warnings():
    assert load_scenario(BASE).warnings == ()


BAD = [
    # (mutation path, value, error class, field)
    (("arm",), DEL, MissingParameter, "arm"),
    (("start",), DEL, MissingParameter, "start"),
    (("goal",), DEL, MissingParameter, "goal"),
    (("arm", "link_lengths"), DEL, MissingParameter, "arm.link_lengths"),
    (("arm", "link_length"), [1, 1], InvalidFormat, "arm.link_length"),  # typo: unknown key
    (("planer",), {}, InvalidFormat, "planer"),
    (("arm", "link_lengths"), "1, 1", InvalidFormat, "arm.link_lengths"),
    (("arm", "link_lengths"), [1, "1"], InvalidFormat, "arm.link_lengths[1]"),
    (("arm", "link_lengths"), [1, True], InvalidFormat, "arm.link_lengths[1]"),
    (("arm", "link_lengths"), [1, None], InvalidFormat, "arm.link_lengths[1]"),
    (("arm", "link_lengths"), [1, -1], InvalidValue, "arm.link_lengths[1]"),
    (("arm", "link_lengths"), [0, 1], InvalidValue, "arm.link_lengths[0]"),
    (("arm", "link_lengths"), [], InvalidValue, "arm.link_lengths"),
    (("arm", "link_lengths"), [1, float("nan")], InvalidValue, "arm.link_lengths[1]"),
    (("arm", "link_lengths"), [1, float("inf")], InvalidValue, "arm.link_lengths[1]"),
    (("arm", "joint_limits"), [[1, -1], None], InvalidValue, "arm.joint_limits[0]"),
    (("arm", "joint_limits"), [None], InvalidValue, "arm.joint_limits"),
    (("arm", "joint_limits"), [[0, 1, 2], None], InvalidValue, "arm.joint_limits[0]"),
    (("arm",), [1, 1], InvalidFormat, "arm"),
    (("obstacles",), {"type": "circle"}, InvalidFormat, "obstacles"),
    (("obstacles", 0, "radius"), 0, InvalidValue, "obstacles[0].radius"),
    (("obstacles", 0, "radius"), -0.3, InvalidValue, "obstacles[0].radius"),
    (("obstacles", 0, "radius"), DEL, MissingParameter, "obstacles[0].radius"),
    (("obstacles", 0, "radius"), "big", InvalidFormat, "obstacles[0].radius"),
    (("obstacles", 0, "center"), [1, 2, 3], InvalidValue, "obstacles[0].center"),
    (("obstacles", 0, "type"), "ellipse", InvalidValue, "obstacles[0].type"),
    (("obstacles", 0, "type"), DEL, MissingParameter, "obstacles[0].type"),
    (("obstacles", 0, "radus"), 1, InvalidFormat, "obstacles[0].radus"),
    (("obstacles", 1, "width"), 0, InvalidValue, "obstacles[1].width"),
    (("obstacles", 1, "height"), -1, InvalidValue, "obstacles[1].height"),
    (("obstacles", 2, "vertices"), [[0, 0], [1, 1]], InvalidValue, "obstacles[2].vertices"),
    (("obstacles", 2, "vertices"), [[0, 0], [1, 1], [2, 2]], InvalidValue,
     "obstacles[2].vertices"),
    (("obstacles", 2, "vertices"), [[0, 0], [1, 0], [1, 1], [0.9, 0.2]], InvalidValue,
     "obstacles[2].vertices"),
    (("start",), [0.0], InvalidValue, "start"),
    (("start",), [0.0, 0.0, 0.0], InvalidValue, "start"),
    (("start",), {"q": [0, 0]}, InvalidFormat, "start"),
    (("goal",), {"joints": [0, 0], "position": [1, 1]}, InvalidFormat, "goal"),
    (("goal",), {}, MissingParameter, "goal"),
    (("goal",), {"joints": [0]}, InvalidValue, "goal.joints"),
    (("goal",), {"position": [3.0, 0.0]}, InvalidValue, "goal.position"),
    (("goal",), {"position": [1.0]}, InvalidValue, "goal.position"),
    (("units",), {"angle": "grad"}, InvalidValue, "units.angle"),
    (("units",), {"length": "ft"}, InvalidValue, "units.length"),
    (("planner", "algorithm"), "dijkstra", InvalidValue, "planner.algorithm"),
    (("planner", "cells"), 2, InvalidValue, "planner.cells"),
    (("planner", "cells"), 1.5, InvalidValue, "planner.cells"),
    (("planner", "cells"), [50], InvalidValue, "planner.cells"),
    (("planner", "cells"), [50, "50"], InvalidFormat, "planner.cells[1]"),
    (("planner", "cells"), 10**6, InvalidValue, "planner.cells"),
    (("planner", "cells"), [10**4, 10**4], InvalidValue, "planner.cells"),
    (("planner", "cells"), 10**400, InvalidValue, "planner.cells"),
    (("planner", "heuristic_weight"), 0.5, InvalidValue, "planner.heuristic_weight"),
    (("planner", "max_expansions"), 0, InvalidValue, "planner.max_expansions"),
    (("planner", "seed"), -1, InvalidValue, "planner.seed"),
    (("planner", "goal_bias"), 2, InvalidValue, "planner.goal_bias"),
    (("trajectory", "duration"), 0, InvalidValue, "trajectory.duration"),
    (("trajectory", "profile"), "linear", InvalidValue, "trajectory.profile"),
    (("trajectory", "samples"), 1, InvalidValue, "trajectory.samples"),
    (("trajectory", "samples"), 10**9, InvalidValue, "trajectory.samples"),
    (("name",), 5, InvalidFormat, "name"),
]


@pytest.mark.parametrize("path,value,cls,field", BAD,
                         ids=[f"{'.'.join(map(str, b[0]))}={b[1]!r}"[:60] for b in BAD])
def test_bad_input_names_the_field(path, value, cls, field):
    with pytest.raises(cls) as e:
        load_scenario(mutate(path, value))
    assert e.value.field == field
    assert "\n" not in str(e.value) and str(e.value).startswith(field)


def test_huge_grid_is_refused_before_any_allocation():
    with pytest.raises(InvalidValue) as e:
        load_scenario(mutate(("planner", "cells"), int(max_cells(2)**0.5) + 1))
    assert e.value.field == "planner.cells" and "GB" in str(e.value)


def test_collisions_and_reach_are_reported_before_any_work():
    d = mutate(("start",), [math.atan2(0.75, 1.75), 0.0])  # link 2 through the first disc
    with pytest.raises(InvalidValue) as e:
        load_scenario(d)
    assert e.value.field == "start" and "collides" in str(e.value)
    d = mutate(("goal",), {"joints": [math.atan2(0.75, 1.75), 0.0]})
    with pytest.raises(InvalidValue) as e:
        load_scenario(d)
    assert e.value.field == "goal.joints"
    assert load_scenario(d, check=False).goal_q is not None  # the check can be skipped
    d = mutate(("arm", "link_lengths"), [1.0, 0.4])  # annulus [0.6, 1.4]
    d["goal"] = {"position": [0.3, 0.2]}
    with pytest.raises(InvalidValue, match="annulus"):
        load_scenario(d, check=False)


def write(tmp_path, data, name="s.json"):
    p = tmp_path / name
    p.write_bytes(data if isinstance(data, bytes) else data.encode())
    return p


@pytest.mark.parametrize("text,cls", [
    ("", InvalidFormat),
    ("   \n", InvalidFormat),
    ("[1, 2]", InvalidFormat),
    ("null", InvalidFormat),
    ('{"arm": ', InvalidFormat),
    ("{'arm': 1}", InvalidFormat),
    (json.dumps(BASE).replace("4.0", "NaN"), InvalidValue),
    (json.dumps(BASE).replace("4.0", "Infinity"), InvalidValue),
    (json.dumps(BASE).replace("4.0", "-Infinity"), InvalidValue),
    (json.dumps(BASE).replace("4.0", "1e999"), InvalidValue),
    (json.dumps(BASE).replace("4.0", "9" * 5000), InvalidValue),   # named: trajectory.duration
    (json.dumps(BASE)[:-1] + ', "arm": {}}', InvalidFormat),  # duplicate key
])
def test_bad_files(tmp_path, text, cls):
    with pytest.raises(cls) as e:
        load_scenario(write(tmp_path, text))
    assert e.value.field and "\n" not in str(e.value)


def test_nan_token_names_its_field(tmp_path):
    text = json.dumps(BASE).replace('"radius": 0.4', '"radius": NaN')
    with pytest.raises(InvalidValue) as e:
        load_scenario(write(tmp_path, text))
    assert e.value.field == "obstacles[0].radius" and "NaN" in str(e.value)


def test_files_that_are_not_files(tmp_path):
    with pytest.raises(FileNotFound) as e:
        load_scenario(tmp_path / "missing.json")
    assert "no such file" in str(e.value)
    with pytest.raises(FileNotFound, match="directory"):
        load_scenario(tmp_path)
    with pytest.raises(InvalidFormat, match="UTF-8"):
        load_scenario(write(tmp_path, b'{"arm": "\xff\xfe"}'))
    with pytest.raises(InvalidFormat):
        load_scenario(42)


def test_absurd_nesting_is_an_error_not_a_crash(tmp_path):
    deep = "[" * 100_000 + "]" * 100_000
    with pytest.raises(InvalidFormat, match="nested"):
        load_scenario(write(tmp_path, deep))
    with pytest.raises(InvalidFormat) as e:
        load_scenario(write(tmp_path, json.dumps(BASE).replace("[0.0, 0.0]", deep, 1)))
    assert e.value.field == "scenario"
    nested = 0.0
    for _ in range(100_000):
        nested = [nested]
    with pytest.raises(InvalidFormat) as e:  # already parsed: validation never recurses
        load_scenario(mutate(("start",), [nested, 0.0]))
    assert e.value.field == "start[0]"


@settings(max_examples=80, deadline=None)
@given(st.data())
def test_every_truncation_of_a_valid_file_is_invalid_format(tmp_path_factory, data):
    text = json.dumps(BASE, indent=1)
    cut = data.draw(st.integers(0, len(text) - 1))
    path = tmp_path_factory.mktemp("t") / "s.json"
    path.write_text(text[:cut])
    with pytest.raises(InvalidFormat):
        load_scenario(path)


@settings(max_examples=100, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(st.binary(max_size=200))
def test_binary_garbage_is_a_scenario_error(tmp_path_factory, blob):
    path = tmp_path_factory.mktemp("b") / "s.json"
    path.write_bytes(blob)
    with pytest.raises(ScenarioError):
        load_scenario(path)


JSON = st.recursive(
    st.none() | st.booleans() | st.integers() | st.floats(allow_nan=True) | st.text(max_size=5),
    lambda kids: st.lists(kids, max_size=4) | st.dictionaries(st.text(max_size=8), kids,
                                                             max_size=4),
    max_leaves=20)


@settings(max_examples=150, deadline=None)
@given(st.sampled_from([(), ("arm",), ("arm", "link_lengths"), ("obstacles",), ("start",),
                        ("goal",), ("planner",), ("planner", "cells"), ("trajectory",),
                        ("obstacles", 0), ("units",)]), JSON)
def test_any_json_value_anywhere_loads_or_raises_a_scenario_error(path, value):
    d = value if path == () else mutate(path, value)
    try:
        s = load_scenario(d)
    except ScenarioError as e:
        assert e.field and "\n" not in str(e)
    else:
        assert load_scenario(s.to_dict()) == s


def test_a_long_wall_near_the_base_is_not_called_unreachable():
    # Every vertex of this wall is beyond the 2 m reach, but its edge passes 1.5 m from the base.
    wall = {"type": "rectangle", "corner": [-5, 1.5], "width": 10, "height": 0.2}
    far = {"type": "rectangle", "corner": [5, 5], "width": 1, "height": 1}
    s = load_scenario({"arm": {"link_lengths": [1, 1]}, "obstacles": [wall, far],
                       "start": [0, 0], "goal": {"joints": [0.1, 0]}})
    assert [w for w in s.warnings if "cannot collide" in w] == [
        "obstacles[1] lies beyond the arm's reach (2 m); it cannot collide"]
    assert collides(s.arm, [np.pi / 2, 0.0], s.obstacles[:1])


# ------------------------------------------------------------ physical ranges (issue: reliability)

@pytest.mark.parametrize("path,value,field", [
    (("trajectory", "duration"), 1e-300, "trajectory.duration"),
    (("trajectory", "duration"), 1e300, "trajectory.duration"),
    (("arm", "link_lengths"), [1e308, 1.0], "arm.link_lengths[0]"),
    (("arm", "link_lengths"), [1e20, 1.0], "arm.link_lengths[0]"),
    (("arm", "link_lengths"), [1e-9, 1.0], "arm.link_lengths[0]"),
    (("start",), [1e300, 0.0], "start[0]"),
    (("goal", "joints"), [0.0, -1e300], "goal.joints[1]"),
    (("obstacles", 1, "width"), 1e-17, "obstacles[1].width"),
    (("obstacles", 1, "corner"), [1e17, 0.0], "obstacles[1].corner[0]"),
    (("obstacles", 0, "radius"), 1e9, "obstacles[0].radius"),
    (("obstacles", 0, "center"), [0.0, -1e12], "obstacles[0].center[1]"),
    (("obstacles", 2, "vertices"), [[0, -1.6], [0.4, -1.6], [0.2, 1e30]], "obstacles[2].vertices[2][1]"),
    (("obstacles", 1, "angle"), 1e300, "obstacles[1].angle"),
    (("planner", "heuristic_weight"), 1e300, "planner.heuristic_weight"),
])
def test_extreme_but_finite_values_are_refused_naming_the_field(path, value, field):
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # and no RuntimeWarning on the way
        with pytest.raises(InvalidValue) as e:
            load_scenario(mutate(path, value))
    assert e.value.field == field, str(e.value)


@pytest.mark.parametrize("key,value", [("goal_threshold", 2.0), ("goal_threshold", 1e9),
                                       ("step", 7.0)])
def test_rrt_settings_have_physical_ranges(key, value):
    d = mutate(("planner",), {"algorithm": "rrt", key: value})
    with pytest.raises(InvalidValue) as e:
        load_scenario(d)
    assert e.value.field == f"planner.{key}"


def test_a_5000_digit_number_names_its_field(tmp_path):
    text = json.dumps(BASE).replace('"radius": 0.4', '"radius": ' + "7" * 5000)
    with pytest.raises(InvalidValue) as e:
        load_scenario(write(tmp_path, text))
    assert e.value.field == "obstacles[0].radius" and "5000 digits" in str(e.value)


@pytest.mark.parametrize("n", range(1, 17))
def test_the_defaults_are_accepted_for_every_number_of_links(n):
    # Before: 9-16 links were refused with "planner.cells: a grid of 1.34e+08 cells ...",
    # a key the user never wrote.
    s = load_scenario({"arm": {"link_lengths": [2.0 / n] * n}, "start": [0.0] * n,
                       "goal": {"joints": [1.0] + [0.0] * (n - 1)}})
    if s.planner.algorithm == "astar":
        assert math.prod(s.planner.cells) <= max_cells(n)
    else:
        assert n > 6 and any("default" in w for w in s.warnings)
        assert "rrt, the default" in echo(s)


def test_the_grid_limit_follows_the_memory_model():
    from rapp import scenario as sc
    for n in range(1, 9):
        assert max_cells(n) * sc.bytes_per_cell(n) <= sc.MEMORY_BUDGET < 2e9
    # The model is above every measurement of benchmarks/bench_memory.py.
    from rapp import recorded
    rec = recorded.load("memory")
    for case in rec["cases"]:
        assert sc.bytes_per_cell(case["joints"]) >= case["bytes_per_cell"], case
        assert case["peak_mb"] < 2000
