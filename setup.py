"""Builds the extension needlesim._core with CMake for `pip install .` (pyproject.toml).

The CMake build folder is build/python inside the checkout (ccache reuses the
objects of other builds), configured without tests and benchmarks, and only the
target needlesim_python is built. NEEDLESIM_CMAKE_BUILD_DIR names an existing
configured build folder to build the target in instead (the tests use it).
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


def project_version():
    match = re.search(r"project\(needlesim VERSION ([0-9.]+)", (ROOT / "CMakeLists.txt").read_text())
    if not match:
        sys.exit("setup.py: no 'project(needlesim VERSION x.y.z)' in %s" % (ROOT / "CMakeLists.txt"))
    return match.group(1)


def cmake():
    return os.environ.get("NEEDLESIM_CMAKE") or shutil.which("cmake") or sys.exit(
        "setup.py: cmake not found (Debian package cmake; scripts/bootstrap.sh installs it)")


def run(command):
    print("setup.py:", " ".join(str(c) for c in command), flush=True)
    subprocess.run([str(c) for c in command], check=True)


def configured_build_folder():
    """NEEDLESIM_CMAKE_BUILD_DIR when given (it must be configured), else build/python, configured here."""
    given = os.environ.get("NEEDLESIM_CMAKE_BUILD_DIR")
    if given:
        folder = pathlib.Path(given).resolve()
        if not (folder / "CMakeCache.txt").is_file():
            sys.exit("setup.py: NEEDLESIM_CMAKE_BUILD_DIR=%s is not a configured CMake build folder "
                     "(no CMakeCache.txt); configure it first, e.g. cmake --preset release" % given)
        return folder
    folder = ROOT / "build" / "python"
    if not (folder / "CMakeCache.txt").is_file():
        generator = ["-G", "Ninja"] if shutil.which("ninja") else []
        run([cmake(), "-S", ROOT, "-B", folder, *generator, "-DCMAKE_BUILD_TYPE=Release",
             "-DNEEDLESIM_BUILD_TESTS=OFF", "-DNEEDLESIM_BUILD_BENCH=OFF",
             "-DPython3_EXECUTABLE=" + os.path.realpath(sys.executable)])
    return folder


class CMakeBuild(build_ext):
    def build_extension(self, ext):
        folder = configured_build_folder()
        run([cmake(), "--build", folder, "--target", TARGET])
        suffix = sysconfig.get_config_var("EXT_SUFFIX")
        built = folder / "python" / "needlesim" / ("_core" + suffix)
        if not built.is_file():
            found = sorted(p.name for p in (folder / "python" / "needlesim").glob("_core*"))
            sys.exit("setup.py: %s was not built for this Python (%s, extension suffix %s); the build folder has: %s"
                     % (built, sys.executable, suffix, ", ".join(found) or "nothing"))
        target = pathlib.Path(self.get_ext_fullpath(ext.name))
        target.parent.mkdir(parents=True, exist_ok=True)
        shutil.copyfile(built, target)


setup(
    version=project_version(),
    ext_modules=[Extension("needlesim._core", sources=[])],
    cmdclass={"build_ext": CMakeBuild},
)
