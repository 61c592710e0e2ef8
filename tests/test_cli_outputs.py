"""The command line's outputs: paths refused before any planning (the scenario itself, two
outputs on one file, a format that cannot be written), atomic figures and animations,
Ctrl-C wherever it lands, reproducible result files, stage times only on request, text
that is safe for a terminal, and no warning on the terminal."""

import io
import json
import os
import re
import subprocess
import sys
import warnings

import numpy as np
import pytest

import rapp.cli as cli
from rapp.cli import main, printable
from tests.helpers import one_line, run
from rapp.planner import STAGES

GOOD = {"arm": {"link_lengths": [1.0, 1.0]},
        "obstacles": [{"type": "circle", "center": [1.75, 0.75], "radius": 0.4}],
        "start": [0.0, 0.0], "goal": {"joints": [2.0, 0.5]},
        "planner": {"cells": 40}, "trajectory": {"samples": 40}}

# What a terminal must never receive raw: C0 but newline, DEL, C1, lone surrogates.
RAW = re.compile("[\x00-\x09\x0b-\x1f\x7f-\x9f\ud800-\udfff]")


def write_scenario(tmp_path, content=GOOD, name="s.json"):
    p = tmp_path / name
    p.write_text(json.dumps(content))  # ensure_ascii: "\ud800" stays a JSON escape
    return p


def leftovers(folder):
    return sorted(n for n in os.listdir(folder) if n.startswith(".rapp-"))


@pytest.fixture
def no_planning(monkeypatch):
    """Make any planning work fail loudly: the refusals must come before it."""
    def must_not_plan(*a, **k):
        raise AssertionError("planned although an output path was bad")

    monkeypatch.setattr("rapp.planner.plan", must_not_plan)


@pytest.fixture
def few_frames(monkeypatch):
    import rapp.plotting as plotting

    full = plotting.animate  # every frame takes long; the wiring is what is tested
    monkeypatch.setattr(plotting, "animate", lambda *a, **k: full(*a, **{**k, "max_frames": 3}))


# --------------------------------------------------------------------------- 1. no clobbering


def _aliases(tmp_path, scenario):
    (tmp_path / "sub").mkdir()
    os.symlink(scenario, tmp_path / "link.json")
    os.link(scenario, tmp_path / "hard.json")
    return {"same": str(scenario), "dotdot": str(tmp_path / "sub" / ".." / "s.json"),
            "relative": "./sub/../s.json", "symlink": str(tmp_path / "link.json"),
            "hardlink": str(tmp_path / "hard.json")}


@pytest.mark.parametrize("alias", ["same", "dotdot", "relative", "symlink", "hardlink"])
@pytest.mark.parametrize("option", ["--out", "--plot", "--animate"])
def test_an_output_on_the_scenario_file_is_refused(capsys, tmp_path, monkeypatch, no_planning,
                                                   option, alias):
    scenario = write_scenario(tmp_path)
    before = scenario.read_bytes()
    monkeypatch.chdir(tmp_path)
    target = _aliases(tmp_path, scenario)[alias]
    code, out, err = run(capsys, "plan", str(scenario), option, target)
    assert code == 2
    line = one_line(err)
    assert line.startswith(f"rapp: error: {option}:") and "scenario file" in line, line
    assert scenario.read_bytes() == before and out == ""
    assert leftovers(tmp_path) == []


@pytest.mark.parametrize("first,second", [("--out", "--plot"), ("--plot", "--animate"),
                                          ("--out", "--animate")])
def test_two_outputs_on_one_file_are_refused(capsys, tmp_path, no_planning, first, second):
    target = tmp_path / "x.gif"
    code, out, err = run(capsys, "plan", "default", first, str(target), second,
                         str(tmp_path / "sub" / ".." / "x.gif"))
    assert code == 2
    assert one_line(err).startswith(f"rapp: error: {second}:")
    assert "same file" in err and os.listdir(tmp_path) == []


def test_two_outputs_through_a_symlink_are_refused(capsys, tmp_path, no_planning):
    (tmp_path / "r.png").write_bytes(b"old")
    os.symlink(tmp_path / "r.png", tmp_path / "link.png")
    code, out, err = run(capsys, "plan", "default", "--out", str(tmp_path / "link.png"),
                         "--plot", str(tmp_path / "r.png"))
    assert code == 2 and one_line(err).startswith("rapp: error: --plot:")
    assert (tmp_path / "r.png").read_bytes() == b"old"


# --------------------------------------------------------------------------- 2. atomic, Ctrl-C


@pytest.mark.parametrize("name", ["f.png", "f.svg"])
def test_plot_interrupted_while_writing_keeps_the_old_file(capsys, tmp_path, monkeypatch, name):
    from matplotlib.figure import Figure

    fig = tmp_path / name
    fig.write_bytes(b"the previous figure")

    def half_written(self, fname, *a, **k):
        with open(fname, "wb") as fh:
            fh.write(b"\x89PNG half")
        raise KeyboardInterrupt

    monkeypatch.setattr(Figure, "savefig", half_written)
    code, out, err = run(capsys, "plan", "default", "--plot", str(fig), "-q")
    assert code == 130 and one_line(err) == "rapp: interrupted"
    assert fig.read_bytes() == b"the previous figure"
    assert leftovers(tmp_path) == []


def test_animation_interrupted_while_writing_keeps_the_old_file(capsys, tmp_path, monkeypatch,
                                                                few_frames):
    gif = tmp_path / "a.gif"
    gif.write_bytes(b"the previous animation")

    def half_written(anim, path, *a, **k):
        with open(path, "wb") as fh:
            fh.write(b"GIF89a half")
        raise KeyboardInterrupt

    monkeypatch.setattr("rapp.plotting.save_gif", half_written)
    code, out, err = run(capsys, "plan", "default", "--animate", str(gif), "-q")
    assert code == 130 and one_line(err) == "rapp: interrupted"
    assert gif.read_bytes() == b"the previous animation"
    assert leftovers(tmp_path) == []


def test_interrupt_inside_the_animation_writer_is_130(capsys, tmp_path, monkeypatch, few_frames):
    # matplotlib's cleanup then fails with an IndexError (no frame grabbed) while the
    # interrupt is being handled: that error used to be reported as an internal error.
    import matplotlib.animation as animation

    def interrupted(self, **k):
        raise KeyboardInterrupt

    monkeypatch.setattr(animation.PillowWriter, "grab_frame", interrupted)
    gif = tmp_path / "a.gif"
    code, out, err = run(capsys, "plan", "default", "--animate", str(gif), "-q")
    assert code == 130 and one_line(err) == "rapp: interrupted"
    assert os.listdir(tmp_path) == []


@pytest.mark.parametrize("where,name", [
    ("rapp.planner.plan", "f.png"), ("rapp.plotting.plot_plan", "f.png"),
    ("rapp.plotting.plot_plan", "f.svg"), ("rapp.scenario.load_scenario", "f.png")])
def test_an_error_raised_while_handling_an_interrupt_is_130(capsys, tmp_path, monkeypatch, where,
                                                            name):
    def cleanup_fails(*a, **k):
        try:
            raise KeyboardInterrupt
        except KeyboardInterrupt:
            raise ValueError("cleanup after Ctrl-C failed") from None

    monkeypatch.setattr(where, cleanup_fails)
    code, out, err = run(capsys, "plan", "default", "--plot", str(tmp_path / name), "-q")
    assert code == 130 and one_line(err) == "rapp: interrupted"
    assert os.listdir(tmp_path) == []


@pytest.mark.parametrize("name", ["f.png", "f.svg"])
def test_a_failed_write_names_the_option_and_leaves_nothing(capsys, tmp_path, monkeypatch, name):
    import errno

    from matplotlib.figure import Figure

    def disk_full(self, fname, *a, **k):
        with open(fname, "wb") as fh:
            fh.write(b"\x89PNG half")
        raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC), fname)

    monkeypatch.setattr(Figure, "savefig", disk_full)
    code, out, err = run(capsys, "plan", "default", "--plot", str(tmp_path / name), "-q")
    assert code == 2
    assert one_line(err) == f"rapp: error: --plot: cannot write: {os.strerror(errno.ENOSPC)}"
    assert os.listdir(tmp_path) == []


# --------------------------------------------------------------------------- 3. checked first


@pytest.mark.parametrize("option,name,needle", [
    ("--plot", "f.xyz", "unsupported extension '.xyz'"),
    ("--plot", "figure", "no extension"),
    ("--animate", "a.avi", "unsupported extension '.avi'"),
    ("--animate", "a.png", "unsupported extension '.png'"),
    ("--animate", "a.mp4", "ffmpeg"),
    ("--out", "", "empty"),
])
def test_output_formats_are_checked_before_planning(capsys, tmp_path, monkeypatch, no_planning,
                                                    option, name, needle):
    import matplotlib.animation as animation

    monkeypatch.setattr(animation.writers, "is_available", lambda writer: writer != "ffmpeg")
    result = tmp_path / "r.json"
    argv = ["plan", "default", option, str(tmp_path / name) if name else name]
    if option != "--out":
        argv += ["--out", str(result)]
    code, out, err = run(capsys, *argv)
    assert code == 2
    line = one_line(err)
    assert line.startswith(f"rapp: error: {option}:") and needle in line, line
    assert not result.exists() and os.listdir(tmp_path) == []


def test_pgf_needs_latex(capsys, tmp_path, monkeypatch, no_planning):
    monkeypatch.setattr(cli.shutil, "which", lambda name: None)
    code, out, err = run(capsys, "plan", "default", "--plot", str(tmp_path / "f.pgf"))
    assert code == 2 and "needs" in one_line(err) and os.listdir(tmp_path) == []


def test_an_output_that_is_not_a_regular_file_is_refused(capsys, no_planning):
    # os.replace would swap /dev/null for a regular file when run as root.
    code, out, err = run(capsys, "plan", "default", "--out", os.devnull)
    assert code == 2 and one_line(err).startswith("rapp: error: --out:")


@pytest.mark.parametrize("name", ["f.svg", "F.PNG", "f.pdf"])
def test_plot_formats_follow_the_extension(capsys, tmp_path, name):
    fig = tmp_path / name
    code, out, err = run(capsys, "plan", "default", "--plot", str(fig), "-q")
    assert code == 0, err
    head = fig.read_bytes()[:5]
    assert head == {"svg": b"<?xml", "png": b"\x89PNG\r", "pdf": b"%PDF-"}[name[-3:].lower()]
    assert leftovers(tmp_path) == []


def test_mp4_is_written_with_ffmpeg_when_it_is_available(capsys, tmp_path, monkeypatch,
                                                         few_frames):
    import matplotlib.animation as animation

    used = []

    def fake_save(self, filename, writer=None, **k):
        used.append(type(writer).__name__)
        with open(filename, "wb") as fh:
            fh.write(b"mp4")

    monkeypatch.setattr(animation.writers, "is_available", lambda writer: True)
    monkeypatch.setattr(animation.Animation, "save", fake_save)
    mp4 = tmp_path / "a.mp4"
    code, out, err = run(capsys, "plan", "default", "--animate", str(mp4), "-q")
    assert code == 0, err
    assert used == ["FFMpegWriter"] and mp4.read_bytes() == b"mp4"
    assert leftovers(tmp_path) == []


# --------------------------------------------------------------------------- 4. reproducible


def test_the_result_file_is_the_same_byte_for_byte(capsys, tmp_path):
    first, second = tmp_path / "1.json", tmp_path / "2.json"
    assert run(capsys, "plan", "srs_typical", "--out", str(first), "-q")[0] == 0
    assert run(capsys, "plan", "srs_typical", "--out", str(second))[0] == 0
    assert first.read_bytes() == second.read_bytes()
    assert "timings" not in json.loads(first.read_text())


def test_stage_times_only_with_timings(capsys, tmp_path):
    code, out, err = run(capsys, "plan", "default")
    assert code == 0 and "time per stage" not in out
    result = tmp_path / "r.json"
    code, out, err = run(capsys, "plan", "default", "--timings", "--out", str(result))
    assert code == 0 and "time per stage: ik " in out and out.rstrip().endswith("verified")
    assert set(json.loads(result.read_text())["timings"]) == set(STAGES)
    code, out, err = run(capsys, "plan", "default", "--timings", "-q")
    lines = out.splitlines()
    assert code == 0 and len(lines) == 3 and lines[0].startswith("time per stage: ")
    # Compilation is reported apart: it is not planning, and no time budget counts it.
    assert lines[1].startswith("compilation: ") and "compile" not in lines[0]
    code, out, err = run(capsys, "plan", "default", "-q")
    assert code == 0 and len(out.splitlines()) == 1


# --------------------------------------------------------------------------- 5. terminal safety


def strict_streams(monkeypatch, encoding="utf-8"):
    streams = [io.TextIOWrapper(io.BytesIO(), encoding=encoding, errors="strict")
               for _ in range(2)]
    monkeypatch.setattr(sys, "stdout", streams[0])
    monkeypatch.setattr(sys, "stderr", streams[1])

    def read():
        texts = []
        for s in streams:
            s.flush()
            texts.append(s.buffer.getvalue().decode(encoding))
        return texts

    return read


@pytest.mark.parametrize("text,shown", [
    ("\u001b[31mred", "\\x1b[31mred"),
    ("\ud800", "\\ud800"),
    ("a\nscenario is valid\u009b", "a\\x0ascenario is valid\\x9b"),  # no forged line
])
@pytest.mark.parametrize("field", ["name", "description"])
@pytest.mark.parametrize("command", ["check", "plan"])
def test_names_reach_the_terminal_escaped(tmp_path, monkeypatch, command, field, text, shown):
    scenario = write_scenario(tmp_path, {**GOOD, field: text})
    read = strict_streams(monkeypatch)
    code = main([command, str(scenario)])
    out, err = read()
    assert code == 0 and err == ""
    assert RAW.search(out) is None, out
    line = next(ln for ln in out.splitlines() if ln.startswith(field if field == "description"
                                                               else "scenario"))
    assert line.split(None, 1)[1] == shown


def test_error_messages_reach_the_terminal_escaped(tmp_path, monkeypatch):
    from rapp.errors import NoPathFound

    def blocked(*a, **k):
        raise NoPathFound("blocked by \u001b[2J\ud800 and\u0085this")

    monkeypatch.setattr("rapp.planner.plan", blocked)
    read = strict_streams(monkeypatch)
    code = main(["plan", "default", "-q"])
    out, err = read()
    assert code == 1 and RAW.search(err) is None
    assert one_line(err) == "rapp: no path: blocked by \\x1b[2J\\ud800 and\\x85this"


def test_a_file_name_with_escapes_is_shown_escaped(tmp_path, monkeypatch):
    scenario = write_scenario(tmp_path, name="\u001b[31m.json")
    read = strict_streams(monkeypatch)
    assert main(["check", str(scenario)]) == 0
    out, err = read()
    assert RAW.search(out) is None and "\\x1b[31m.json" in out


def test_a_terminal_that_is_not_utf8_gets_escapes(tmp_path, monkeypatch):
    scenario = write_scenario(tmp_path, {**GOOD, "name": "café"})
    read = strict_streams(monkeypatch, encoding="ascii")
    assert main(["check", str(scenario)]) == 0
    out, err = read()
    assert "caf\\xe9" in out and err == ""


def test_real_entry_point_on_a_strict_terminal(tmp_path):
    scenario = write_scenario(tmp_path, {**GOOD, "name": "\ud800\u001b[31mred"})
    env = {**os.environ, "MPLBACKEND": "Agg", "PYTHONIOENCODING": "utf-8:strict"}
    r = subprocess.run([sys.executable, "-m", "rapp", "check", str(scenario)], capture_output=True,
                       timeout=120, cwd=tmp_path, env=env)
    assert r.returncode == 0 and r.stderr == b""
    out = r.stdout.decode("utf-8")
    assert RAW.search(out) is None and "\\ud800\\x1b[31mred" in out


def test_printable_keeps_ordinary_text():
    assert printable("C:\\path\\ café 1 × 2 → π") == "C:\\path\\ café 1 × 2 → π"
    assert printable("\t\r\x00\x7f\x80\u202e\u2028") == "\\x09\\x0d\\x00\\x7f\\x80\\u202e\\u2028"
    assert printable("a\nb", newline=True) == "a\nb"
    assert printable(printable("\x1b\ud800")) == "\\x1b\\ud800"


# --------------------------------------------------------------------------- 6. no warnings


def _show_on_stderr(message, category, filename, lineno, file=None, line=None):
    sys.stderr.write(warnings.formatwarning(message, category, filename, lineno, line))


@pytest.mark.parametrize("quiet", [False, True])
def test_numpy_warnings_never_reach_the_terminal(capsys, monkeypatch, quiet):
    import rapp.planner as planner

    verify = planner.verify

    def noisy_verify(*a, **k):
        np.float64(1.0) / 0.0
        np.array([0.0]) / np.array([0.0])
        return verify(*a, **k)

    monkeypatch.setattr(planner, "verify", noisy_verify)
    with warnings.catch_warnings():
        # As outside pytest: warnings are printed on stderr.
        warnings.resetwarnings()
        warnings.simplefilter("default")
        warnings.showwarning = _show_on_stderr
        code, out, err = run(capsys, "plan", "default", *(["-q"] if quiet else []))
    assert code == 0 and err == ""
    assert "RuntimeWarning" not in out
    assert out.rstrip().endswith("verified")
    notes = [ln for ln in out.splitlines() if ln.startswith("note: ")]
    assert notes == ([] if quiet else
                     ["note: 2 warnings silenced while running "
                      "(first: divide by zero encountered in scalar divide)"])


def test_warning_as_error_is_one_internal_error_line(capsys, monkeypatch):
    import rapp.planner as planner

    def noisy(*a, **k):
        np.float64(1.0) / 0.0

    monkeypatch.setattr(planner, "plan", noisy)
    with warnings.catch_warnings():
        warnings.simplefilter("error", RuntimeWarning)  # python -W error::RuntimeWarning
        code, out, err = run(capsys, "plan", "default", "-q")
    assert code == 3 and one_line(err).startswith("rapp: internal error: RuntimeWarning:")


def test_a_closed_pipe_ends_quietly(tmp_path):
    # `rapp plan | head -1`: the reader closes the pipe; before, this ended with
    # "rapp: error: output: Broken pipe" and exit 2.
    import subprocess
    import sys

    # -u: unbuffered, so the first line arrives before the rest is written.
    proc = subprocess.Popen([sys.executable, "-u", "-m", "rapp", "plan", "default"],
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE)
    proc.stdout.readline()
    proc.stdout.close()
    err = proc.stderr.read().decode()
    assert proc.wait(timeout=120) == 141
    assert err == ""


def test_plot_png_is_the_book_figure_drawn_without_pyplot(capsys, tmp_path):
    # One renderer: rapp.plotting.plot_plan, at PLAN_FIGSIZE and 100 dpi, on a figure of its own.
    import matplotlib.pyplot as plt
    from PIL import Image

    from rapp.plotting import PLAN_FIGSIZE

    open_before = plt.get_fignums()
    fig = tmp_path / "f.png"
    code, out, err = run(capsys, "plan", "default", "--plot", str(fig), "-q")
    assert code == 0, err
    with Image.open(fig) as image:
        assert image.format == "PNG"
        assert image.size == tuple(round(100 * inches) for inches in PLAN_FIGSIZE)
    assert plt.get_fignums() == open_before  # no pyplot figure made, none left open
