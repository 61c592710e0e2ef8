"""JSON Schemas (draft 2020-12) of the scenario and result files, built from the loader's limits.

Other tools (an editor, a CI step, a service in another language) can validate a rapp file
without rapp. The schemas are *built* from the same definitions the loader reads: the key
lists and ranges of :mod:`rapp.scenario` (``MAX_LINKS``, ``MIN_LENGTH`` ... ``MAX_DURATION``,
``PROFILES``) and the planner table (:data:`rapp.planners.PLANNERS`: every setting's kind,
range, default and whether ``null`` is allowed), so a new planner setting appears in the
schema by itself. The package ships them as ``rapp/schemas/scenario.schema.json`` and
``result.schema.json`` (a test holds the files equal to :func:`scenario_schema` and
:func:`result_schema`); ``python -m rapp schema scenario|result`` prints them.

A schema checks the shape of a file: keys, types, counts and the ranges that hold in every
unit. What depends on several values at once (an angle's range once its unit is known, a
goal within reach, a start outside every obstacle, memory budgets) is the loader's to say
(:func:`rapp.load_scenario`): a file the loader accepts always validates; a file that
validates may still be refused by the loader, with one line naming the field.

Examples
--------
>>> s = scenario_schema()
>>> s["$schema"], s["required"]
('https://json-schema.org/draft/2020-12/schema', ['arm', 'start', 'goal'])
>>> sorted(s["properties"]["planner"]["properties"]["algorithm"]["enum"])
['astar', 'prm', 'rrt', 'rrt_connect', 'rrt_star']
"""

from __future__ import annotations

import json
import math
from importlib import resources
from typing import Any

from rapp import planners as planner_table
from rapp import scenario as sc
from rapp.results import RESULT_FORMAT, RESULT_VERSION

__all__ = ["DRAFT", "SCHEMAS", "scenario_schema", "result_schema", "schema", "schema_text",
           "shipped_schema"]

#: The JSON Schema dialect of both schemas.
DRAFT = "https://json-schema.org/draft/2020-12/schema"

#: The schemas by name: what ``python -m rapp schema NAME`` prints.
SCHEMAS = ("scenario", "result")

_NUMBER: dict = {"type": "number"}
_NAME = {"type": "string"}


def _range(low: float, high: float, *, low_open: bool = False, kind: str = "number") -> dict:
    out: dict[str, Any] = {"type": kind}
    if not math.isinf(low):
        out["exclusiveMinimum" if low_open else "minimum"] = int(low) if kind == "integer" else low
    if not math.isinf(high):
        out["maximum"] = int(high) if kind == "integer" else high
    return out


def _list_of(item: dict, low: int | None = None, high: int | None = None) -> dict:
    out: dict[str, Any] = {"type": "array", "items": item}
    if low is not None:
        out["minItems"] = low
    if high is not None:
        out["maxItems"] = high
    return out


def _point(description: str) -> dict:
    c = _range(-sc.MAX_COORDINATE, sc.MAX_COORDINATE)
    return {**_list_of(c, 2, 2), "description": description}


def _length(description: str) -> dict:
    return {**_range(sc.MIN_LENGTH, sc.MAX_LENGTH), "description": description + " (m)"}


def _setting(spec: planner_table.Setting) -> dict:
    """One planner setting of the table as a schema."""
    if spec.kind == "cells":
        cell = {"type": "integer", "minimum": 3}
        out: dict[str, Any] = {"anyOf": [cell, _list_of(cell, 1, sc.MAX_LINKS)]}
    else:
        out = _range(spec.low, spec.high, low_open=spec.low_open, kind=spec.kind)
        if spec.nullable:
            out = {"anyOf": [out, {"type": "null"}]}
    if spec.default is not None and spec.kind != "cells":
        out["default"] = spec.default
    out["description"] = spec.description + (f" ({spec.unit})" if spec.unit else "")
    return out


def _rate(unit: str) -> dict:
    one = {"type": "number", "exclusiveMinimum": 0}
    return {"anyOf": [one, _list_of(one, 1, sc.MAX_LINKS), {"type": "null"}],
            "description": f"one limit for every joint or one per joint ({unit}, or deg "
                           "units when units.angle is 'deg')"}


def _obstacles() -> dict:
    circle = {"type": "object", "additionalProperties": False,
              "required": ["type", "center", "radius"],
              "properties": {"type": {"const": "circle"}, "center": _point("centre (m)"),
                             "radius": _length("radius")}}
    rectangle = {"type": "object", "additionalProperties": False,
                 "required": ["type", "corner", "width", "height"],
                 "properties": {"type": {"const": "rectangle"}, "corner": _point("a corner (m)"),
                                "width": _length("width"), "height": _length("height"),
                                "angle": {**_NUMBER, "description": "turn about the corner"}}}
    polygon = {"type": "object", "additionalProperties": False, "required": ["type", "vertices"],
               "properties": {"type": {"const": "polygon"},
                              "vertices": _list_of(_point("a vertex (m)"), 3)}}
    return _list_of({"oneOf": [circle, rectangle, polygon]}, None, sc.MAX_OBSTACLES)


def _gap() -> dict:
    """A width or margin (m): 0, or within [MIN_GAP, MAX_LENGTH] (the loader's ``_gap``)."""
    return {"anyOf": [{"const": 0}, _range(sc.MIN_GAP, sc.MAX_LENGTH)]}


def _arm() -> dict:
    angle = dict(_NUMBER)
    limit = {"anyOf": [_list_of(angle, 2, 2), {"type": "null"}]}
    properties = {
        "link_lengths": {**_list_of(_range(sc.MIN_LENGTH, sc.MAX_LENGTH), 1, sc.MAX_LINKS),
                         "description": "L1 .. Ln (m)"},
        "joint_limits": {"anyOf": [_list_of(limit, 1, sc.MAX_LINKS), {"type": "null"}],
                         "description": "per joint [lo, hi] or null (turns freely)"},
        "joint_names": {"anyOf": [{**_list_of({"type": "string", "minLength": 1}, 1,
                                              sc.MAX_LINKS), "uniqueItems": True},
                                  {"type": "null"}],
                        "description": "one distinct name per joint (default joint1 .. jointn)"},
        "base": {"anyOf": [{"type": "object", "additionalProperties": False, "properties": {
            "x": _range(-sc.MAX_COORDINATE, sc.MAX_COORDINATE),
            "y": _range(-sc.MAX_COORDINATE, sc.MAX_COORDINATE), "heading": dict(_NUMBER)}},
            {"type": "null"}], "description": "the base frame in the world: x, y (m), heading"},
        "joint_offsets": {"anyOf": [_list_of(angle, 1, sc.MAX_LINKS), {"type": "null"}],
                          "description": "what each encoder reads at the model's zero"},
        "link_radius": {"anyOf": [_gap(), _list_of(_gap(), 1, sc.MAX_LINKS)],
                        "description": "half the width of each link (m; one for all, or one per link)"},
        "self_collision": {"type": "boolean",
                           "description": "true: links that share no joint keep apart"},
    }
    assert set(properties) == {"link_lengths", *sc.ARM_OPTIONAL_KEYS}
    return {"type": "object", "additionalProperties": False, "required": ["link_lengths"],
            "properties": properties}


def _trajectory() -> dict:
    properties = {
        "duration": {**_range(sc.MIN_DURATION, sc.MAX_DURATION), "description": "seconds"},
        "profile": {"enum": list(sc.PROFILES)},
        "samples": {"type": "integer", "minimum": 2, "maximum": sc.MAX_SAMPLES},
        "dt": {**_range(1.0 / sc.MAX_SAMPLE_RATE, sc.MAX_DURATION),
               "description": "a fixed time step (s) instead of samples"},
        "max_velocity": _rate("rad/s"),
        "max_acceleration": _rate("rad/s^2"),
    }
    assert tuple(properties) == sc.TRAJECTORY_KEYS
    return {"type": "object", "additionalProperties": False, "properties": properties,
            "not": {"required": ["samples", "dt"]}}


def _planner() -> dict:
    properties: dict[str, Any] = {"algorithm": {"enum": list(planner_table.names())}}
    properties.update({key: _setting(spec) for key, spec in planner_table.all_settings().items()})
    return {"type": "object", "additionalProperties": False, "properties": properties}


def scenario_schema() -> dict:
    """The JSON Schema of a scenario file (see the module notes for what it leaves to the loader).

    Examples
    --------
    >>> sorted(scenario_schema()["properties"])   # doctest: +NORMALIZE_WHITESPACE
    ['arm', 'description', 'goal', 'name', 'obstacles', 'planner', 'safety_margin', 'start',
     'trajectory', 'units']
    """
    joints = _list_of(dict(_NUMBER), 1, sc.MAX_LINKS)
    goal = {"type": "object", "additionalProperties": False,
            "properties": {"joints": joints, "position": _point("end-effector goal (m)"),
                           "path": {"enum": list(sc.GOAL_PATHS)}},
            "oneOf": [{"required": ["joints"]}, {"required": ["position"]}]}
    properties = {
        "arm": _arm(),
        "obstacles": _obstacles(),
        "start": {**joints, "description": "start joint angles"},
        "goal": goal,
        "units": {"type": "object", "additionalProperties": False,
                  "properties": {"angle": {"enum": ["rad", "deg"]}, "length": {"enum": ["m"]}}},
        "planner": _planner(),
        "trajectory": _trajectory(),
        "name": _NAME,
        "description": _NAME,
        "safety_margin": {**_gap(), "description": "the gap (m) every link keeps beyond its radius"},
    }
    assert set(properties) == set(sc.TOP_KEYS)
    return {"$schema": DRAFT, "$id": "rapp:scenario.schema.json", "title": "rapp scenario",
            "description": "A scenario file of rapp (the book's 'Scenario files' page).",
            "type": "object", "additionalProperties": False, "required": ["arm", "start", "goal"],
            "properties": properties}


def result_schema() -> dict:
    """The JSON Schema of a result file (:func:`rapp.save_result`); its ``scenario`` is a scenario.

    Arrays hold numbers or ``null`` (a non-finite value is written as ``null``). Keys a later
    version adds (``timings``, ``motion``, ...) are allowed: a reader takes what it knows.

    Examples
    --------
    >>> r = result_schema()
    >>> r["properties"]["format"], r["properties"]["scenario"]["$ref"]
    ({'const': 'rapp-result'}, '#/$defs/scenario')
    """
    value = {"type": ["number", "null"]}
    vector = _list_of(value)
    matrix = _list_of(vector)
    scenario = {k: v for k, v in scenario_schema().items() if k not in ("$schema", "$id")}
    check = {"type": "object", "required": ["name", "ok"],
             "properties": {"name": {"type": "string"}, "ok": {"type": "boolean"},
                            "value": value, "limit": value, "unit": {"type": "string"},
                            "detail": {"type": "string"}}}
    properties = {
        "format": {"const": RESULT_FORMAT},
        "version": {"const": RESULT_VERSION},
        "scenario": {"$ref": "#/$defs/scenario"},
        "scenario_source": {"type": "string"},
        "scenario_angle_unit": {"enum": ["rad", "deg"]},
        "echo": _list_of({"type": "string"}),
        "profile": {"type": "string"},
        "t": {**vector, "description": "sample times (s)"},
        "q": {**matrix, "description": "joint angles (rad), one row per sample"},
        "qd": {**matrix, "description": "joint velocities (rad/s)"},
        "qdd": {**matrix, "description": "joint accelerations (rad/s^2)"},
        "xy": {**matrix, "description": "end-effector positions (m)"},
        "waypoints": matrix,
        "shortcut": matrix,
        "goal_q": vector,
        "grid_cells": {"anyOf": [_list_of({"type": "integer", "minimum": 1}), {"type": "null"}]},
        "occupancy": {"anyOf": [{"type": "null"}, {
            "type": "object", "required": ["shape", "packbits_base64"],
            "properties": {"shape": _list_of({"type": "integer", "minimum": 0}),
                           "packbits_base64": {"type": "string"}}}]},
        "report": {"anyOf": [{"type": "null"}, {
            "type": "object", "required": ["ok", "checks"],
            "properties": {"ok": {"type": "boolean"}, "checks": _list_of(check)}}]},
        "metrics": {"type": "object"},
        "timings": {"type": "object", "additionalProperties": {"type": ["number", "null"]}},
        "motion": {"description": "the timed motion itself, when the plan has one"},
    }
    required = ["format", "version", "scenario", "t", "q", "qd", "qdd", "xy", "waypoints",
                "shortcut", "goal_q"]
    return {"$schema": DRAFT, "$id": "rapp:result.schema.json", "title": "rapp result",
            "description": "A result file of rapp (rapp.save_result, python -m rapp plan --out).",
            "type": "object", "required": required, "properties": properties,
            "additionalProperties": True, "$defs": {"scenario": scenario}}


def schema(name: str) -> dict:
    """The schema called ``name`` (one of :data:`SCHEMAS`), built now.

    Examples
    --------
    >>> schema("result")["title"]
    'rapp result'
    """
    if name == "scenario":
        return scenario_schema()
    if name == "result":
        return result_schema()
    raise ValueError(f"unknown schema {name!r} (known: {', '.join(SCHEMAS)})")


def schema_text(name: str) -> str:
    """:func:`schema` as the shipped file holds it: indented JSON ending in a newline."""
    return json.dumps(schema(name), indent=2) + "\n"


def shipped_schema(name: str) -> dict:
    """The schema file the package ships (``rapp/schemas/NAME.schema.json``), read.

    Examples
    --------
    >>> shipped_schema("scenario") == scenario_schema()
    True
    """
    if name not in SCHEMAS:
        raise ValueError(f"unknown schema {name!r} (known: {', '.join(SCHEMAS)})")
    text = resources.files("rapp").joinpath("schemas").joinpath(f"{name}.schema.json").read_text("utf-8")
    return json.loads(text)
