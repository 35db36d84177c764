"""Scenarios: loading files and text, parameter variation with with_values, the
seed 003 numbers of a run in memory, bad input raising needlesim.InputError."""
import pathlib

import pytest

import needlesim
from conftest import SOURCE_DIR, eq_5_1


def test_load_a_scenario_file(gelatin):
    assert gelatin.name == "gelatin_18G_3mms" and gelatin.engine == "lumped"
    assert repr(gelatin) == "<Scenario 'gelatin_18G_3mms' (lumped), 53.3333 s, from %s>" % (
        SOURCE_DIR / "examples" / "gelatin_18G_3mms.yaml")


def test_exit_force_is_eq_5_1(gelatin):
    exit_force, unit = needlesim.run(gelatin).results["exit_force"]
    assert unit == "N"
    assert exit_force == pytest.approx(eq_5_1(0.055, 0.003), rel=2e-3)


def test_a_plain_run_has_notes_and_no_warning(gelatin):
    r = needlesim.run(gelatin)
    assert r.warnings == [] and len(r.notes) > 0


def test_a_run_that_is_not_quasi_static_says_so(example):
    r = needlesim.run(example("explicit/target_inclusion_2d.yaml"))
    assert any("not quasi-static" in w for w in r.warnings), r.warnings


def test_with_values_changes_the_speed(gelatin):
    fast = gelatin.with_values({"insertion.profile[0].insert.speed": "10 mm/s"})
    assert needlesim.run(fast).results["exit_force"].value == pytest.approx(eq_5_1(0.055, 0.010), abs=2e-3)


def test_with_values_takes_numbers_and_writes_sections_the_base_omits(gelatin):
    assert "poisson: 0.31" in gelatin.with_values({"needle.poisson": 0.31}).yaml
    assert "relaxation_time: 0.5 s" in gelatin.with_values({"model.lumped.relaxation_time": "0.5 s"}).yaml


def test_exception_classes():
    assert issubclass(needlesim.InputError, ValueError)
    assert issubclass(needlesim.SolverError, RuntimeError)


SPEED = "insertion.profile[%s].insert.speed"


@pytest.mark.parametrize("values, words", [
    ({"tissue.friction.C_p": "-1 N/m"}, ["tissue.friction.C_p"]),
    ({SPEED % "99999999999": "1 mm/s"}, ["has no entry [99999999999]", "an index from 0 to"]),
    ({SPEED % "x": "1 mm/s"}, ["'x' is not an index", "character 19"]),
    ({SPEED % "-1": "1 mm/s"}, ["'-1' is not an index"]),
    ({"insertion.profile[0]junk.insert.speed": "1 mm/s"}, ["'junk' follows ']'"]),
    ({"tissue.friction.Cp": "3 N/m"}, ["did you mean 'C_p'?", "b_p"]),
    ({"tissue.friction.C_p": float("nan")}, ["with_values(tissue.friction.C_p)", "nan", "finite"]),
])
def test_bad_with_values_raise_input_error(gelatin, values, words):
    with pytest.raises(needlesim.InputError) as e:
        gelatin.with_values(values)
    assert all(w in str(e.value) for w in words), str(e.value)


def test_load_paths_with_colons_and_pathlib(tmp_path):
    colon = tmp_path / "a:b.yaml"
    colon.write_text((SOURCE_DIR / "examples" / "gelatin_18G_3mms.yaml").read_text())
    assert needlesim.load(str(colon)).name == "gelatin_18G_3mms"
    assert needlesim.load(colon).name == "gelatin_18G_3mms"


@pytest.mark.parametrize("what, words", [
    (lambda d: str(d / "x:missing.yaml"), ["file not found"]),
    (lambda d: d / "missing", ["file not found"]),
    (lambda d: str(d), ["is a folder"]),
    (lambda d: "tissue: [1", ["<python>:1:", "not valid YAML"]),
])
def test_load_refuses_bad_input(tmp_path, what, words):
    with pytest.raises(needlesim.InputError) as e:
        needlesim.load(what(tmp_path))
    assert all(w in str(e.value) for w in words), str(e.value)


@pytest.mark.parametrize("args, words", [
    ((float("nan"), 1e-3, 1e-3), ["LumpedForceModel.step(depth)", "nan", "finite"]),
    ((0.0, float("inf"), 1e-3), ["LumpedForceModel.step(velocity)", "inf", "finite"]),
    ((0.0, 1e-3, 0.0), ["LumpedForceModel.step(dt)", "'0'", "> 0"]),
    ((0.0, 1e-3, -1e-3), ["LumpedForceModel.step(dt)", "'-0.001'", "> 0"]),
])
def test_lumped_force_model_refuses_bad_steps(gelatin, args, words):
    with pytest.raises(needlesim.InputError) as e:
        needlesim.LumpedForceModel(gelatin).step(*args)
    assert all(w in str(e.value) for w in words), str(e.value)


def test_lumped_force_model_steps_to_eq_5_1(gelatin):
    m = needlesim.LumpedForceModel(gelatin)
    for k in range(20000):  # 20 mm at 1 mm/s, 1 kHz
        total, stiffness, cutting, friction = m.step(k * 1e-6, 1e-3, 1e-3)
    assert total == pytest.approx(eq_5_1(0.02, 1e-3), abs=1e-3)
    assert total == pytest.approx(stiffness + cutting + friction)


@pytest.mark.parametrize("to_path", [str, pathlib.Path])
def test_run_to_a_results_folder(gelatin, tmp_path, to_path):
    r = needlesim.run(gelatin, out=to_path(tmp_path / "run"))
    assert (r.folder / "summary.json").is_file()
    assert r.folder == tmp_path / "run"


def test_run_to_an_existing_folder_needs_overwrite(gelatin, tmp_path):
    needlesim.run(gelatin, out=tmp_path / "run")
    with pytest.raises(Exception, match="already exists"):
        needlesim.run(gelatin, out=tmp_path / "run")
    assert needlesim.run(gelatin, out=tmp_path / "run", overwrite=True).status == "complete"
