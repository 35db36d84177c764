"""needlesim.plan (docs/planning.md): the gel example planned from Python, and a scenario
without a plan section refused."""
import pytest

import needlesim


def test_the_gel_example_is_planned_around_the_vessel(example):
    r = needlesim.plan(example("planning/gel_block.yaml"))
    assert r.results["feasible"].value == 1.0
    assert r.results["clearance_vessel"].value >= 2e-3
    assert r.results["closed_loop_error_p95"].value < 1e-3
    path = r.tables["path"]
    assert len(path["x"]) > 10 and min(path["clearance"]) >= 2e-3


def test_a_scenario_without_a_plan_section_is_an_input_error(gelatin):
    with pytest.raises(needlesim.InputError, match="no plan section"):
        needlesim.plan(gelatin)
