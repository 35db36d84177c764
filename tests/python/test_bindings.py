"""Python bindings: a scenario runs in memory with the seed 003 numbers, parameters
can be varied, bad input raises needlesim.InputError, the force model steps."""
import os
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

fast = s.with_values({"insertion.profile[0].insert.speed": "10 mm/s"})
f10 = needlesim.run(fast)["results"]["exit_force"][0]
check(abs(f10 - (0.04335 + 0.055 * (3.791 + 285.053 * 0.010))) < 2e-3, "with_values changes the speed")

try:
    s.with_values({"tissue.friction.C_p": "-1 N/m"})
    check(False, "negative friction rejected")
except needlesim.InputError as e:
    check("tissue.friction.C_p" in str(e), "negative friction rejected: " + str(e)[:80])

m = needlesim.LumpedForceModel(s)
total = 0.0
for k in range(20000):  # 20 mm at 1 mm/s, 1 kHz
    total, stiff, cut, fric = m.step(k * 1e-6, 1e-3, 1e-3)
check(abs(total - (0.04335 + 0.02 * (3.791 + 285.053 * 1e-3))) < 1e-3, "LumpedForceModel.step at 20 mm: %.5f N" % total)

with tempfile.TemporaryDirectory() as d:
    out = needlesim.run(s, out=os.path.join(d, "run"))
    check(os.path.exists(os.path.join(out["folder"], "summary.json")), "run to a results folder")

print("%d failed" % failures)
sys.exit(1 if failures else 0)
