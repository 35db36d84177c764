"""Every engine runs from Python; the engines that write fields give them back as
arrays whose shapes agree (points x dim, a step's point data one row per point,
cell data one row per cell) and whose values agree with each other."""
import math

import numpy as np
import pytest

import needlesim

# The quickest scenario of each engine (shortened where that keeps it meaningful).
QUICK = {
    "lumped": ("gelatin_18G_3mms.yaml", {}),
    "realtime2d": ("realtime2d/thesis_gelatin_18G_10mms.yaml", {"insertion.profile[0].insert.to": "20 mm"}),
    "realtime3d": ("realtime3d/quick_block.yaml", {}),
    "kinematic": ("steering/table2_gelC_054_kinematic.yaml", {}),
    "energy": ("steering/table2_gelC_054_energy.yaml", {}),
    "beam-foundation": ("steering/table2_gelC_054_beam_foundation.yaml", {}),
    "explicit": ("explicit/deformable_needle_2d.yaml", {}),
    "mpm": ("mpm/quick_needle_block.yaml", {}),
}
WRITES_FIELDS = {"realtime2d", "realtime3d", "explicit", "mpm"}


def test_every_engine_of_this_build_has_a_quick_scenario():
    assert sorted(needlesim.engines()) == sorted(QUICK)


@pytest.fixture(scope="module")
def runs():
    """Each engine's quick scenario run once with fields=True."""
    cache = {}

    def get(engine, example_dir):
        if engine not in cache:
            name, values = QUICK[engine]
            s = needlesim.load(example_dir / name)
            cache[engine] = needlesim.run(s.with_values(values) if values else s, fields=True)
        return cache[engine]

    return get


@pytest.fixture
def run_of(runs):
    from conftest import SOURCE_DIR
    return lambda engine: runs(engine, SOURCE_DIR / "examples")


@pytest.mark.parametrize("engine", sorted(QUICK))
def test_engine_runs_with_tables_as_arrays(run_of, engine):
    r = run_of(engine)
    assert r.engine == engine and r.status == "complete" and r.folder is None
    assert r.tables and all(isinstance(t.data, np.ndarray) and len(t) > 0 for name, t in r.tables.items()
                            if name not in ("fracture",))
    assert all(q.unit for q in r.results.values())
    assert bool(r.fields) == (engine in WRITES_FIELDS), list(r.fields)


def check_series_shapes(series):
    assert len(series) > 1 and np.all(np.diff(series.times) > 0)
    dim = series.points.shape[1]
    assert series.points.ndim == 2 and dim in (2, 3)
    for step in series:
        n = len(step.points)
        assert step.points.shape == (n, dim) and np.isfinite(step.points).all()
        if step.cells is not None:
            assert step.cells.ndim == 2 and step.cells.min() >= 0 and step.cells.max() < n
        for name, a in step.point_data.items():
            assert a.shape[0] == n and np.isfinite(a).all(), (series.name, name, a.shape, n)
        for name, a in step.cell_data.items():
            cells = n if step.cells is None else len(step.cells)
            assert a.shape[0] == cells and np.isfinite(a).all(), (series.name, name, a.shape, cells)


def check_points_are_the_reference(series):
    """A series with a displacement keeps its reference points at every step (Warp By Vector
    by the displacement gives the deformed shape)."""
    if "displacement" not in series.point_data_names():
        return
    for step in series:
        np.testing.assert_array_equal(step.points, series.points)


@pytest.mark.parametrize("engine", sorted(WRITES_FIELDS))
def test_fields_are_arrays_with_consistent_shapes(run_of, engine):
    r = run_of(engine)
    for series in r.fields.values():
        check_series_shapes(series)
        check_points_are_the_reference(series)
        if "displacement" in series.point_data_names():
            assert series.units["displacement"] == "m", series.units
        for name in series.point_data_names():
            stacked = series.point_data(name)
            assert stacked.shape[:2] == (len(series), len(series.points))


def test_fields_end_at_the_end_of_the_run(run_of):
    for engine in sorted(WRITES_FIELDS):
        r = run_of(engine)
        end = r.tables["forces"]["time"][-1]
        for series in r.fields.values():
            assert series.times[0] == pytest.approx(0.0, abs=1e-12)
            assert series.times[-1] == pytest.approx(end, rel=1e-6), (engine, series.name)


def test_mpm_particles_move_as_the_needle_pushes(run_of):
    """The particles beside the needle move with it: the largest displacement is a sizeable part of the 5 mm stroke."""
    particles = run_of("mpm").fields["particles"]
    u = particles.point_data("displacement")
    assert u.shape[-1] == particles.points.shape[1] == 3
    assert 0.1e-3 < np.linalg.norm(u[-1], axis=1).max() < 5e-3


def test_realtime2d_needle_field_ends_at_the_tip(run_of):
    r = run_of("realtime2d")
    f = r.tables["forces"]
    needle = r.fields["needle"]
    np.testing.assert_allclose(needle[-1].points[-1, :2], [f["tip_x"][-1], f["tip_y"][-1]], atol=1e-9)


def test_kinematic_tip_is_on_the_circle_of_its_curvature(run_of):
    """Webster's model at constant curvature: the tip lies on a circle of radius 1/kappa (seed 002 Table 2)."""
    r = run_of("kinematic")
    radius, length = 1 / 4.1667, r.results["inserted_length"].value
    tip = r.tables["tip_path"]
    assert tip["tip_x"][-1] == pytest.approx(radius * math.sin(length / radius), rel=1e-5)
    assert abs(tip["tip_y"][-1]) == pytest.approx(radius * (1 - math.cos(length / radius)), rel=1e-5)


def test_a_run_into_a_folder_reads_its_fields_from_the_files(example, tmp_path):
    r = needlesim.run(example("mpm/quick_needle_block.yaml"), out=tmp_path / "mpm")
    assert r.fields["particles"].path == tmp_path / "mpm" / "particles.xdmf"
    assert r.fields["particles"][-1].point_data["displacement"].shape == (len(r.fields["particles"].points), 3)
    assert "particles" in repr(r) and "<FieldSeries 'particles': %d steps" % len(r.fields["particles"]) in repr(r.fields["particles"])


def test_an_unknown_field_array_names_those_there(run_of):
    particles = run_of("mpm").fields["particles"]
    with pytest.raises(needlesim.UnknownNameError, match="has no point data 'pressure'; it has: .*displacement"):
        particles.point_data("pressure")
