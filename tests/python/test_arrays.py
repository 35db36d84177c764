"""Results as NumPy arrays: tables by column with units, key results with units,
the same numbers from memory and from a results folder, readable reprs."""
import numpy as np
import pytest

import needlesim
from conftest import eq_5_1


@pytest.fixture
def lumped_run(gelatin):
    return needlesim.run(gelatin)


def test_table_columns_are_float_arrays_with_units(lumped_run):
    forces = lumped_run.tables["forces"]
    total = forces["force_total"]
    assert isinstance(total, np.ndarray) and total.dtype == np.float64 and total.ndim == 1
    assert len(total) == len(forces) == forces.data.shape[0] > 1000
    assert forces.data.shape[1] == len(forces.columns)
    assert lumped_run.units["forces"]["force_total"] == "N"
    assert forces.units["depth"] == "m" and forces.units["time"] == "s" and forces.units["phase"] == "1"
    assert forces.columns[:4] == ["time", "depth", "velocity", "force_total"]


def test_force_columns_follow_eq_5_1_while_cutting(lumped_run):
    """Seed 003 eq 5.1 at every sample of steady cutting at 3 mm/s (10 to 50 mm)."""
    f = lumped_run.tables["forces"]
    cutting = (f["phase"] == 2) & (f["depth"] > 0.010) & (f["depth"] < 0.050)
    assert cutting.sum() > 1000
    np.testing.assert_allclose(f["force_total"][cutting], eq_5_1(f["depth"][cutting], 0.003), rtol=3e-3)
    np.testing.assert_allclose(f["force_total"], f["force_stiffness"] + f["force_cutting"] + f["force_friction"],
                               rtol=1e-12, atol=1e-15)


def test_key_results_are_values_with_units(lumped_run):
    q = lumped_run.results["exit_force"]
    value, unit = q
    assert isinstance(q, needlesim.Quantity) and unit == "N" and float(q) == value == q.value
    assert value == pytest.approx(eq_5_1(0.055, 0.003), rel=2e-3)
    assert "exit face" in q.meaning
    assert str(q) == "%.6g N" % value
    assert str(lumped_run.results["punctures"]) == "1"


def test_mapping_access_reaches_the_same_arrays(lumped_run):
    assert lumped_run["tables"]["forces"]["force_total"] is not None
    np.testing.assert_array_equal(lumped_run["tables"]["forces"]["force_total"],
                                  lumped_run.tables["forces"]["force_total"])
    assert lumped_run["results"]["exit_force"] == lumped_run.results["exit_force"]


def test_an_unknown_column_names_the_columns(lumped_run):
    with pytest.raises(needlesim.UnknownNameError, match="table 'forces' has no column 'force'; its columns: time, depth"):
        lumped_run.tables["forces"]["force"]


def test_reprs_say_what_is_inside(lumped_run):
    text = repr(lumped_run)
    assert text.startswith("<needlesim.Results of 'gelatin_18G_3mms' (lumped), complete")
    assert "exit_force = 0.29" in text and "forces (%d x 14)" % len(lumped_run.tables["forces"]) in text
    assert repr(lumped_run.tables["forces"]).startswith(
        "<Table 'forces': %d rows; time [s], depth [m], velocity [m/s], force_total [N]" % len(lumped_run.tables["forces"]))


def test_a_results_folder_reads_back_the_same_numbers(gelatin, lumped_run, tmp_path):
    folder = needlesim.run(gelatin, out=tmp_path / "run")
    again = needlesim.open_results(tmp_path / "run")
    for r in (folder, again):
        assert r.engine == "lumped" and r.name == "gelatin_18G_3mms" and r.status == "complete"
        assert r.units == lumped_run.units
        assert set(r.results) == set(lumped_run.results)
        for key, q in lumped_run.results.items():
            assert r.results[key].unit == q.unit and r.results[key].value == pytest.approx(q.value, rel=1e-12)
        for name, t in lumped_run.tables.items():
            np.testing.assert_allclose(r.tables[name].data, t.data, rtol=1e-9, atol=1e-15)  # CSV: 10 digits
    for name, t in lumped_run.tables.items():  # the run's own tables, not the CSV's digits
        np.testing.assert_array_equal(folder.tables[name].data, t.data)
    assert repr(folder).endswith("folder: %s>" % (tmp_path / "run"))


def test_open_results_refuses_a_folder_without_summary(tmp_path):
    with pytest.raises(needlesim.NotFoundError, match="not a needlesim results folder: it has no summary.json"):
        needlesim.open_results(tmp_path)


def test_run_refuses_what_is_not_a_scenario():
    with pytest.raises(needlesim.ArgumentTypeError, match="scenario must be a needlesim.Scenario"):
        needlesim.run("examples/gelatin_18G_3mms.yaml")


@pytest.mark.parametrize("env_set, expected", [({}, "GOMP_SPINCOUNT=1000"),
                                               ({"OMP_WAIT_POLICY": "active"}, "OMP_WAIT_POLICY=active")])
def test_the_package_shortens_openmps_spin_unless_the_caller_chose(tmp_path, env_set, expected):
    """libgomp reads its wait settings when the extension loads: the package sets GOMP_SPINCOUNT
    first (apps/needlesim/openmp_wait.cpp says why), keeps a caller's own, and summary.json says which."""
    import json, os, subprocess, sys
    from conftest import SOURCE_DIR
    env = {k: v for k, v in os.environ.items() if k not in ("OMP_WAIT_POLICY", "GOMP_SPINCOUNT")} | env_set
    code = "import sys, needlesim; needlesim.run(needlesim.load(sys.argv[1]), out=sys.argv[2])"
    subprocess.run([sys.executable, "-c", code, str(SOURCE_DIR / "examples" / "gelatin_18G_3mms.yaml"),
                    str(tmp_path / "run")], env=env, check=True, capture_output=True)
    assert json.loads((tmp_path / "run" / "summary.json").read_text())["needlesim"]["openmp_wait"] == expected
