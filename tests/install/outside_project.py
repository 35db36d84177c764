#!/usr/bin/env python3
"""Install.OutsideProject: install this build into a fresh prefix, build the numbered
examples (examples/cpp, a project of its own) against it with find_package(needlesim),
run each one and check what it prints, check that the README's C++ program is
examples/cpp/readme_snippet.cpp character for character and that the force it prints is seed 003's
closed form, check that the installed program runs, and remove the prefix again.

usage: outside_project.py BUILD_DIR SOURCE_DIR WORK_DIR VERSION GENERATOR BUILD_TYPE [CXX_FLAGS]
(the examples build with the build's type and flags, e.g. its sanitizers)
"""
import os
import re
import shutil
import subprocess
import sys

build, source, work, version = sys.argv[1:5]
generator, build_type = sys.argv[5:7]
cxx_flags = sys.argv[7] if len(sys.argv) > 7 else ""
prefix = os.path.join(work, "prefix")
examples = os.path.join(source, "examples")
failures = []


def run(cmd, cwd=None):
    p = subprocess.run(cmd, cwd=cwd, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    if p.returncode != 0:
        sys.exit("FAIL (exit %d): %s\n%s" % (p.returncode, " ".join(cmd), p.stdout))
    return p.stdout


def check(ok, what, output=""):
    print(("ok: " if ok else "FAIL: ") + what)
    if not ok:
        failures.append(what)
        print(output)


def number(pattern, text):
    m = re.search(pattern, text)
    return float(m.group(1)) if m else float("nan")


shutil.rmtree(work, ignore_errors=True)
os.makedirs(work)
try:
    run(["cmake", "--install", build, "--prefix", prefix])
    for f in ["include/needlesim/needlesim.hpp", "lib/cmake/needlesim/needlesimConfig.cmake",
              "lib/cmake/needlesim/needlesimConfigVersion.cmake", "lib/cmake/needlesim/needlesimTargets.cmake"]:
        check(os.path.exists(os.path.join(prefix, f)), "installed " + f)

    # Only the public API is exported: no needlesim:: symbol outside needlesim::api.
    if shutil.which("nm"):
        symbols = run(["nm", "-DC", "--defined-only", os.path.join(prefix, "lib", "libneedlesim.so")])
        private = [l for l in symbols.splitlines() if "needlesim::" in l and "needlesim::api::" not in l]
        api = [l for l in symbols.splitlines() if "needlesim::api::run(" in l]
        check(not private and api, "libneedlesim.so exports needlesim::api and nothing else of needlesim",
              "\n".join(private[:20]))

    out = run([os.path.join(prefix, "bin", "needlesim"), "--version"])
    check(version in out, "the installed program runs: needlesim --version says " + out.strip())

    ex_build = os.path.join(work, "examples")
    run(["cmake", "-S", os.path.join(examples, "cpp"), "-B", ex_build, "-G", generator,
         "-DCMAKE_BUILD_TYPE=" + build_type, "-DCMAKE_CXX_FLAGS=" + cxx_flags, "-DCMAKE_PREFIX_PATH=" + prefix])
    run(["cmake", "--build", ex_build])

    def example(name, *args):
        return run([os.path.join(ex_build, name), examples, *args], cwd=work)

    out = example("ex1_haptic_loop")
    print(out)
    check("steps: 10333 at 1000 Hz" in out, "ex1 runs its 10333 steps (-1 mm to 30 mm at 3 mm/s, 1 kHz)", out)
    # At 30 mm: cutting + friction on 30 mm of shaft at 3 mm/s; the FE model's coupled nodes
    # carry the friction of seed 003 eq 5.1 to within 5 %.
    force = number(r"depth\s+30\.00 mm\s+axial force\s+([-0-9.e]+) N", out)
    lumped = 0.04335 + 0.030 * (3.791 + 285.053 * 0.003)
    check(abs(force - lumped) < 0.05 * lumped, "ex1 axial force at 30 mm %.4f N near %.4f N" % (force, lumped), out)

    # The README's C++ program, as printed there: the lumped model at 5 mm/s, friction
    # (C_p + b_p v) on the shaft in the block plus the cutting force (seed 003 eq 5.1).
    with open(os.path.join(source, "README.md")) as f:
        readme = f.read()
    with open(os.path.join(examples, "cpp", "readme_snippet.cpp")) as f:
        snippet = f.read()
    printed = re.search(r"<!-- examples/cpp/readme_snippet\.cpp[^\n]*-->\n```cpp\n(.*?)```\n", readme, re.S)
    check(printed is not None and printed.group(1) == snippet,
          "README.md prints examples/cpp/readme_snippet.cpp exactly", printed.group(1) if printed else "no block")
    out = run([os.path.join(ex_build, "readme_snippet")], cwd=source)
    print(out)
    friction_5 = 3.791 + 285.053 * 0.005  # N/m of shaft at 5 mm/s
    exit_force = number(r"exit force at 5 mm/s: ([-0-9.e]+) N", out)
    expected = 0.04335 + 0.055 * friction_5  # 55 mm block
    check(abs(exit_force - expected) < 2e-3 * expected,
          "README program: exit force %.4f N = %.4f N (seed 003 eq 5.1, 55 mm)" % (exit_force, expected), out)
    force = number(r"axial force at 10 mm: ([-0-9.e]+) N", out)
    expected = 0.04335 + 0.010 * friction_5
    check(abs(force - expected) < 2e-3 * expected,
          "README program: axial force at 10 mm %.4f N = %.4f N (seed 003 eq 5.1)" % (force, expected), out)

    out = example("ex2_planner")
    print(out)
    check("plans: 1147" in out, "ex2 evaluates 1147 insertions", out)
    m = re.search(r"best plan: entry angle (\S+) deg, speed (\S+) mm/s, peak force (\S+) N", out)
    check(m is not None and m.group(1) == "90" and m.group(2) == "1.00", "ex2 picks 90 deg at 1 mm/s", out)
    if m:
        exit_force = 0.04335 + 0.055 * (3.791 + 285.053 * 0.001)  # seed 003 eq 5.1, 55 mm of shaft
        peak = float(m.group(3))
        check(abs(peak - exit_force) < 1e-3 * exit_force,
              "ex2 best peak force %.6f N = exit force %.6f N (seed 003 eq 5.1)" % (peak, exit_force), out)

    out = example("ex3_fit")
    print(out)
    check(re.search(r"fitted law: \S+", out) is not None and "C10" in out and "material: {law:" in out,
          "ex3 prints the fitted law, its parameters and the scenario block", out)

    out = example("ex4_study", os.path.join(work, "study"))
    print(out)
    check("cases: 12 (12 ran, 0 reused, 0 failed)" in out and "all cases complete" in out,
          "ex4 runs the 12 cases of the study", out)
    check(os.path.exists(os.path.join(work, "study", "study.csv")), "ex4 writes study.csv", out)
finally:
    if not failures:
        shutil.rmtree(work, ignore_errors=True)

sys.exit(1 if failures else 0)
