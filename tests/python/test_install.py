"""The package installs and imports without touching sys.path: `pip install .`
from the checkout into a fresh virtual environment (offline, Debian's
setuptools, the extension built in an existing CMake build folder), the
README's install command as printed, and `cmake --install --component python`
into one. All import needlesim from another folder with no PYTHONPATH and get
NumPy arrays. A Python without wheel and NumPy is told so before anything is built."""
import os
import pathlib
import re
import subprocess
import sys
import time

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
    env = {k: v for k, v in os.environ.items()
           if k not in ("PYTHONPATH", "PYTHONHOME", "PYTHONSTARTUP") and not k.startswith("PIP_")}
    env["PIP_NO_INPUT"] = "1"
    env["PIP_CONFIG_FILE"] = os.devnull  # no find-links or index of this machine's pip configuration or PIP_*
    return env


def make_venv(folder):
    subprocess.run([sys.executable, "-m", "venv", "--system-site-packages", str(folder)], check=True)
    assert (folder / "pyvenv.cfg").is_file()
    return folder / "bin" / "python"


def run(command, **kwargs):
    p = subprocess.run([str(c) for c in command], capture_output=True, text=True, env=clean_env(),
                       start_new_session=True, **kwargs)
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
                       capture_output=True, text=True, env=dict(clean_env(), **env_build), cwd=tmp_path,
                       start_new_session=True)  # no terminal: setup.py's progress goes to pip's log
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


def readme_install_command():
    """The line of the README's section 'Use it from Python' that runs pip install."""
    text = (SOURCE_DIR / "README.md").read_text()
    section = text.split("## Use it from Python", 1)[1].split("\n## ", 1)[0]
    lines = [line for line in section.splitlines() if "pip install" in line]
    assert len(lines) == 1, lines
    return lines[0]


def checkout_view(folder):
    """folder with a link to each top-level entry of the checkout: the README's command can
    create its .venv there, and setup.py still finds the checkout (and its build/release)."""
    folder.mkdir()
    for entry in SOURCE_DIR.iterdir():
        if entry.name != ".venv":
            (folder / entry.name).symlink_to(entry)
    return folder


@pytest.mark.skipif(not BUILD_DIR or pathlib.Path(BUILD_DIR).resolve() != (SOURCE_DIR / "build" / "release").resolve(),
                    reason="the README's install reuses build/release; this build folder is elsewhere")
def test_readme_install_command_reuses_build_release(tmp_path):
    command = readme_install_command()
    checkout = checkout_view(tmp_path / "checkout")
    env = dict(clean_env(), PIP_NO_INDEX="1", PIP_VERBOSE="1")  # offline; setup.py's lines in the output
    env.pop("NEEDLESIM_CMAKE_BUILD_DIR", None)
    started = time.monotonic()
    p = subprocess.run(["bash", "-ec", command], capture_output=True, text=True, env=env, cwd=checkout,
                       start_new_session=True)
    seconds = time.monotonic() - started
    assert p.returncode == 0, command + "\n" + p.stdout[-4000:] + p.stderr[-4000:]
    said = [line.strip() for line in p.stderr.splitlines() if line.strip().startswith("setup.py: ")]  # pip -v
    assert "setup.py: reusing the build folder %s" % (SOURCE_DIR / "build" / "release") in "\n".join(said), said
    assert "Successfully installed needlesim-" in p.stdout
    (tmp_path / "elsewhere").mkdir()
    check_import(checkout / ".venv" / "bin" / "python", checkout / ".venv", tmp_path / "elsewhere")
    print("README install command: %.1f s" % seconds)


def test_missing_prerequisites_are_named_before_building(tmp_path):
    """A venv that does not see Debian's packages has pip and setuptools but neither wheel
    nor NumPy, like a pyenv or conda Python: setup.py names both and how to install them."""
    subprocess.run([sys.executable, "-m", "venv", str(tmp_path / "bare")], check=True)
    python = tmp_path / "bare" / "bin" / "python"
    started = time.monotonic()
    p = subprocess.run([str(python), "-m", "pip", "install", "--no-build-isolation", "--no-index", "--no-cache-dir",
                        str(SOURCE_DIR)], capture_output=True, text=True, env=clean_env(), cwd=tmp_path,
                       start_new_session=True)
    out = p.stdout + p.stderr
    assert p.returncode != 0, out[-4000:]
    assert "setup.py: cannot build needlesim with %s" % python in out, out[-4000:]
    assert "the package 'wheel'" in out and "NumPy" in out, out[-4000:]
    assert re.search(r"-m pip install wheel numpy\b", out), out[-4000:]
    assert "/usr/bin/python3 -m venv --system-site-packages .venv" in out, out[-4000:]
    assert " --build " not in out and " -S " not in out, out[-4000:]  # stopped before CMake ran
    assert time.monotonic() - started < 120, "setup.py should stop before building"
