"""The JSON Schemas of scenario and result files: shipped as built, draft 2020-12, every embedded
scenario and a result validate, malformed files do not, and the command line prints them."""

import copy
import json
from importlib import resources

import pytest

import rapp
from rapp import schema
from rapp.cli import main

jsonschema = pytest.importorskip("jsonschema")


def validator(name):
    s = schema.shipped_schema(name)
    jsonschema.Draft202012Validator.check_schema(s)
    return jsonschema.Draft202012Validator(s)


def embedded():
    for name in rapp.list_scenarios():
        text = resources.files("rapp").joinpath("scenarios", f"{name}.json").read_text("utf-8")
        yield name, json.loads(text)


@pytest.mark.parametrize("name", schema.SCHEMAS)
def test_the_shipped_schema_is_the_one_built_from_the_loader_and_planner_table(name):
    assert schema.shipped_schema(name) == schema.schema(name)
    assert resources.files("rapp").joinpath("schemas", f"{name}.schema.json").read_text(
        "utf-8") == schema.schema_text(name)


def test_every_embedded_scenario_and_its_canonical_form_validate():
    v = validator("scenario")
    for name, data in embedded():
        assert not list(v.iter_errors(data)), name
        assert not list(v.iter_errors(rapp.load_scenario(name).to_dict())), name


def test_the_planner_table_is_the_schemas_planner_keys():
    planner = schema.scenario_schema()["properties"]["planner"]["properties"]
    assert set(planner) == {"algorithm", *rapp.planners.all_settings()}
    assert planner["algorithm"]["enum"] == list(rapp.planners.names())
    step = rapp.planners.all_settings()["step"]
    assert planner["step"]["minimum"] == step.low and planner["step"]["maximum"] == step.high


def test_a_result_validates(tmp_path):
    s = rapp.load_scenario({**next(iter(embedded()))[1], "trajectory": {"samples": 20}})
    p = rapp.plan(s)
    rapp.save_result(p, tmp_path / "r.json", timings=True)
    result = json.loads((tmp_path / "r.json").read_text())
    v = validator("result")
    assert not list(v.iter_errors(result))
    # The motion engineer's `motion` key (or any later key) is allowed.
    assert not list(v.iter_errors({**result, "motion": {"breaks": [0, 1], "coefficients": []}}))


MALFORMED = [
    ("missing arm", lambda d: d.pop("arm")),
    ("unknown top key", lambda d: d.update(colour="red")),
    ("link length a string", lambda d: d["arm"].update(link_lengths=["1"])),
    ("negative link length", lambda d: d["arm"].update(link_lengths=[-1.0, 1.0])),
    ("17 links", lambda d: d["arm"].update(link_lengths=[0.1] * 17)),
    ("unknown obstacle", lambda d: d.update(obstacles=[{"type": "ellipse"}])),
    ("circle without radius", lambda d: d.update(obstacles=[{"type": "circle", "center": [0, 0]}])),
    ("goal with both", lambda d: d.update(goal={"joints": [0, 0], "position": [1, 1]})),
    ("unknown planner", lambda d: d.update(planner={"algorithm": "dijkstra"})),
    ("step out of range", lambda d: d.update(planner={"step": 10.0})),
    ("samples and dt", lambda d: d.update(trajectory={"samples": 10, "dt": 0.1})),
    ("unknown profile", lambda d: d.update(trajectory={"profile": "bang-bang"})),
    ("repeated joint names", lambda d: d["arm"].update(joint_names=["a", "a"])),
    ("base as a list", lambda d: d["arm"].update(base=[0, 0, 0])),
]


@pytest.mark.parametrize("what, spoil", MALFORMED, ids=[m[0] for m in MALFORMED])
def test_a_malformed_scenario_is_rejected_by_the_schema_and_the_loader(what, spoil):
    data = copy.deepcopy(dict(embedded())["default"])
    spoil(data)
    assert list(validator("scenario").iter_errors(data)), what
    with pytest.raises(rapp.ScenarioError):
        rapp.load_scenario(data)


def test_a_malformed_result_is_rejected():
    v = validator("result")
    assert list(v.iter_errors({"format": "rapp-result"}))
    assert list(v.iter_errors({"format": "other", "version": 1}))


def test_the_command_line_prints_the_shipped_schemas(capsys):
    for name in schema.SCHEMAS:
        assert main(["schema", name]) == 0
        assert json.loads(capsys.readouterr().out) == schema.shipped_schema(name)
    assert main(["schema", "nonsense"]) == 2
    capsys.readouterr()
