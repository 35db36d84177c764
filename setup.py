"""Builds the extension needlesim._core with CMake for `pip install .` (pyproject.toml).

Before anything is built, setup.py checks what the build needs (setuptools' bdist_wheel
or the package wheel, NumPy, Python's headers, cmake, a C++ compiler) and stops with one
message naming each missing piece and the command that installs it.

The CMake build folder, first match:
  - NEEDLESIM_CMAKE_BUILD_DIR, an existing configured build folder (the tests use it);
  - build/release (cmake --preset release) when it was configured from this checkout
    for a Python with the same extension suffix: only the target needlesim_python is
    built there, so an up-to-date build is reused;
  - build/python, configured here without tests and benchmarks (ccache reuses the
    objects of other builds).
pip hides the output of setup.py unless it fails or runs with -v, so the choice of
folder and the compiler's progress go to the terminal (/dev/tty) when there is one.
"""
import os
import pathlib
import re
import shutil
import subprocess
import sys
import sysconfig

from setuptools import Extension, setup
from setuptools.command.build_ext import build_ext

ROOT = pathlib.Path(__file__).resolve().parent
TARGET = "needlesim_python"
DEBIAN_PYTHON = "/usr/bin/python3"
CMAKE_MINIMUM = re.search(r"cmake_minimum_required\(VERSION ([0-9.]+)",
                          (ROOT / "CMakeLists.txt").read_text()).group(1)


def project_version():
    match = re.search(r"project\(needlesim VERSION ([0-9.]+)", (ROOT / "CMakeLists.txt").read_text())
    if not match:
        sys.exit("setup.py: no 'project(needlesim VERSION x.y.z)' in %s" % (ROOT / "CMakeLists.txt"))
    return match.group(1)


def open_terminal():
    """The terminal pip runs on, when pip captures this script's output; else None."""
    if sys.stdout.isatty():
        return None
    try:
        return open("/dev/tty", "w")
    except OSError:
        return None


TERMINAL = open_terminal()


def say(text):
    """A line for the user: on the terminal when there is one, and in pip's log."""
    print("setup.py:", text, flush=True)
    if TERMINAL:
        TERMINAL.write("\nneedlesim setup.py: %s\n" % text)
        TERMINAL.flush()


# ---------------------------------------------------------------- prerequisites

def pip_install(package):
    return "%s -m pip install %s" % (sys.executable, package)


def has_module(name):
    try:
        __import__(name)
        return True
    except ImportError:
        return False


def missing_python_parts():
    """(what, how to get it) for each Python-side piece this interpreter lacks."""
    import setuptools
    missing = []
    if not (has_module("setuptools.command.bdist_wheel") or has_module("wheel")):
        missing.append(("the package 'wheel' (setuptools %s has no bdist_wheel)" % setuptools.__version__,
                        pip_install("wheel")))
    isolated = "pip-build-env" in setuptools.__file__  # pip installs the run dependencies itself
    if not isolated and not has_module("numpy"):
        missing.append(("NumPy", pip_install("numpy")))
    headers = pathlib.Path(sysconfig.get_paths()["include"]) / "Python.h"
    if not headers.is_file():
        missing.append(("Python's C headers (%s)" % headers, "Debian: apt install python3-dev"))
    return missing


def cmake_version(cmake):
    out = subprocess.run([cmake, "--version"], capture_output=True, text=True).stdout
    match = re.search(r"version ([0-9]+)\.([0-9]+)", out)
    return tuple(int(x) for x in match.groups()) if match else (0, 0)


def missing_build_tools():
    """(what, how to get it) for cmake and the C++ compiler when they are not there."""
    missing = []
    cmake = os.environ.get("NEEDLESIM_CMAKE") or shutil.which("cmake")
    needed = tuple(int(x) for x in CMAKE_MINIMUM.split(".")[:2])
    if not cmake:
        missing.append(("cmake %s or newer" % CMAKE_MINIMUM, "Debian: apt install cmake"))
    elif cmake_version(cmake) < needed:
        missing.append(("cmake %s or newer (%s is %s)" % (CMAKE_MINIMUM, cmake, ".".join(map(str, cmake_version(cmake)))),
                        "Debian: apt install cmake"))
    compiler = os.environ.get("CXX") or shutil.which("c++") or shutil.which("g++") or shutil.which("clang++")
    if not compiler:
        missing.append(("a C++20 compiler", "Debian: apt install g++"))
    return missing


def check_prerequisites():
    """Stops with one message when anything the build needs is missing."""
    missing = missing_python_parts() + missing_build_tools()
    if not missing:
        return
    lines = ["cannot build needlesim with %s (Python %s); missing:" % (sys.executable, sys.version.split()[0])]
    lines += ["  - %s: %s" % item for item in missing]
    pip_packages = [how.split()[-1] for what, how in missing if " -m pip install " in how]
    if len(pip_packages) > 1:
        lines.append("pip installs them from a package index: %s" % pip_install(" ".join(pip_packages)))
    if os.path.exists(DEBIAN_PYTHON):
        lines.append("Debian's Python has all of it offline (scripts/bootstrap.sh installs the packages):")
        lines.append("  %s -m venv --system-site-packages .venv && .venv/bin/pip install --no-build-isolation ."
                     % DEBIAN_PYTHON)
    sys.exit("setup.py: " + "\n".join(lines))


# ---------------------------------------------------------------- build folder

def cmake():
    return os.environ.get("NEEDLESIM_CMAKE") or shutil.which("cmake")


def run(command, **kwargs):
    print("setup.py:", " ".join(str(c) for c in command), flush=True)
    subprocess.run([str(c) for c in command], check=True, **kwargs)


def read_cache(folder):
    """The entries of folder/CMakeCache.txt as name -> value, {} when it is not a configured folder."""
    try:
        text = (folder / "CMakeCache.txt").read_text(errors="replace")
    except OSError:
        return {}
    return dict(re.findall(r"^([A-Za-z_][^:=\n]*):[A-Z_]+=(.*)$", text, re.MULTILINE))


def extension_suffix_of(python):
    p = subprocess.run([python, "-c", "import sysconfig; print(sysconfig.get_config_var('EXT_SUFFIX'))"],
                       capture_output=True, text=True)
    return p.stdout.strip() if p.returncode == 0 else None


def release_folder_reason(folder, cache):
    """Why folder (build/release) cannot serve this install, or None when it can."""
    if not cache:
        return "%s is not configured" % folder
    home = cache.get("CMAKE_HOME_DIRECTORY", "")
    if not home or pathlib.Path(home).resolve() != ROOT:
        return "%s was configured from %s, not %s" % (folder, home or "an unknown source", ROOT)
    if cache.get("pybind11_DIR", "NOTFOUND").endswith("NOTFOUND"):
        return "%s was configured without pybind11 (Debian: pybind11-dev)" % folder
    python = cache.get("_Python3_EXECUTABLE") or cache.get("Python3_EXECUTABLE")
    suffix = sysconfig.get_config_var("EXT_SUFFIX")
    if not python or extension_suffix_of(python) != suffix:
        return "%s builds the extension for %s, not for this Python (%s)" % (folder, python or "no Python", suffix)
    return None


def configure_python_folder():
    """build/python, configured for this Python when it is not yet."""
    folder = ROOT / "build" / "python"
    python = os.path.realpath(sys.executable)
    cache = read_cache(folder)
    if cache.get("_Python3_EXECUTABLE") != python:
        generator = ["-G", "Ninja"] if shutil.which("ninja") and not cache else []
        run([cmake(), "-S", ROOT, "-B", folder, *generator, "-DCMAKE_BUILD_TYPE=Release",
             "-DNEEDLESIM_BUILD_TESTS=OFF", "-DNEEDLESIM_BUILD_BENCH=OFF", "-DPython3_EXECUTABLE=" + python])
    if read_cache(folder).get("pybind11_DIR", "NOTFOUND").endswith("NOTFOUND"):
        sys.exit("setup.py: CMake found no pybind11 in %s; Debian: apt install pybind11-dev" % folder)
    return folder


def configured_build_folder():
    """The CMake build folder to build the extension in (see the top of this file)."""
    given = os.environ.get("NEEDLESIM_CMAKE_BUILD_DIR")
    if given:
        folder = pathlib.Path(given).resolve()
        if not (folder / "CMakeCache.txt").is_file():
            sys.exit("setup.py: NEEDLESIM_CMAKE_BUILD_DIR=%s is not a configured CMake build folder "
                     "(no CMakeCache.txt); configure it first, e.g. cmake --preset release" % given)
        say("building the extension in %s (NEEDLESIM_CMAKE_BUILD_DIR)" % folder)
        return folder
    release = ROOT / "build" / "release"
    reason = release_folder_reason(release, read_cache(release))
    if reason is None:
        say("reusing the build folder %s (cmake --preset release): building only the extension there" % release)
        return release
    say("%s; compiling the library in %s (several minutes on 2 cores; after `cmake --preset release && "
        "cmake --build --preset release` an install reuses build/release)" % (reason, ROOT / "build" / "python"))
    return configure_python_folder()


def build_target(folder):
    """cmake --build for the extension, its progress on the terminal when there is one."""
    command = [cmake(), "--build", folder, "--target", TARGET]
    if TERMINAL:
        run(command, stdout=TERMINAL, stderr=TERMINAL)
    else:
        run(command)


class CMakeBuild(build_ext):
    def build_extension(self, ext):
        folder = configured_build_folder()
        build_target(folder)
        suffix = sysconfig.get_config_var("EXT_SUFFIX")
        built = folder / "python" / "needlesim" / ("_core" + suffix)
        if not built.is_file():
            found = sorted(p.name for p in (folder / "python" / "needlesim").glob("_core*"))
            sys.exit("setup.py: %s was not built for this Python (%s, extension suffix %s); the build folder has: %s"
                     % (built, sys.executable, suffix, ", ".join(found) or "nothing"))
        target = pathlib.Path(self.get_ext_fullpath(ext.name))
        target.parent.mkdir(parents=True, exist_ok=True)
        shutil.copyfile(built, target)
        say("installed the extension built in %s" % folder)


if "sdist" not in sys.argv:
    check_prerequisites()

setup(
    version=project_version(),
    ext_modules=[Extension("needlesim._core", sources=[])],
    cmdclass={"build_ext": CMakeBuild},
)
