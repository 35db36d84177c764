#!/usr/bin/env python3
"""The run-time estimate of each shipped example against its measured time.

Runs `needlesim run EXAMPLE --out TMP` for each example (the scenarios of examples/ that `run`
accepts; studies and plans are left out), reads the estimate it prints before the first step and
measures the child's CPU time (user + sys, from its rusage) and wall time. The CPU time divided
by the threads the engine used is the load-independent measure the estimate is compared with.
--threads N sets OMP_NUM_THREADS (default 1: one thread, so CPU time is the run's own work).

  scripts/example_times.py --binary build/release/apps/needlesim/needlesim --select quick
  scripts/example_times.py ... --select long --check 1.5     # exit 1 where a ratio is outside 1/1.5..1.5
  scripts/example_times.py ... --check-relative 2            # the same, against this machine's median ratio
  scripts/example_times.py --self-test                       # the two checks on synthetic rows
  scripts/example_times.py ... --only examples/mpm/tumour_target.yaml

--select quick: the examples whose estimate (from `needlesim check`) is at most --quick-seconds;
long: the others (--most-seconds leaves out those estimated above it); all: every one. Prints a Markdown table (docs/performance.md "Run-time
estimates") and, with --check, the examples outside the factor.

The estimate is CPU time on the machine the constants of src/needlesim/engines/run_cost.hpp were
measured on; another machine runs every example some factor slower or faster, and not quite the
same factor for every engine (MPM lost the most on the 2-core development machine, docs/performance.md).
--check-relative F takes that factor as the median ratio over the examples run and fails an
example whose ratio is outside 1/F..F of it, or a median outside 1/MACHINE_RANGE..MACHINE_RANGE:
it checks the cost model on any machine, where --check checks the machine as well.
"""
import argparse
import json
import os
import pathlib
import re
import resource
import statistics
import subprocess
import sys
import tempfile
import time

SOURCE_DIR = pathlib.Path(__file__).resolve().parents[1]
ESTIMATE = re.compile(r"estimate: (?P<text>[^\n)]*)")
ABOUT = re.compile(r"about (?P<value>[0-9.]+) (?P<unit>s|min|h|days)\b")
POINTS = re.compile(r"x (?P<n>[0-9.e+]+) (?P<what>points|elements|nodes|updates)")
UNIT_SECONDS = {"s": 1.0, "min": 60.0, "h": 3600.0, "days": 86400.0}


def estimate_seconds(text):
    """The seconds of an estimate's text ("at least 712 steps x 2304 points, about 0.8 s"), or None."""
    m = ABOUT.search(text or "")
    return float(m.group("value")) * UNIT_SECONDS[m.group("unit")] if m else None


def shipped_examples(root):
    """Every scenario of examples/ that `needlesim run` accepts (not studies, not plans)."""
    out = []
    for path in sorted((root / "examples").rglob("*.yaml")):
        rel = path.relative_to(root)
        if rel.parts[1] in ("studies", "planning"):
            continue
        out.append(str(rel))
    return out


def check_estimates(binary, root, examples, threads):
    """{example: estimate text} from one `needlesim check` of them all (nothing runs) on `threads`."""
    env = dict(os.environ, OMP_NUM_THREADS=str(threads))
    p = subprocess.run([binary, "check", *examples], cwd=root, capture_output=True, text=True, env=env)
    found = {}
    for line in p.stdout.splitlines():
        name, _, rest = line.partition(": ok (")
        m = ESTIMATE.search(rest)
        if m:
            found[name] = m.group("text")
    return found


def run_one(binary, root, example, threads, work):
    """Runs one example; its estimate text, CPU seconds (user + sys), wall seconds and summary."""
    out = pathlib.Path(work) / str(pathlib.Path(example).with_suffix("")).replace("/", "_")  # mpm/ and realtime3d/ share names
    env = dict(os.environ, OMP_NUM_THREADS=str(threads), OPENBLAS_NUM_THREADS="1")
    t0 = time.monotonic()
    proc = subprocess.Popen([binary, "run", example, "--out", str(out)], cwd=root, env=env,
                            stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    text = proc.stdout.read()
    _, status, usage = os.wait4(proc.pid, 0)
    proc.returncode = os.waitstatus_to_exitcode(status)
    wall = time.monotonic() - t0
    m = ESTIMATE.search(text)
    summary = {}
    if (out / "summary.json").is_file():
        summary = json.loads((out / "summary.json").read_text())
    return {"example": example, "rc": proc.returncode, "estimate": m.group("text") if m else None,
            "cpu": usage.ru_utime + usage.ru_stime, "wall": wall, "threads": threads,
            "updates": counted_updates(summary), "steps": summary.get("results", {}).get("steps", {}).get("value"),
            "tail": text[-2000:]}


def counted_updates(summary):
    """The points or elements the run reports it had (summary.json results), or None."""
    results = summary.get("results", {})
    for key in ("particles", "elements"):
        if key in results:
            return results[key].get("value")
    return None


# Below this difference an estimate is right whatever the ratio: a process's start and rusage's
# 10 ms granularity vary by about this much on runs of a tenth of a second (lumped, steering).
SLACK_SECONDS = 0.1


# A machine more than this much faster or slower than the one the constants were measured on is
# taken for a cost model off as a whole (every constant wrong), not for a machine.
MACHINE_RANGE = 4.0


def within(row, q, factor, machine=1.0):
    """The estimate, scaled to a machine `machine` times as fast as the constants' one, is right."""
    est = estimate_seconds(row["estimate"])
    if est and abs(est / machine - row["cpu"] / row["threads"]) <= SLACK_SECONDS:
        return True
    return bool(q and 1 / factor <= q / machine <= factor)


def machine_factor(rows):
    """The median estimate / measured ratio of the rows: this machine's speed relative to the
    constants' machine (1 there, 0.5 on a machine taking twice as long), or None."""
    qs = [q for q in map(ratio, rows) if q]
    return statistics.median(qs) if qs else None


def ratio(row):
    est = estimate_seconds(row["estimate"])
    return est / (row["cpu"] / row["threads"]) if est and row["cpu"] > 0 else None


def table(rows):
    lines = ["| example | estimate | measured CPU / thread | wall | ratio |", "|---|---|---|---|---|"]
    for r in rows:
        q = ratio(r)
        lines.append("| `{}` | {} | {:.1f} s | {:.1f} s | {} |".format(
            r["example"], r["estimate"], r["cpu"] / r["threads"], r["wall"], "%.2f" % q if q else "-"))
    return "\n".join(lines)


def failures(rows, args):
    """The rows that failed: a run that did not end with 0, an estimate outside --check, or one
    outside --check-relative of this machine's median ratio (a median outside MACHINE_RANGE fails all)."""
    bad = [r for r in rows if r["rc"] != 0 or (args.check and not within(r, ratio(r), args.check))]
    if args.check_relative:
        m = machine_factor(rows)
        print("this machine: median ratio %s (estimates are for a machine of ratio 1)" % ("%.2f" % m if m else "-"))
        if not m or not 1 / MACHINE_RANGE <= m <= MACHINE_RANGE:
            print("FAILED: the median ratio is outside 1/%g..%g: the cost model is off as a whole" % (
                MACHINE_RANGE, MACHINE_RANGE))
            return rows
        bad += [r for r in rows if r not in bad and not within(r, ratio(r), args.check_relative, m)]
    return bad


def self_test():
    """The checks on synthetic rows: ten engines' examples, each measured some factor off its estimate."""
    def rows(factors):
        return [{"example": "e%d" % i, "rc": 0, "estimate": "about 10 s", "cpu": 10.0 * f, "threads": 1}
                for i, f in enumerate(factors)]
    class Args:
        check = None
        check_relative = 2.0
    cases = [  # (measured / estimate of each example, how many the relative check fails)
        ([1.0] * 10, 0),
        ([2.0] * 10, 0),                     # a machine twice as slow: the cost model is right
        ([2.0] * 9 + [2.0 * 2.5], 1),        # one engine's constant 2.5x off on that machine
        ([2.0] * 9 + [2.0 / 2.5], 1),
        ([1.0, 1.2, 0.8, 1.9, 0.55] * 2, 0),  # this machine's spread at idle (0.59-1.39 of the median)
        ([10.0] * 10, 10),                   # every constant 10x off: the median is outside MACHINE_RANGE
    ]
    ok = True
    for factors, expected in cases:
        got = len(failures(rows(factors), Args))
        print("%s: %d failed, expected %d" % (factors, got, expected))
        ok &= got == expected
    Args.check, Args.check_relative = 1.5, None
    got = len(failures(rows([2.0] * 10), Args))  # the absolute check fails a machine twice as slow
    print("absolute check, machine twice as slow: %d failed, expected 10" % got)
    return ok and got == 10


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--binary")
    ap.add_argument("--self-test", action="store_true", help="check the two checks on synthetic rows")
    ap.add_argument("--source-dir", default=str(SOURCE_DIR))
    ap.add_argument("--select", choices=("quick", "long", "all"), default="quick")
    ap.add_argument("--quick-seconds", type=float, default=10.0)
    ap.add_argument("--most-seconds", type=float, help="leave out the examples estimated above this")
    ap.add_argument("--only", nargs="*", help="these examples instead of a selection")
    ap.add_argument("--threads", type=int, default=1)
    ap.add_argument("--check", type=float, help="fail where estimate / measured is outside 1/F..F")
    ap.add_argument("--check-relative", type=float,
                    help="fail where estimate / measured is outside 1/F..F of the median ratio of the examples run")
    ap.add_argument("--json", help="also write the rows here")
    args = ap.parse_args()
    if args.self_test:
        return 0 if self_test() else 1
    if not args.binary:
        ap.error("--binary is required")
    root = pathlib.Path(args.source_dir)
    binary = str(pathlib.Path(args.binary).resolve())
    examples = args.only or shipped_examples(root)
    if not args.only and args.select != "all":
        est = check_estimates(binary, root, examples, args.threads)
        quick = lambda e: (estimate_seconds(est.get(e)) or float("inf")) <= args.quick_seconds
        examples = [e for e in examples if quick(e) == (args.select == "quick")]
        if args.most_seconds:
            over = [e for e in examples if (estimate_seconds(est.get(e)) or 0.0) > args.most_seconds]
            for e in over:
                print("%s: left out, estimate %s is above --most-seconds %g" % (e, est.get(e), args.most_seconds))
            examples = [e for e in examples if e not in over]
    rows = []
    with tempfile.TemporaryDirectory(prefix="example_times_") as work:
        for e in examples:
            r = run_one(binary, root, e, args.threads, work)
            rows.append(r)
            q = ratio(r)
            print("%s: estimate %s; CPU %.2f s on %d thread(s), wall %.2f s; ratio %s (load %.1f)" % (
                e, r["estimate"], r["cpu"], r["threads"], r["wall"], "%.2f" % q if q else "-",
                os.getloadavg()[0]), flush=True)
    print(table(rows))
    if args.json:
        pathlib.Path(args.json).write_text(json.dumps(rows, indent=1))
    bad = failures(rows, args)
    for r in bad:
        print("FAILED: %s (exit %d, estimate %s, CPU %.2f s / %d thread(s))\n%s" % (
            r["example"], r["rc"], r["estimate"], r["cpu"], r["threads"], r["tail"] if r["rc"] else ""))
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main())
