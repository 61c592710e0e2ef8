"""``import rapp`` is cheap: the contract names are loaded on first use, and all of them resolve."""

from __future__ import annotations

import json
import subprocess
import sys

import rapp

HEAVY = ("matplotlib", "sympy", "numba", "scipy", "ipywidgets", "numpy.ma")


def _fresh(code: str):
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    return json.loads(out.stdout)


def test_import_rapp_loads_no_heavy_module():
    loaded = _fresh("import json, sys, rapp; print(json.dumps(sorted(sys.modules)))")
    assert not [m for m in HEAVY if m in loaded]
    assert not [m for m in loaded if m.startswith("rapp.") and m != "rapp.errors"]


def test_the_command_line_plan_imports_no_heavy_module(tmp_path):
    code = ("import json, sys; from rapp.cli import main; "
            f"main(['plan', '--out', {str(tmp_path / 'r.json')!r}]); "
            "print(json.dumps(sorted(sys.modules)))")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    loaded = json.loads(out.stdout.strip().splitlines()[-1])
    assert not [m for m in HEAVY if m in loaded]


def test_every_contract_name_resolves_in_a_fresh_process():
    got = _fresh("import json, rapp; print(json.dumps({n: type(getattr(rapp, n)).__name__ "
                 "for n in rapp.__all__}))")
    assert sorted(got) == sorted(rapp.__all__)
    assert "module" not in got.values()
    assert set(rapp.__all__) <= set(dir(rapp))


def test_from_rapp_import_and_submodules_keep_working():
    got = _fresh(
        "import json, rapp.ik, rapp.prm, rapp.verify\n"
        "from rapp import ik, plan, RRTResult, Arm\n"
        "import rapp\n"
        "print(json.dumps([callable(rapp.ik) and rapp.ik is ik, type(rapp.prm).__name__,\n"
        "                  type(rapp.verify).__name__, rapp.cspace.__name__,\n"
        "                  rapp.exercises.__name__, hasattr(rapp, 'no_such_name')]))")
    assert got == [True, "function", "function", "rapp.cspace", "rapp.exercises", False]
