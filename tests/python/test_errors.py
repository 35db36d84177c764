"""Every error the package raises is a needlesim.InputError or SolverError (subclasses
may also be the matching builtin), worded as the CLI words it: bad arguments, results
folders that are missing or damaged, folders that cannot be written; Sessions keep the
step guard from the first step and refuse poses outside the tissue's reach; with_values
resolves relative data paths from the scenario's folder."""
import json
import math
import os
import pathlib
import shutil
import subprocess
import sys

import numpy as np
import pytest

import needlesim
from conftest import SOURCE_DIR

COARSE = {"insertion.profile[0].insert.to": "20 mm", "model.realtime2d.nodes_depth": 11,
          "model.realtime2d.nodes_lateral": 16}


def message(error_class, call, *args, **kwargs):
    """The message of the error_class that call(*args, **kwargs) raises."""
    with pytest.raises(error_class) as e:
        call(*args, **kwargs)
    assert isinstance(e.value, (needlesim.InputError, needlesim.SolverError)), type(e.value)
    return str(e.value)


def test_the_error_classes():
    assert issubclass(needlesim.InputError, ValueError) and issubclass(needlesim.SolverError, RuntimeError)
    for cls, builtin in ((needlesim.ArgumentTypeError, TypeError), (needlesim.NotFoundError, FileNotFoundError),
                         (needlesim.UnknownNameError, KeyError)):
        assert issubclass(cls, needlesim.InputError) and issubclass(cls, builtin)
    assert str(needlesim.UnknownNameError("no column 'x'")) == "no column 'x'"  # not quoted as KeyError quotes


# --- results folders --------------------------------------------------------------------


@pytest.fixture(scope="module")
def lumped_folder(tmp_path_factory):
    out = tmp_path_factory.mktemp("written") / "run"
    needlesim.run(needlesim.load(SOURCE_DIR / "examples" / "gelatin_18G_3mms.yaml"), out=out)
    return out


@pytest.fixture
def damaged(lumped_folder, tmp_path):
    """A copy of a complete results folder, to damage."""
    folder = tmp_path / "copy"
    shutil.copytree(lumped_folder, folder)
    return folder


def test_a_missing_folder_is_not_found(tmp_path):
    text = message(needlesim.NotFoundError, needlesim.open_results, tmp_path / "nothing")
    assert "nothing: does not exist" in text and "results folder" in text
    (tmp_path / "file").write_text("x")
    assert "file: is not a folder" in message(needlesim.NotFoundError, needlesim.open_results, tmp_path / "file")
    text = message(needlesim.NotFoundError, needlesim.open_results, tmp_path)
    assert "not a needlesim results folder: it has no summary.json" in text


@pytest.mark.parametrize("content, words", [
    (b'{"engine": "lumped", "files": ["forces.csv"', ["summary.json:1:", "is not valid JSON"]),
    (b"", ["summary.json:1:1", "is not valid JSON"]),
    (b"[1, 2]", ["summary.json", "holds a JSON list, not an object"]),
    (b'{"files": 3}', ["summary.json", "'files' is a int, not a list"]),
    (b'{"results": {"f": 3}}', ["summary.json", "results['f'] is not {value: a number"]),
    (b'{"results": {"f": {"value": "x"}}}', ["summary.json", "results['f']"]),
    (b'{"scenario": "x"}', ["summary.json", "'scenario' is a str, not a dict"]),
    (b'{"files": ["../../outside.csv"]}', ["summary.json", "names '../../outside.csv'", "inside the results folder"]),
    (b'{"files": ["/etc/passwd.csv"]}', ["summary.json", "names '/etc/passwd.csv'"]),
    (b'{"engine": "\xff\xfe"}', ["summary.json", "is not UTF-8 text (byte 12)"]),
    (b"[" * 100000, ["summary.json", "is not valid JSON"]),
])
def test_a_damaged_summary_is_an_input_error(damaged, content, words):
    (damaged / "summary.json").write_bytes(content)
    text = message(needlesim.InputError, needlesim.open_results, damaged)
    assert all(w in text for w in words), text


def test_a_truncated_summary_names_the_file(damaged):
    summary = (damaged / "summary.json").read_bytes()
    (damaged / "summary.json").write_bytes(summary[: len(summary) // 2])
    assert "is not valid JSON" in message(needlesim.InputError, needlesim.open_results, damaged)


@pytest.mark.parametrize("damage, error, words", [
    (lambda f: f.write_bytes(b"time [s],depth [m]\n0,\xff\n"), needlesim.InputError, ["forces.csv", "not UTF-8"]),
    (lambda f: f.unlink(), needlesim.NotFoundError, ["forces.csv: does not exist"]),
    (lambda f: f.write_text("time [s],depth [m]\n0,1\n2\n"), needlesim.InputError,
     ["forces.csv:3", "has 1 values", "2 numbers"]),
    (lambda f: f.write_text("time [s],depth [m]\n0,1\n2,abc\n"), needlesim.InputError,
     ["forces.csv:3", "'abc' is not a number"]),
    (lambda f: (f.unlink(), f.mkdir()), needlesim.InputError, ["forces.csv: is a folder"]),
])
def test_a_damaged_table_is_an_input_error(damaged, damage, error, words):
    damage(damaged / "forces.csv")
    text = message(error, needlesim.open_results, damaged)
    assert all(w in text for w in words), text


def test_missing_and_damaged_field_files(damaged):
    summary = json.loads((damaged / "summary.json").read_text())
    summary["files"].append("tissue.xdmf")
    (damaged / "summary.json").write_text(json.dumps(summary))
    assert "tissue.xdmf: does not exist" in message(needlesim.NotFoundError, needlesim.open_results, damaged)
    (damaged / "tissue.xdmf").write_bytes(b"<Xdmf><Domain>")
    assert "is not a readable XDMF file" in message(needlesim.InputError, needlesim.open_results, damaged)
    grid = ('<Xdmf><Domain><Grid><Time Value="x"/><Geometry><DataItem Format="HDF">t.h5:/p</DataItem></Geometry>'
            '</Grid></Domain></Xdmf>')
    (damaged / "tissue.xdmf").write_text(grid)
    assert "tissue.xdmf: cannot be read" in message(needlesim.InputError, needlesim.open_results, damaged)
    (damaged / "tissue.xdmf").write_text(grid.replace(' Value="x"', "").replace("t.h5", "../t.h5"))
    assert "outside the XDMF file's folder" in message(needlesim.InputError, needlesim.open_results, damaged)
    (damaged / "tissue.xdmf").write_text(grid.replace(' Value="x"', "").replace("Format=\"HDF\"", ""))
    assert "format 'XML'" in message(needlesim.InputError, needlesim.open_results, damaged)
    (damaged / "tissue.xdmf").write_text(grid.replace(' Value="x"', ""))
    r = needlesim.open_results(damaged)  # the HDF5 file is read when used
    assert "t.h5: does not exist" in message(needlesim.NotFoundError, lambda: r.fields["tissue"].points)
    (damaged / "t.h5").write_bytes(b"not HDF5")
    assert "t.h5: cannot be read" in message(needlesim.InputError, lambda: r.fields["tissue"].points)


def test_unknown_names_are_unknown_name_errors(damaged):
    r = needlesim.open_results(damaged)
    assert "has no column 'nope'" in message(needlesim.UnknownNameError, lambda: r.tables["forces"]["nope"])
    assert "Results has no 'nope'" in message(needlesim.UnknownNameError, lambda: r["nope"])


# --- running into a folder ----------------------------------------------------------------


@pytest.mark.parametrize("out, words", [
    ("/proc/needlesim-results", ["needlesim.run(out)", "/proc/needlesim-results", "cannot be written"]),
    ("a\0b", ["needlesim.run(out)", "NUL"]),
])
def test_a_folder_that_cannot_be_written_is_an_input_error(gelatin, out, words):
    text = message(needlesim.InputError, needlesim.run, gelatin, out=out)
    assert all(w in text for w in words), text


def test_run_into_a_folder_under_a_file(gelatin, tmp_path):
    (tmp_path / "file").write_text("mine")
    message(needlesim.InputError, needlesim.run, gelatin, out=tmp_path / "file" / "run")
    assert (tmp_path / "file").read_text() == "mine"


def test_a_results_folder_whose_name_is_not_utf8(gelatin, tmp_path):
    out = os.fsdecode(bytes(tmp_path) + b"/run-\xff")  # a name with a byte that is not UTF-8
    r = needlesim.run(gelatin, out=out)
    assert r.results["exit_force"].unit == "N" and os.path.samefile(r.folder, out)


# --- arguments of the wrong type -----------------------------------------------------------


def test_arguments_of_the_wrong_type(gelatin):
    session = needlesim.Session(gelatin)
    calls = [
        lambda: needlesim.load(5),
        lambda: needlesim.load(b"examples/gelatin_18G_3mms.yaml"),
        lambda: needlesim.run(5),
        lambda: needlesim.run(gelatin, out=5),
        lambda: needlesim.run(gelatin, overwrite="yes"),
        lambda: needlesim.open_results(5),
        lambda: needlesim.FieldSeries(None),
        lambda: needlesim.Session("gelatin"),
        lambda: needlesim.LumpedForceModel(3),
        lambda: session.step("deep"),
        lambda: session.step(None),
        lambda: session.step(0.0, dt="1 ms"),
        lambda: session.needle_shape("many"),
        lambda: gelatin.motion_at("now"),
        lambda: gelatin.with_values([("tissue.friction.C_p", "3 N/m")]),
        lambda: gelatin.with_values({1: 2}),
        lambda: gelatin.with_values({"tissue.friction.C_p": object()}),
    ]
    for call in calls:
        text = message(needlesim.ArgumentTypeError, call)
        assert text.startswith("needlesim.") or text.startswith("Scenario."), text


def test_text_that_is_not_unicode(gelatin, tmp_path):
    undecodable = os.fsdecode(bytes(tmp_path) + b"/\xff.yaml")  # a file name with a byte that is not UTF-8
    assert "file not found" in message(needlesim.InputError, needlesim.load, undecodable)
    assert "not valid text" in message(needlesim.InputError, gelatin.with_values, {"tissue.friction.C_p": "\udcff"})


def test_a_pipe_or_device_is_not_read_as_a_scenario(tmp_path):
    """/dev/zero would be read without end, a pipe without a writer waits for ever: both are refused
    at once (in a child process, so that a hang fails the test instead of stopping it)."""
    os.mkfifo(tmp_path / "pipe.yaml")
    script = ("import needlesim, sys\n"
              "for p in sys.argv[1:]:\n"
              "    try:\n"
              "        needlesim.load(p)\n"
              "    except needlesim.InputError as e:\n"
              "        print(e)\n")
    done = subprocess.run([sys.executable, "-c", script, "/dev/zero", str(tmp_path / "pipe.yaml")],
                          capture_output=True, text=True, timeout=60)
    lines = done.stdout.splitlines()
    assert len(lines) == 2 and all("is not a regular file" in line for line in lines), done.stdout + done.stderr


# --- Sessions: the step guard from the first step, the tissue's reach ----------------------


@pytest.fixture
def coarse(example):
    return example("realtime2d/thesis_gelatin_18G_10mms.yaml").with_values(COARSE)


def test_the_first_step_keeps_the_step_guard(gelatin, coarse):
    # lumped: the thinnest layer is the 55 mm block, 27.5 mm per step at most
    text = message(needlesim.InputError, needlesim.Session(gelatin).step, 0.100)
    assert "moves the tip 100 mm in its first step (a Session starts at insertion.start_depth, 0 mm" in text, text
    assert "at most 27.5 mm per step" in text
    text = message(needlesim.InputError, needlesim.Session(coarse).step, 0.050)
    assert "moves the tip 50 mm in its first step (a Session starts at insertion.start_depth, -1 mm" in text, text
    assert "at most 4 mm per step" in text
    # before the tissue the needle may start anywhere; from there on every step is guarded
    session = needlesim.Session(coarse)
    assert session.step(-0.030).depth == pytest.approx(-0.030)
    assert "moves the tip 31 mm in one step (from -30 mm)" in message(needlesim.InputError, session.step, 0.001)
    assert needlesim.Session(gelatin).step(0.020).depth == 0.020  # within the guard


def test_the_step_guard_gives_the_message_of_every_session(gelatin):
    # One guard for every caller (engines/session.hpp): the C++ API's Session, needlesim serve
    # and its haptic bridge give these texts too (tests/api/test_api.cpp, TheStepGuardRefuses...)
    session = needlesim.Session(gelatin)
    assert message(needlesim.InputError, session.step, 0.100) == (
        "<session>: Session.step(depth): moves the tip 100 mm in its first step (a Session starts at "
        "insertion.start_depth, 0 mm; only before the tissue (depth <= 0 mm) may it be placed anywhere) (got '0.1'); "
        "allowed: at most 27.5 mm per step (0.5 x the thinnest layer); take smaller steps")
    assert message(needlesim.InputError, session.step, float("nan")) == (
        "<session>: Session.step(depth): must be a finite number (got 'nan'); allowed: a tip depth in m")
    assert session.time == 0.0 and session.depth is None  # nothing was stepped


def test_a_session_refuses_a_tip_deeper_than_the_needle(gelatin):
    text = message(needlesim.InputError, needlesim.Session(gelatin).step, 1.0)
    assert "Session.step(depth)" in text and "deeper than the needle is long" in text and "0.15 m" in text


@pytest.mark.parametrize("kwargs, words", [
    ({"lateral": 1e9}, ["Session.step(lateral)", "'1e+09'", "entry face", "-0.06 m < lateral < 0.06 m"]),
    ({"lateral": -0.0601}, ["Session.step(lateral)", "-0.06 m < lateral"]),
    ({"rotation": 1e9}, ["Session.step(rotation)", "'1e+09'", "-1.5708 rad < rotation < 1.5708 rad"]),
    ({"rotation": -1.6}, ["Session.step(rotation)"]),
])
def test_realtime2d_refuses_poses_outside_the_tissue(coarse, kwargs, words):
    session = needlesim.Session(coarse)
    session.step(0.0)
    text = message(needlesim.InputError, session.step, 0.001, **kwargs)
    assert all(w in text for w in words), text
    s = session.step(0.001, lateral=1e-3, rotation=0.01)  # the session goes on; poses within reach step
    assert math.isfinite(s.force_total) and s.depth == pytest.approx(0.001, abs=1e-4)


@pytest.mark.parametrize("kwargs, words", [
    ({"lateral": 1e9}, ["Session.step(lateral)", "entry face"]),
    ({"rotation": 1e9}, ["Session.step(rotation)"]),
    ({"tilt": 1e9}, ["Session.step(tilt)", "-1.5708 rad < tilt < 1.5708 rad"]),
    ({"depth": 1.0}, ["Session.step(depth)", "deeper than the needle is long"]),
])
def test_realtime3d_refuses_poses_outside_the_tissue(example, kwargs, words):
    session = needlesim.Session(example("realtime3d/quick_block.yaml"))
    args = dict({"depth": 0.0}, **kwargs)
    text = message(needlesim.InputError, session.step, **args)
    assert all(w in text for w in words), text


def test_a_step_too_short_for_a_finite_velocity(gelatin):
    session = needlesim.Session(gelatin)
    for k in range(101):
        session.step(k * 1e-4)  # 10 mm in, cutting
    text = message(needlesim.InputError, session.step, 0.0102, dt=5e-324)
    assert "Session.step(dt)" in text and "makes the tip velocity infinite" in text, text
    s = session.step(0.0102)
    assert math.isfinite(s.force_total) and s.phase == "cutting"


def test_needle_shape_points_are_bounded(coarse):
    text = message(needlesim.InputError, needlesim.Session(coarse).needle_shape, 2_000_000_000)
    assert "Session.needle_shape(count)" in text and "2 to 1000000" in text


# --- with_values: relative paths from the scenario's folder --------------------------------


def test_with_values_resolves_relative_paths_from_the_scenario_folder(example, tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)  # not the scenario's folder
    base = example("realtime2d/imported_block.yaml")  # tissue.geometry.file: imported_block.geo
    varied = base.with_values({"insertion.profile[0].insert.to": "10 mm"})
    geometry = os.path.normpath(str(SOURCE_DIR / "examples" / "realtime2d" / "imported_block.geo"))
    assert geometry in varied.yaml
    assert varied.duration == pytest.approx(1.1)  # (10 mm + 1 mm) at 10 mm/s
    # a relative path given among the values resolves from the scenario's folder too, and a
    # second with_values keeps it
    again = varied.with_values({"tissue.geometry.file": "imported_block.geo"}).with_values(
        {"insertion.profile[0].insert.to": "12 mm"})
    assert again.duration == pytest.approx(1.3) and geometry in again.yaml
    assert "missing.geo" in message(needlesim.InputError, base.with_values, {"tissue.geometry.file": "missing.geo"})
