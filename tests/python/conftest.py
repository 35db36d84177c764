"""Shared fixtures of the Python tests (pytest; CTest runs them with the build
tree's package on PYTHONPATH, python/CMakeLists.txt)."""
import os
import pathlib

import pytest

import needlesim

SOURCE_DIR = pathlib.Path(os.environ.get("NEEDLESIM_SOURCE_DIR", pathlib.Path(__file__).resolve().parents[2]))


@pytest.fixture
def example():
    """example("mpm/quick_needle_block.yaml"): a scenario of examples/."""
    return lambda name: needlesim.load(SOURCE_DIR / "examples" / name)


@pytest.fixture
def gelatin(example):
    """Seed 003 section 5.1: 10 wt% gelatin, 18 G needle, 3 mm/s (lumped)."""
    return example("gelatin_18G_3mms.yaml")


def eq_5_1(depth, speed):
    """Seed 003 eq 5.1 for 10 wt% gelatin and the 18 G needle: F = 0.04335 + d (3.791 + 285.053 v) [N]."""
    return 0.04335 + depth * (3.791 + 285.053 * speed)
