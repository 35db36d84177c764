"""The package installs and imports without touching sys.path: `pip install .`
from the checkout into a fresh virtual environment (offline, Debian's
setuptools, the extension built in an existing CMake build folder), and
`cmake --install --component python` into one. Both import needlesim from
another folder with no PYTHONPATH and get NumPy arrays."""
import os
import pathlib
import subprocess
import sys

import pytest

from conftest import SOURCE_DIR

BUILD_DIR = os.environ.get("NEEDLESIM_CMAKE_BUILD_DIR")
CMAKE = os.environ.get("NEEDLESIM_CMAKE", "cmake")
pytestmark = pytest.mark.skipif(not BUILD_DIR, reason="needs NEEDLESIM_CMAKE_BUILD_DIR (CTest sets it)")

IMPORT_CHECK = """
import numpy, needlesim
r = needlesim.run(needlesim.default_scenario())
force = r.tables["forces"]["force_total"]
assert isinstance(force, numpy.ndarray) and force.dtype == numpy.float64 and len(force) > 1000
print(needlesim.__file__)
print(r.units["forces"]["force_total"], "%.4f" % r.results["exit_force"].value)
"""


def clean_env():
    env = {k: v for k, v in os.environ.items() if k not in ("PYTHONPATH", "PYTHONHOME", "PYTHONSTARTUP")}
    env["PIP_NO_INPUT"] = "1"
    env["PIP_CONFIG_FILE"] = os.devnull  # no find-links or index of this machine's pip configuration
    return env


def make_venv(folder):
    subprocess.run([sys.executable, "-m", "venv", "--system-site-packages", str(folder)], check=True)
    assert (folder / "pyvenv.cfg").is_file()
    return folder / "bin" / "python"


def run(command, **kwargs):
    p = subprocess.run([str(c) for c in command], capture_output=True, text=True, env=clean_env(), **kwargs)
    assert p.returncode == 0, "%s failed (%d):\n%s\n%s" % (command, p.returncode, p.stdout[-4000:], p.stderr[-4000:])
    return p.stdout


def check_import(python, venv, cwd):
    out = run([python, "-c", IMPORT_CHECK], cwd=cwd).splitlines()
    location = pathlib.Path(out[-2])
    assert location.parent.name == "needlesim" and venv in location.parents, out
    assert not str(location).startswith(str(SOURCE_DIR)), out
    assert out[-1] == "N 0.2989", out  # seed 003 eq 5.1: 0.04335 + 0.055 (3.791 + 285.053 x 0.003)


def test_pip_install_from_the_checkout(tmp_path):
    python = make_venv(tmp_path / "venv")
    env_build = {"NEEDLESIM_CMAKE_BUILD_DIR": BUILD_DIR, "NEEDLESIM_CMAKE": CMAKE}
    p = subprocess.run([str(python), "-m", "pip", "install", "--no-build-isolation", "--no-index", "--no-cache-dir",
                        str(SOURCE_DIR)],
                       capture_output=True, text=True, env=dict(clean_env(), **env_build), cwd=tmp_path)
    assert p.returncode == 0, p.stdout[-4000:] + p.stderr[-4000:]
    assert "Successfully installed needlesim-" in p.stdout
    (tmp_path / "elsewhere").mkdir()
    check_import(python, tmp_path / "venv", tmp_path / "elsewhere")


def test_cmake_install_into_a_venv(tmp_path):
    python = make_venv(tmp_path / "venv")
    out = run([CMAKE, "--install", BUILD_DIR, "--component", "python", "--prefix", tmp_path / "venv"])
    assert "site-packages/needlesim/_core" in out, out
    (tmp_path / "elsewhere").mkdir()
    check_import(python, tmp_path / "venv", tmp_path / "elsewhere")
