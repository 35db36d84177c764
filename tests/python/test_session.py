"""needlesim.Session: the real-time engines stepped from Python agree with the
engine's own run of the same scenario (realtime2d) and with seed 003 eq 5.1
(lumped); bad arguments raise needlesim.InputError naming the argument."""
import math

import numpy as np
import pytest

import needlesim
from conftest import eq_5_1

SHORT = {"insertion.profile[0].insert.to": "20 mm"}
# A coarser mesh (8 mm spacing) where the mesh does not matter: a quicker set-up.
COARSE = dict(SHORT, **{"model.realtime2d.nodes_depth": 11, "model.realtime2d.nodes_lateral": 16})


@pytest.fixture
def thesis(example):
    """Seed 003 section 5.6 at 10 mm/s in realtime2d, inserted 20 mm."""
    return example("realtime2d/thesis_gelatin_18G_10mms.yaml").with_values(SHORT)


@pytest.fixture
def coarse(example):
    return example("realtime2d/thesis_gelatin_18G_10mms.yaml").with_values(COARSE)


def step_through_profile(scenario, session):
    """Steps the session as the engine does: every model.time_step, the profile's depth and angles."""
    steps = math.ceil(scenario.duration / session.dt - 1e-9)
    out = []
    for k in range(1, steps + 1):
        m = scenario.motion_at(min(k * session.dt, scenario.duration))
        out.append(session.step(m.depth, rotation=m.rotation, roll=m.roll))
    return out


def test_realtime2d_session_agrees_with_the_engine(thesis):
    run = needlesim.run(thesis, fields=True)
    session = needlesim.Session(thesis)
    assert session.engine == "realtime2d" and session.dt == pytest.approx(1e-3)
    steps = step_through_profile(thesis, session)
    last = steps[-1]
    f = run.tables["forces"]
    assert last.depth == pytest.approx(f["depth"][-1], abs=1e-12) == pytest.approx(0.020, abs=1e-9)
    assert last.force_total == pytest.approx(run.results["final_force"].value, rel=1e-12)
    assert last.tip_deflection == pytest.approx(run.results["final_tip_deflection"].value, rel=1e-12)
    assert last.force_lateral == pytest.approx(f["force_lateral"][-1], rel=1e-9)
    for name in ("force_stiffness", "force_cutting", "force_friction"):
        assert getattr(last, name) == pytest.approx(f[name][-1], rel=1e-9, abs=1e-15)
    np.testing.assert_allclose(last.tip_position, [f["tip_x"][-1], f["tip_y"][-1], 0.0], atol=1e-12)
    assert last.phase == "cutting"
    assert sum(s.punctured_now for s in steps) == 1
    # The tissue: the session's node displacements are the engine's last field step.
    tissue = run.fields["tissue"]
    np.testing.assert_allclose(session.points, tissue.points[:, :2], atol=1e-12)
    np.testing.assert_array_equal(session.cells, tissue.cells)
    u = tissue[-1].point_data["displacement"]
    np.testing.assert_allclose(session.displacement, u[:, :2], atol=1e-12)
    assert np.abs(session.displacement).max() > 1e-4  # the needle drags the gel by a fraction of a mm


def test_realtime2d_session_arrays(coarse):
    session = needlesim.Session(coarse)
    n = len(session.points)
    assert session.points.shape == (n, 2) == session.displacement.shape
    assert session.cells.shape == (10 * 15, 4) and n == 11 * 16
    assert not session.displacement.any()
    shape = session.needle_shape(11)
    assert shape.shape == (11, 2)
    np.testing.assert_allclose(np.linalg.norm(shape[-1] - shape[0]), 0.1, rtol=1e-12)  # 100 mm straight needle


def test_lumped_session_exit_force_is_eq_5_1(gelatin):
    session = needlesim.Session(gelatin)
    assert session.engine == "lumped"
    steps = step_through_profile(gelatin, session)
    exit_step = next(k for k, s in enumerate(steps) if s.depth >= 0.055)
    inside = steps[:exit_step]
    assert inside[-1].force_total == pytest.approx(eq_5_1(0.055, 0.003), rel=2e-3)
    assert inside[-1].force_total == pytest.approx(needlesim.run(gelatin).results["exit_force"].value, rel=1e-12)
    s = inside[-1]
    assert s.force_total == pytest.approx(s.force_stiffness + s.force_cutting + s.force_friction)
    assert s.force_lateral == 0.0 and s.tip_deflection == 0.0 and s.phase == "cutting"
    np.testing.assert_allclose(s.tip_position, [s.depth, 0.0, 0.0], atol=1e-12)
    assert steps[exit_step].phase == "through"
    with pytest.raises(needlesim.InputError, match="the lumped engine has no tissue mesh"):
        session.points


def test_lumped_session_takes_a_velocity(gelatin):
    session = needlesim.Session(gelatin)
    for k in range(20001):  # 20 mm at 1 mm/s, 1 kHz
        s = session.step(k * 1e-6, 1e-3, velocity=1e-3)
    assert s.force_total == pytest.approx(eq_5_1(0.02, 1e-3), abs=1e-3)
    assert s.time == pytest.approx(20.001)


@pytest.mark.parametrize("kwargs, words", [
    ({"depth": float("nan")}, ["Session.step(depth)", "nan", "finite"]),
    ({"depth": 0.0, "dt": 0.0}, ["Session.step(dt)", "'0'", "> 0"]),
    ({"depth": 0.0, "dt": -1e-3}, ["Session.step(dt)", "'-0.001'", "> 0"]),
    ({"depth": 0.0, "dt": float("inf")}, ["Session.step(dt)", "inf", "finite"]),
    ({"depth": 0.0, "rotation": float("nan")}, ["Session.step(rotation)", "finite"]),
    ({"depth": 0.0, "velocity": 1e-3}, ["Session.step(velocity)", "realtime2d takes the velocity"]),
])
def test_realtime2d_session_refuses_bad_arguments(coarse, kwargs, words):
    with pytest.raises(needlesim.InputError) as e:
        needlesim.Session(coarse).step(**kwargs)
    assert all(w in str(e.value) for w in words), str(e.value)


def test_a_session_refuses_a_jump_its_steps_cannot_resolve(coarse):
    session = needlesim.Session(coarse)
    session.step(0.0)
    with pytest.raises(needlesim.InputError) as e:
        session.step(0.010)
    assert "moves the tip 10 mm in one step (from 0 mm)" in str(e.value)
    assert "at most 4 mm per step (0.5 x the node spacing" in str(e.value)
    session.step(0.001)  # the session goes on after a refused step


@pytest.mark.parametrize("kwargs, words", [
    ({"depth": 0.0, "lateral": 1e-3}, ["Session.step(lateral)", "along its axis only"]),
    ({"depth": 0.0, "velocity": float("-inf")}, ["Session.step(velocity)", "finite"]),
])
def test_lumped_session_refuses_bad_arguments(gelatin, kwargs, words):
    with pytest.raises(needlesim.InputError) as e:
        needlesim.Session(gelatin).step(**kwargs)
    assert all(w in str(e.value) for w in words), str(e.value)


def test_other_engines_cannot_be_stepped(example):
    with pytest.raises(needlesim.InputError) as e:
        needlesim.Session(example("mpm/quick_needle_block.yaml"))
    assert "model.engine" in str(e.value) and "lumped, realtime2d or realtime3d" in str(e.value)
    assert "quick_needle_block.yaml:" in str(e.value)


def test_step_session_and_motion_reprs(coarse):
    session = needlesim.Session(coarse)
    assert repr(session) == "<Session realtime2d 'realtime2d_thesis_10mms': t=0 s, not stepped yet>"
    assert repr(session.step(coarse.motion_at(0.001).depth)).startswith("<SessionStep t=0.001 s depth=-0.99 mm")
    assert repr(session) == "<Session realtime2d 'realtime2d_thesis_10mms': t=0.001 s, depth=-0.99 mm>"
    assert session.time == pytest.approx(0.001) and session.depth == pytest.approx(-0.99e-3)
    assert repr(coarse.motion_at(1.0)) == "<MotionSample t=1 s depth=9 mm velocity=10 mm/s rotation=0 rad roll=0 rad>"


def test_realtime3d_session_agrees_with_the_engine_and_steers_out_of_plane(example):
    """realtime3d from Python: the same numbers as its engine run; tilt and the 3D mesh arrays."""
    scenario = example("realtime3d/quick_block.yaml")
    run = needlesim.run(scenario, fields=True)
    session = needlesim.Session(scenario)
    assert session.engine == "realtime3d"
    last = step_through_profile(scenario, session)[-1]
    f = run.tables["forces"]
    assert last.force_total == pytest.approx(run.results["final_force"].value, rel=1e-12)
    assert last.tip_deflection == pytest.approx(run.results["final_tip_deflection"].value, rel=1e-12)
    assert last.tip_deflection_z == pytest.approx(run.results["final_tip_deflection_z"].value, rel=1e-12)
    np.testing.assert_allclose(last.tip_position, [f["tip_x"][-1], f["tip_y"][-1], f["tip_z"][-1]], atol=1e-12)
    # The quarter turn of the bevel bends the needle out of the plane, towards -z.
    assert last.tip_deflection_z < -1e-5
    tissue = run.fields["tissue"]
    n = len(session.points)
    assert session.points.shape == (n, 3) and session.displacement.shape == (n, 3)
    np.testing.assert_allclose(session.points, tissue.points, atol=1e-12)
    np.testing.assert_allclose(session.displacement, tissue[-1].point_data["displacement"], atol=1e-12)
    assert session.cells.shape[1] == 4 and session.surface.shape[1] == 3
    assert session.needle_shape(11).shape == (11, 3)
    # A tilt out of the insertion plane about the tip: the shaft inside swings to -z, the tissue
    # pushes it back along +z.
    tilted = needlesim.Session(scenario)
    for k in range(1, 1001):
        tilted.step(-1e-3 + 20e-3 * k / 1000)
    for k in range(1, 201):
        s = tilted.step(19e-3, tilt=0.02 * k / 200)
    assert s.force_out_of_plane > 1e-3


def test_tilt_is_refused_by_the_2d_engines(coarse):
    session = needlesim.Session(coarse)
    with pytest.raises(needlesim.InputError, match="tilt"):
        session.step(0.0, tilt=0.1)


def test_realtime3d_session_inclusions_are_the_engines(example):
    """Session.inclusions on the tumour target: the scenario's entry and the nodes of its material
    (as the C++ API gives a viewer); after the profile, the displaced centre is the centre plus the
    mean displacement of those nodes, and the miss from the end of the needle's centre line is the
    engine run's tumour_miss_distance and tumour_miss_from_axis."""
    # A quicker run: the direct back-end (no modes to find on this small block), 5 ms steps.
    scenario = example("realtime3d/tumour_target.yaml").with_values(
        {"model.realtime3d.solver": "direct", "model.time_step": "5 ms"})
    session = needlesim.Session(scenario)
    (tumour,) = session.inclusions
    assert isinstance(tumour, needlesim.Inclusion)
    assert (tumour.name, tumour.shape, tumour.target) == ("tumour", "sphere", True)
    np.testing.assert_allclose(tumour.centre, [0.025, 0.002, 0.0], atol=1e-12)
    assert tumour.radius == pytest.approx(0.006, rel=1e-12)
    # Its material: the nodes of the elements whose centre lies in the sphere, each within the
    # radius and one element diameter of the centre.
    cells = session.cells
    points = session.points
    diameter = max(np.linalg.norm(points[c[i]] - points[c[j]]) for c in cells for i in range(4) for j in range(i))
    assert len(tumour.region) > 0
    assert np.linalg.norm(points[tumour.region] - tumour.centre, axis=1).max() <= tumour.radius + diameter
    np.testing.assert_array_equal(tumour.displaced_centre, tumour.centre)
    assert tumour.miss is None and tumour.miss_from_axis is None  # not stepped: no needle yet

    step_through_profile(scenario, session)
    (tumour,) = session.inclusions
    moved = tumour.centre + session.displacement[tumour.region].mean(axis=0)
    np.testing.assert_allclose(tumour.displaced_centre, moved, atol=1e-15)
    assert np.linalg.norm(moved - tumour.centre) > 1e-5  # the needle pushes the tumour by tens of um
    shape = session.needle_shape(41)
    tip, axis = shape[-1], (shape[-1] - shape[-2]) / np.linalg.norm(shape[-1] - shape[-2])
    d = moved - tip
    assert tumour.miss == pytest.approx(np.linalg.norm(d), rel=1e-12)
    assert tumour.miss_from_axis == pytest.approx(np.linalg.norm(d - d.dot(axis) * axis), rel=1e-12)
    run = needlesim.run(scenario)
    assert tumour.miss == pytest.approx(run.results["tumour_miss_distance"].value, rel=1e-9)
    assert tumour.miss_from_axis == pytest.approx(run.results["tumour_miss_from_axis"].value, rel=1e-9)
    assert "miss=" in repr(tumour) and "'tumour' (target)" in repr(tumour)


def test_lumped_session_inclusions_have_no_region(example):
    """The lumped model has no mesh: the inclusion as the scenario gives it, not moved, no miss."""
    scenario = example("realtime2d/layered_target.yaml").with_values({"model.engine": "lumped"})
    session = needlesim.Session(scenario)
    session.step(-0.5e-3)
    (vessel,) = session.inclusions
    assert (vessel.name, vessel.shape) == ("target", "cylinder")
    assert len(vessel.region) == 0 and vessel.miss is None
    np.testing.assert_array_equal(vessel.displaced_centre, vessel.centre)
