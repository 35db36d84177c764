"""Python bindings: a scenario runs in memory with the seed 003 numbers, parameters
can be varied, bad input (field paths, files, step arguments) raises needlesim.InputError,
paths with ':' and pathlib.Path load as files, the force model steps."""
import os
import pathlib
import sys
import tempfile

import needlesim

src = os.environ["NEEDLESIM_SOURCE_DIR"]
failures = 0


def check(cond, what):
    global failures
    if not cond:
        failures += 1
        print("FAIL:", what)
    else:
        print("ok:", what)


s = needlesim.load(os.path.join(src, "examples", "gelatin_18G_3mms.yaml"))
check(s.name == "gelatin_18G_3mms" and s.engine == "lumped", "load a scenario file")
r = needlesim.run(s)
exit_force, unit = r["results"]["exit_force"]
expected = 0.04335 + 0.055 * (3.791 + 285.053 * 0.003)  # seed 003 eq 5.1
check(unit == "N" and abs(exit_force - expected) < 2e-3 * expected, "exit force %.5f N = %.5f N" % (exit_force, expected))
check(len(r["tables"]["forces"]["force_total"]) > 100, "time series returned")
check(r["warnings"] == [] and len(r["notes"]) > 0, "a plain run: notes and no warning")
zw = needlesim.run(needlesim.load(os.path.join(src, "examples", "explicit", "target_inclusion_2d.yaml")))["warnings"]
check(any("not quasi-static" in w for w in zw), "a run that is not quasi-static says so in 'warnings': %s" % zw)

fast = s.with_values({"insertion.profile[0].insert.speed": "10 mm/s"})
f10 = needlesim.run(fast)["results"]["exit_force"][0]
check(abs(f10 - (0.04335 + 0.055 * (3.791 + 285.053 * 0.010))) < 2e-3, "with_values changes the speed")

try:
    s.with_values({"tissue.friction.C_p": "-1 N/m"})
    check(False, "negative friction rejected")
except needlesim.InputError as e:
    check("tissue.friction.C_p" in str(e), "negative friction rejected: " + str(e)[:80])



def raises(cls, words, call, what):
    """call() raises exactly `cls` (a needlesim exception) with every word in its message."""
    try:
        call()
    except Exception as e:  # noqa: BLE001 - the class is what is checked
        msg = str(e)
        ok = type(e) is cls and all(w in msg for w in words)
        check(ok, "%s: %s %s" % (what, type(e).__name__, msg[:160]))
        return
    check(False, what + ": no exception")


check(issubclass(needlesim.InputError, ValueError), "InputError is a ValueError")
check(issubclass(needlesim.SolverError, RuntimeError), "SolverError is a RuntimeError")

# Field paths of with_values: strict grammar, schema keys, list lengths of the base.
speed = "insertion.profile[%s].insert.speed"
raises(needlesim.InputError, ["has no entry [99999999999]", "an index from 0 to"],
       lambda: s.with_values({speed % "99999999999": "1 mm/s"}), "with_values huge index")
raises(needlesim.InputError, ["'x' is not an index", "character 19"],
       lambda: s.with_values({speed % "x": "1 mm/s"}), "with_values index x")
raises(needlesim.InputError, ["'-1' is not an index"], lambda: s.with_values({speed % "-1": "1 mm/s"}),
       "with_values index -1")
raises(needlesim.InputError, ["'junk' follows ']'"],
       lambda: s.with_values({"insertion.profile[0]junk.insert.speed": "1 mm/s"}), "with_values junk after ]")
raises(needlesim.InputError, ["did you mean 'C_p'?", "b_p"], lambda: s.with_values({"tissue.friction.Cp": "3 N/m"}),
       "with_values typo")
raises(needlesim.InputError, ["with_values(tissue.friction.C_p)", "nan", "finite"],
       lambda: s.with_values({"tissue.friction.C_p": float("nan")}), "with_values NaN value")
check("poisson: 0.31" in s.with_values({"needle.poisson": 0.31}).yaml, "with_values takes a number")
check("relaxation_time: 0.5 s" in s.with_values({"model.lumped.relaxation_time": "0.5 s"}).yaml,
      "with_values writes a section the base omits")

# load: a path with ':' is a file, pathlib.Path is accepted, a missing .yaml is "file not found".
with tempfile.TemporaryDirectory() as d:
    colon = os.path.join(d, "a:b.yaml")
    with open(os.path.join(src, "examples", "gelatin_18G_3mms.yaml")) as f, open(colon, "w") as g:
        g.write(f.read())
    check(needlesim.load(colon).name == "gelatin_18G_3mms", "load a file whose path holds ':'")
    check(needlesim.load(pathlib.Path(colon)).name == "gelatin_18G_3mms", "load a pathlib.Path")
    raises(needlesim.InputError, ["file not found"], lambda: needlesim.load(os.path.join(d, "x:missing.yaml")),
           "load a missing .yaml")
    raises(needlesim.InputError, ["file not found"], lambda: needlesim.load(pathlib.Path(d) / "missing"),
           "load a missing pathlib.Path")
    raises(needlesim.InputError, ["is a folder"], lambda: needlesim.load(d), "load a folder")
raises(needlesim.InputError, ["<python>:1:", "not valid YAML"], lambda: needlesim.load("tissue: [1"),
       "load bad YAML text")

m = needlesim.LumpedForceModel(s)
raises(needlesim.InputError, ["LumpedForceModel.step(depth)", "nan", "finite"],
       lambda: m.step(float("nan"), 1e-3, 1e-3), "step with NaN depth")
raises(needlesim.InputError, ["LumpedForceModel.step(velocity)", "inf", "finite"],
       lambda: m.step(0.0, float("inf"), 1e-3), "step with infinite velocity")
raises(needlesim.InputError, ["LumpedForceModel.step(dt)", "'0'", "> 0"], lambda: m.step(0.0, 1e-3, 0.0),
       "step with dt 0")
raises(needlesim.InputError, ["LumpedForceModel.step(dt)", "'-0.001'", "> 0"], lambda: m.step(0.0, 1e-3, -1e-3),
       "step with negative dt")
m.reset()
total = 0.0
for k in range(20000):  # 20 mm at 1 mm/s, 1 kHz
    total, stiff, cut, fric = m.step(k * 1e-6, 1e-3, 1e-3)
check(abs(total - (0.04335 + 0.02 * (3.791 + 285.053 * 1e-3))) < 1e-3, "LumpedForceModel.step at 20 mm: %.5f N" % total)

with tempfile.TemporaryDirectory() as d:
    out = needlesim.run(s, out=os.path.join(d, "run"))
    check(os.path.exists(os.path.join(out["folder"], "summary.json")), "run to a results folder")
    out = needlesim.run(s, out=pathlib.Path(d) / "run_path")
    check(os.path.exists(os.path.join(out["folder"], "summary.json")), "run to a pathlib.Path results folder")

print("%d failed" % failures)
sys.exit(1 if failures else 0)
