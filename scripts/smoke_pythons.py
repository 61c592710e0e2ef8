"""Install rapp from this checkout on every CPython 3.10-3.13 the machine has and run the
library's own tests there (not the book's: no Jupyter, no notebooks).

For each interpreter found (``pythonX.Y`` on the PATH, or pyenv's ``~/.pyenv/versions/X.Y.*``):
a fresh venv in a temporary folder, ``pip install ".[fast]"`` (numba; when pip cannot install
it for that Python, plain ``.`` and the numpy code paths), the test tools, then

* ``rapp --version`` and ``rapp plan -q`` (the installed console script), and
* pytest on :data:`TESTS`, copied into the temporary folder with ``conftest.py`` and the few
  files they read, so that ``import rapp`` is the installed wheel, not the checkout.

An interpreter that is not on the machine is skipped, saying so. Exit status 0 when every
interpreter found passed (and at least one was found), else 1.

Usage: ``python scripts/smoke_pythons.py [3.10 3.12 ...]`` (default: 3.10 to 3.13).
"""

from __future__ import annotations

import glob
import os
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
VERSIONS = ("3.10", "3.11", "3.12", "3.13")
#: The library's own tests: kinematics, timing, the planner contract, files and formats, the
#: command line's library features. None needs the book stack (Jupyter, matplotlib figures).
TESTS = ("tests/test_library.py", "tests/test_schema.py", "tests/test_arm.py",
         "tests/test_time_scaling.py", "tests/test_planner_table.py")
#: Files the tests read beside them (the version, the licence, the changelog).
FILES = ("pyproject.toml", "LICENSE", "CHANGELOG.md")
#: The repository's conftest.py loads the notebook machinery; the library's tests need only
#: its hypothesis profile (derandomized under CI, as there).
CONFTEST = """import os
from hypothesis import settings
settings.register_profile("ci", derandomize=True, print_blob=True, database=None)
settings.load_profile("ci" if os.environ.get("CI") else "default")
"""
TOOLS = ("pytest", "hypothesis", "jsonschema")


def find(version: str) -> str | None:
    """An interpreter of ``version`` (``"3.12"``), or None."""
    on_path = shutil.which(f"python{version}")
    candidates = ([on_path] if on_path else []) + sorted(
        glob.glob(os.path.expanduser(f"~/.pyenv/versions/{version}.*/bin/python{version}")),
        reverse=True)
    for exe in candidates:
        try:
            out = subprocess.run([exe, "-c", "import sys, venv; print('%d.%d' % sys.version_info[:2])"],
                                 capture_output=True, text=True, timeout=60)
        except (OSError, subprocess.TimeoutExpired):
            continue
        if out.returncode == 0 and out.stdout.strip() == version:
            return exe
    return None


def run(cmd, **kw) -> subprocess.CompletedProcess:
    return subprocess.run([str(c) for c in cmd], text=True, capture_output=True, **kw)


def smoke(version: str, exe: str) -> bool:
    start = time.perf_counter()
    with tempfile.TemporaryDirectory(prefix=f"rapp-smoke-{version}-") as tmp:
        tmp = Path(tmp)
        venv = tmp / "venv"
        py = venv / "bin" / "python"
        steps = [[exe, "-m", "venv", venv]]
        for step in steps:
            r = run(step)
            if r.returncode:
                print(f"{version}: FAILED creating the venv\n{r.stdout}{r.stderr}")
                return False
        pip = [py, "-m", "pip", "install", "--quiet", "--disable-pip-version-check",
               "--progress-bar", "off"]
        t0 = time.perf_counter()
        r = run(pip + [f"{ROOT}[fast]", *TOOLS])
        extra = "[fast]"
        if r.returncode:   # numba may have no wheel for this Python yet
            print(f"{version}: '.[fast]' did not install ({r.stderr.strip().splitlines()[-1:]}); "
                  "trying '.'")
            extra = ""
            r = run(pip + [ROOT, *TOOLS])
            if r.returncode:
                print(f"{version}: FAILED pip install .\n{r.stdout}{r.stderr}")
                return False
        print(f"{version}: installed in {time.perf_counter() - t0:.0f} s", flush=True)
        work = tmp / "work"
        (work / "tests").mkdir(parents=True)
        for f in FILES:
            shutil.copy(ROOT / f, work / f)
        for f in TESTS:
            shutil.copy(ROOT / f, work / f)
        (work / "conftest.py").write_text(CONFTEST, encoding="utf-8")
        env = dict(os.environ)
        env.pop("PYTHONPATH", None)
        rapp = venv / "bin" / "rapp"
        checks = [([rapp, "--version"], "rapp --version"), ([rapp, "plan", "-q"], "rapp plan -q"),
                  ([py, "-m", "pytest", "-q", "-p", "no:cacheprovider", "-o", "addopts=",
                    "-m", "not slow", "-W", "error::DeprecationWarning:rapp.*", *TESTS],
                   "pytest " + " ".join(Path(t).name for t in TESTS))]
        for cmd, what in checks:
            r = run(cmd, cwd=work, env=env)
            if r.returncode:
                print(f"{version}: FAILED {what}\n{r.stdout[-4000:]}{r.stderr[-4000:]}")
                return False
            last = (r.stdout.strip().splitlines() or [""])[-1]
            print(f"{version}: {what}: {last}")
        numba = run([py, "-c", "import rapp.jit as j; print(j.numba_available())"]).stdout.strip()
        print(f"{version}: passed ('.{extra}', numba {'on' if numba == 'True' else 'off'}) in "
              f"{time.perf_counter() - start:.0f} s")
        return True


def main(argv: list[str]) -> int:
    versions = argv or list(VERSIONS)
    found = 0
    ok = True
    for version in versions:
        exe = find(version)
        if exe is None:
            print(f"{version}: skipped: no python{version} on this machine")
            continue
        found += 1
        print(f"{version}: {exe}", flush=True)
        ok = smoke(version, exe) and ok
        sys.stdout.flush()
    if not found:
        print("no CPython 3.10-3.13 found")
        return 1
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
